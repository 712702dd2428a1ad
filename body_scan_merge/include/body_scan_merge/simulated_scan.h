// A whole-body scan of a simulated rig at core level (no ROS): every pair of the rig renders
// the scene by timing groups (members' light interfering, thesis 4.3), is decoded
// (StripeDecoder), triangulated with its factory calibration (Triangulator) and moved to the
// world frame, then merged exactly as the Merge nodelet does (mergeClouds: crop, voxel grid).
#pragma once

#include <body_scan_merge/cloud_merge.h>
#include <body_scan_merge/timing_groups.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace body_scan_merge {
namespace sim {
class Scene;
struct Rig;
}  // namespace sim

struct SimulatedScan {
  MergedCloud cloud;                                     // world frame, x y z rgb
  std::vector<std::pair<std::string, size_t>> per_pair;  // valid points of each pair, rig order
};

// Every pair of the rig with its factory calibration (the simulator's true geometry) and pose:
// what the timing groups of a simulated rig are planned from.
std::vector<PairGeometry> rigFactoryGeometry(const body_scan_driver::sim::Rig& rig);

// Groups of pair ids projecting at the same time. Every pair of the rig must be in exactly one
// group; throws std::invalid_argument naming the pair otherwise.
using TimingGroupList = std::vector<std::vector<std::string>>;
TimingGroupList eachPairAlone(const body_scan_driver::sim::Rig& rig);
TimingGroupList allPairsTogether(const body_scan_driver::sim::Rig& rig);
// The groups planTimingGroups computes from the rig's factory calibrations and poses.
TimingGroupList plannedTimingGroups(const body_scan_driver::sim::Rig& rig);
// YAML: a sequence of sequences of pair ids. Throws std::runtime_error naming the file.
TimingGroupList loadTimingGroups(const std::string& path);

SimulatedScan simulateScan(const body_scan_driver::sim::Rig& rig,
                           const std::shared_ptr<const body_scan_driver::sim::Scene>& scene,
                           const TimingGroupList& groups, uint32_t scan_id = 1,
                           const MergeOptions& merge = {});

}  // namespace body_scan_merge
