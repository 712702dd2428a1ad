// PatternSet (Triangulate's input): bytes -> ROS deserialization -> checkPatternSet -> what
// Triangulate does with a set that passes: decode, triangulate (a 32x24 virtual pair's factory
// calibration; sets of other sizes stop at the decoder, as the Triangulator would refuse them)
// and colour from the texture. A set the check passes must never make the core throw.
#include <body_scan_driver/fuzz_target.h>
#include <body_scan_driver/ros/message_checks.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>

#include <memory>
#include <opencv2/core.hpp>

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

cv::Mat view(const sensor_msgs::Image& image, int type) {
  return cv::Mat(static_cast<int>(image.height), static_cast<int>(image.width), type,
                 const_cast<uint8_t*>(image.data.data()), image.step);
}

}  // namespace

BODY_SCAN_FUZZ_TARGET(pattern_set) {
  body_scan_msgs::PatternSet set;
  if (!fuzz::deserialize(data, size, set) || checkPatternSet(set)) return 0;
  std::vector<cv::Mat> frames;
  for (const auto& frame : set.frames) frames.push_back(view(frame, CV_8UC1));
  StripeImage stripes;
  StripeDecoder(PatternLayout(set.bits, set.inverse_frames), DecoderParams())
      .decode(frames, stripes);
  const Triangulator& triangulator = smallPair();
  if (frames[0].cols != triangulator.calibration().camera.width ||
      frames[0].rows != triangulator.calibration().camera.height)
    return 0;
  std::vector<float> points(4 * frames[0].total());
  triangulator.triangulate(stripes.coordinate, points.data(), 4);
  if (!set.texture.data.empty()) {  // the colour loop reads every texture pixel
    const cv::Mat texture = view(set.texture, CV_8UC3);
    volatile unsigned sink = 0;
    for (int v = 0; v < texture.rows; ++v)
      for (int u = 0; u < texture.cols; ++u) sink = sink + texture.at<cv::Vec3b>(v, u)[0];
  }
  return 0;
}
