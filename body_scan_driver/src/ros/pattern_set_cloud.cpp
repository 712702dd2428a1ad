#include <body_scan_driver/ros/conversions.h>
#include <body_scan_driver/ros/pattern_set_cloud.h>

#include <cmath>
#include <cstring>

namespace body_scan_driver {
namespace {

// A cv::Mat header over an image message's bytes (no copy); the image has passed checkImage.
cv::Mat view(const sensor_msgs::Image& image, int type) {
  return cv::Mat(static_cast<int>(image.height), static_cast<int>(image.width), type,
                 const_cast<uint8_t*>(image.data.data()), image.step);
}

float packRgb(uint8_t r, uint8_t g, uint8_t b) {  // PCL's packed-float rgb field
  const uint32_t packed = (static_cast<uint32_t>(r) << 16) | (static_cast<uint32_t>(g) << 8) | b;
  float value;
  std::memcpy(&value, &packed, sizeof value);
  return value;
}

}  // namespace

size_t PatternSetCloud::triangulate(const body_scan_msgs::PatternSet& set,
                                    const Triangulator& triangulator,
                                    sensor_msgs::PointCloud2& cloud) {
  std::vector<cv::Mat> frames;
  for (const sensor_msgs::Image& frame : set.frames) frames.push_back(view(frame, CV_8UC1));
  if (!decoder_ || decoder_->layout().bits() != set.bits ||
      decoder_->layout().inverseFrames() != set.inverse_frames)
    decoder_ =
        std::make_unique<StripeDecoder>(PatternLayout(set.bits, set.inverse_frames), params_);
  decoder_->decode(frames, stripes_);
  refineDecoding(frames, decoder_->layout(), {}, stripes_, robust_);

  const cv::Size size = frames[0].size();
  layoutFloatCloud(cloud, size.width, size.height, /*rgb=*/true);
  cloud.is_dense = false;
  float* points = reinterpret_cast<float*>(cloud.data.data());
  const size_t valid = triangulator.triangulate(stripes_.coordinate, points, 4);
  // World alignment (eq 4.1): tf2 carries the rigid part world -> optical frame; the residual
  // linear part L of H_a = [R L | t] is applied here, in the camera frame.
  if (const auto& alignment = triangulator.calibration().alignment) {
    const Eigen::Matrix3f residual = alignment->residual_linear.cast<float>();
    const size_t count = static_cast<size_t>(size.width) * size.height;
    for (size_t i = 0; i < count; ++i) {
      Eigen::Map<Eigen::Vector3f> point(points + 4 * i);
      if (std::isfinite(point.z())) point = residual * point;
    }
  }
  // Colour from the texture (checked: the frames' size), else white.
  const bool coloured = !set.texture.data.empty();
  const cv::Mat texture = coloured ? view(set.texture, CV_8UC3) : cv::Mat();
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) {
      const cv::Vec3b c = coloured ? texture.at<cv::Vec3b>(v, u) : cv::Vec3b(255, 255, 255);
      points[4 * (static_cast<size_t>(v) * size.width + u) + 3] = packRgb(c[0], c[1], c[2]);
    }
  return valid;
}

}  // namespace body_scan_driver
