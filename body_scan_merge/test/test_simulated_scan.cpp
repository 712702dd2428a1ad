// The simulated full scan of the default rig (every pair rendered by its timing group, decoded,
// triangulated with the factory calibration) against the true surface: issue 4's targets.
#include <body_scan_driver/sim/rig.h>
#include <body_scan_merge/simulated_scan.h>
#include <gtest/gtest.h>

using namespace body_scan;

namespace {
const std::string kDriverConfig = BODY_SCAN_DRIVER_CONFIG_DIR;

}  // namespace

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
