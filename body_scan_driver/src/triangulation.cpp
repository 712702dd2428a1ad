#include <body_scan_driver/triangulation.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace body_scan {

Triangulator::Triangulator(const PairCalibration& calibration, double min_range, double max_range)
    : calibration_(calibration),
      min_range_(static_cast<float>(min_range)),
      max_range_(static_cast<float>(max_range)) {
  const PinholeCamera& camera = calibration.camera;
  if (calibration.projector.stripeCount() < 2)
    throw std::invalid_argument("calibration of '" + calibration.pair_id +
                                "' has fewer than 2 stripe planes");
  ray_x_.resize(static_cast<size_t>(camera.width) * camera.height);
  ray_y_.resize(ray_x_.size());
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector2d ray = camera.normalizedPoint({u, v});
      ray_x_[static_cast<size_t>(v) * camera.width + u] = static_cast<float>(ray.x());
      ray_y_[static_cast<size_t>(v) * camera.width + u] = static_cast<float>(ray.y());
    }
  for (const Eigen::Vector4d& plane : calibration.projector.planes)
    for (int i = 0; i < 4; ++i) planes_.push_back(static_cast<float>(plane[i]));
}

size_t Triangulator::triangulate(const cv::Mat1f& coordinate, float* out,
                                 size_t point_stride) const {
  const PinholeCamera& camera = calibration_.camera;
  if (coordinate.cols != camera.width || coordinate.rows != camera.height)
    throw std::invalid_argument(
        "stripe image is " + std::to_string(coordinate.cols) + "x" +
        std::to_string(coordinate.rows) + " but the calibration of '" + calibration_.pair_id +
        "' is for " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
        ": use the calibration file of this camera and resolution");
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  const int last_lower = calibration_.projector.stripeCount() - 2;
  size_t valid = 0;
  for (int v = 0; v < camera.height; ++v) {
    const float* s = coordinate.ptr<float>(v);
    const size_t row = static_cast<size_t>(v) * camera.width;
    for (int u = 0; u < camera.width; ++u) {
      float* point = out + (row + u) * point_stride;
      // Plane i sits at the stripe centre s = i + 0.5; interpolate between neighbours.
      const float position = s[u] - 0.5f;
      if (!(position > -1.f)) {  // also rejects NaN
        point[0] = point[1] = point[2] = kNaN;
        continue;
      }
      int lower = static_cast<int>(position);
      lower = lower > last_lower ? last_lower : lower;
      const float f = position - static_cast<float>(lower);
      const float* p = &planes_[4 * static_cast<size_t>(lower)];
      const float a = p[0] + f * (p[4] - p[0]), b = p[1] + f * (p[5] - p[1]);
      const float c = p[2] + f * (p[6] - p[2]), d = p[3] + f * (p[7] - p[3]);
      const float x = ray_x_[row + u], y = ray_y_[row + u];
      const float z = -d / (a * x + b * y + c);  // eq 3.12 for a general plane
      if (z > min_range_ && z < max_range_) {
        point[0] = x * z;  // eq 3.10
        point[1] = y * z;  // eq 3.11
        point[2] = z;
        ++valid;
      } else {
        point[0] = point[1] = point[2] = kNaN;
      }
    }
  }
  return valid;
}

}  // namespace body_scan
