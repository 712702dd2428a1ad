// The simulated full scan of the default rig at core level (every pair rendered by its timing
// group, decoded, triangulated with the factory calibration, merged as the Merge nodelet does)
// against the true surface (eval::evaluateScan): the whole-body accuracy targets, and what
// interference does.
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/rig.h>
#include <body_scan_merge/eval/scan_accuracy.h>
#include <body_scan_merge/simulated_scan.h>
#include <gtest/gtest.h>

using namespace body_scan_merge;
using namespace body_scan_driver;

namespace {
const std::string kDriverConfig = body_scan_driver::sim::driverConfigDir();

eval::ScanAccuracy evaluate(const SimulatedScan& scan, const body_scan_driver::sim::Scene& scene) {
  return eval::evaluateScan(scan.cloud.xyzrgb, scene);
}

void print(const std::string& what, const eval::ScanAccuracy& a) {
  std::cout << "[ figure ] " << what << ": " << a.points << " points, mean "
            << 1000 * a.mean_distance << " mm, p95 " << 1000 * a.p95_distance << " mm, outliers "
            << a.outliers << ", coverage " << 100 * a.body.fraction() << " %;";
  for (const auto& [region, coverage] : a.regions)
    std::cout << " " << eval::regionName(region) << " " << 100 * coverage.fraction() << " %";
  std::cout << "\n";
}

const eval::Region kHardRegions[] = {eval::Region::kUnderChin,     eval::Region::kArmpitLeft,
                                     eval::Region::kArmpitRight,   eval::Region::kGroin,
                                     eval::Region::kTorsoSideLeft, eval::Region::kTorsoSideRight};
}  // namespace

TEST(SimulatedScan, DefaultRigMeetsTheAccuracyAndCoverageTargets) {
  const body_scan_driver::sim::Rig rig =
      body_scan_driver::sim::loadRig(kDriverConfig + "/rigs/thesis_rig.yaml");
  auto scene = std::make_shared<const body_scan_driver::sim::Scene>(
      body_scan_driver::sim::loadScene(kDriverConfig + "/scenes/standing_person.yaml"));
  const SimulatedScan scan = simulateScan(rig, scene, plannedTimingGroups(rig));
  ASSERT_EQ(scan.per_pair.size(), 12u);
  for (const auto& [id, count] : scan.per_pair) EXPECT_GT(count, 1000u) << id;
  const eval::ScanAccuracy a = evaluate(scan, *scene);
  print("default rig, planned groups, standing_person", a);
  EXPECT_LE(a.mean_distance, 0.002);
  EXPECT_GE(a.body.fraction(), 0.95);
  for (eval::Region r : kHardRegions)
    EXPECT_GE(a.regions.at(r).fraction(), 0.80) << eval::regionName(r);
}

TEST(SimulatedScan, GroupsMustCoverEveryPairOnce) {
  const body_scan_driver::sim::Rig rig =
      body_scan_driver::sim::loadRig(kDriverConfig + "/rigs/thesis_rig.yaml");
  auto scene = std::make_shared<const body_scan_driver::sim::Scene>();
  TimingGroupList groups = eachPairAlone(rig);
  groups.pop_back();
  EXPECT_THROW(simulateScan(rig, scene, groups), std::invalid_argument);
  groups = eachPairAlone(rig);
  groups.push_back({groups.front().front()});
  EXPECT_THROW(simulateScan(rig, scene, groups), std::invalid_argument);
  EXPECT_EQ(allPairsTogether(rig).front().size(), 12u);
}
