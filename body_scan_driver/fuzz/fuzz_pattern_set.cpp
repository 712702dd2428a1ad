// PatternSet (Triangulate's input): bytes -> ROS deserialization -> checkPatternSet -> the
// Triangulate nodelet's own path for a set that passes (PatternSetCloud: decode, triangulate
// with a 32x24 virtual pair's factory calibration, colour from the texture). A set the check
// passes must never make that path throw, except the Triangulator's refusal of frames of
// another size than its calibration's (they are still decoded first, as in the nodelet).
#include <body_scan_driver/fuzz_target.h>
#include <body_scan_driver/ros/message_checks.h>
#include <body_scan_driver/ros/pattern_set_cloud.h>
#include <body_scan_driver/sim/virtual_pair.h>

#include <memory>
#include <stdexcept>

namespace {

using namespace body_scan_driver;

// The pair whose frames the seeds hold: a 32x24 camera looking at a wall 1 m away.
const Triangulator& smallPair() {
  static const std::unique_ptr<Triangulator> triangulator = [] {
    sim::VirtualPairConfig config;
    config.camera = PinholeCamera{32, 24, 40, 40, 0, 15.5, 11.5, 0, 0};
    auto scene = std::make_shared<sim::Scene>();
    scene->add(std::make_unique<sim::Plane>(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1),
                                            sim::Material{0.8, {0.8, 0.8, 0.8}}));
    return std::make_unique<Triangulator>(sim::VirtualPair(config, scene).factoryCalibration());
  }();
  return *triangulator;
}

}  // namespace

BODY_SCAN_FUZZ_TARGET(pattern_set) {
  body_scan_msgs::PatternSet set;
  if (!fuzz::deserialize(data, size, set) || checkPatternSet(set)) return 0;
  const Triangulator& triangulator = smallPair();
  static PatternSetCloud cloud_maker;  // keeps its decoder between inputs, as the nodelet does
  sensor_msgs::PointCloud2 cloud;
  try {
    cloud_maker.triangulate(set, triangulator, cloud);
  } catch (const std::invalid_argument&) {
    const PinholeCamera& camera = triangulator.calibration().camera;
    const bool calibration_size = set.frames[0].width == static_cast<uint32_t>(camera.width) &&
                                  set.frames[0].height == static_cast<uint32_t>(camera.height);
    if (calibration_size) throw;  // a checked set of the right size must triangulate
  }
  return 0;
}
