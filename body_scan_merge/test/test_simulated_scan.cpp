// The simulated full scan of the default rig (every pair rendered by its timing group, decoded,
// triangulated with the factory calibration) against the true surface: issue 4's targets.
#include <body_scan_driver/sim/rig.h>
#include <body_scan_merge/scan_accuracy.h>
#include <body_scan_merge/simulated_scan.h>
#include <gtest/gtest.h>

using namespace body_scan;

namespace {
const std::string kDriverConfig = BODY_SCAN_DRIVER_CONFIG_DIR;

void printAccuracy(const std::string& what, const ScanAccuracy& a) {
  std::cout << "[ figure ] " << what << ": " << a.points << " points, mean "
            << 1000 * a.mean_distance << " mm, median " << 1000 * a.median_distance << " mm, p95 "
            << 1000 * a.p95_distance << " mm, outliers " << a.outliers << ", coverage "
            << 100 * a.coverage << " %;";
  for (int r = 0; r < kBodyRegionCount; ++r)
    std::cout << " " << bodyRegionName(static_cast<BodyRegion>(r)) << " "
              << 100 * a.regions[r].fraction() << " %";
  std::cout << "\n";
}
}  // namespace

TEST(SimulatedScan, DefaultRigMeetsTheAccuracyAndCoverageTargets) {
  const sim::Rig rig = sim::loadRig(kDriverConfig + "/rigs/thesis_rig.yaml");
  auto scene = std::make_shared<const sim::Scene>(
      sim::loadScene(kDriverConfig + "/scenes/standing_person.yaml"));
  const SimulatedScan scan = simulateScan(rig, scene, plannedTimingGroups(rig));
  ASSERT_EQ(scan.per_pair.size(), 12u);
  for (const auto& [id, count] : scan.per_pair) EXPECT_GT(count, 1000u) << id;
  const ScanAccuracy a = evaluateScan(scan.points, *scene);
  printAccuracy("default rig, standing_person", a);
  EXPECT_LE(a.mean_distance, 0.002);
  EXPECT_GE(a.coverage, 0.95);
  for (BodyRegion r : {BodyRegion::kUnderChin, BodyRegion::kArmpitLeft, BodyRegion::kArmpitRight,
                       BodyRegion::kGroin, BodyRegion::kTorsoSideLeft, BodyRegion::kTorsoSideRight})
    EXPECT_GE(a.regions[static_cast<int>(r)].fraction(), 0.80) << bodyRegionName(r);
}

TEST(SimulatedScan, GroupsMustCoverEveryPairOnce) {
  const sim::Rig rig = sim::loadRig(kDriverConfig + "/rigs/thesis_rig.yaml");
  auto scene = std::make_shared<const sim::Scene>();
  TimingGroupList groups = eachPairAlone(rig);
  groups.pop_back();
  EXPECT_THROW(simulateScan(rig, scene, groups), std::invalid_argument);
  groups = eachPairAlone(rig);
  groups.push_back({groups.front().front()});
  EXPECT_THROW(simulateScan(rig, scene, groups), std::invalid_argument);
  EXPECT_EQ(allPairsTogether(rig).front().size(), 12u);
}
