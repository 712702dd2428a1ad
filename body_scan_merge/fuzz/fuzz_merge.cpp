// Merge's inputs: a PairCloud (bytes -> ROS deserialization -> checkPairCloud -> the cloud view
// and the merge Merge makes of it), TimingGroups (-> checkTimingGroups), and the files the merge
// package reads: a timing-group plan and a PLY cloud.
#include <body_scan_driver/fuzz_target.h>
#include <body_scan_driver/ros/message_checks.h>
#include <body_scan_driver/sim/rig.h>  // simulated_scan.h uses sim::Rig
#include <body_scan_merge/cloud_merge.h>
#include <body_scan_merge/ply_writer.h>
#include <body_scan_merge/ros/cloud_view_msg.h>
#include <body_scan_merge/simulated_scan.h>

#include <cstdlib>

using namespace body_scan_merge;
namespace fuzz = body_scan_driver::fuzz;

BODY_SCAN_FUZZ_TARGET(pair_cloud) {
  body_scan_msgs::PairCloud part;
  if (!fuzz::deserialize(data, size, part) || body_scan_driver::checkPairCloud(part)) return 0;
  const sensor_msgs::PointCloud2& cloud = part.cloud;
  const CloudView view = cloudView(cloud);  // as the Merge nodelet reads a checked cloud
  const MergedCloud merged = mergeClouds({view}, MergeOptions());
  if (merged.valid_per_part.size() != 1 || merged.valid_per_part[0] > view.count) std::abort();
  return 0;
}

BODY_SCAN_FUZZ_TARGET(timing_groups) {
  body_scan_msgs::TimingGroups groups;
  if (fuzz::deserialize(data, size, groups)) body_scan_driver::checkTimingGroups(groups);
  return 0;
}

BODY_SCAN_FUZZ_TARGET(timing_groups_yaml) {
  try {
    loadTimingGroups(fuzz::inputFile("timing_groups_yaml", data, size, ".yaml"));
  } catch (const std::exception&) {
  }
  return 0;
}

BODY_SCAN_FUZZ_TARGET(ply) {
  try {
    const std::vector<float> points = readPly(fuzz::inputFile("ply", data, size, ".ply"));
    if (points.size() % 4 != 0) std::abort();
  } catch (const std::exception&) {
  }
  return 0;
}
