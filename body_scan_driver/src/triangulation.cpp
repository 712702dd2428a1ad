#include <body_scan_driver/triangulation.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace body_scan {

namespace {

// The per-pixel work over plain arrays. Stripes cross a row rarely (they are bands across the
// image), so each row is cut into runs of one plane index: within a run the plane and its
// slope are constants and the loop vectorizes; a NaN coordinate gives a NaN depth.
size_t triangulateRows(const float* coordinates, size_t coordinate_step, int width, int height,
                       const float* rays_x, const float* rays_y, const float* planes,
                       const float* deltas, int stripe_count, float min_range, float max_range,
                       float* out, size_t point_stride) {
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  const int last_lower = stripe_count - 2;
  std::vector<float> depth_buffer(width);
  std::vector<int> lower_buffer(width);
  float* __restrict depth = depth_buffer.data();
  int* __restrict lower = lower_buffer.data();
  size_t valid = 0;
  for (int v = 0; v < height; ++v) {
    const float* __restrict s = coordinates + static_cast<size_t>(v) * coordinate_step;
    const size_t row = static_cast<size_t>(v) * width;
    const float* __restrict ray_x = rays_x + row;
    const float* __restrict ray_y = rays_y + row;
    // Plane i sits at the stripe centre s = i + 0.5: pixel u interpolates planes lower[u] and
    // lower[u] + 1.
    for (int u = 0; u < width; ++u) {
      const float position = s[u] - 0.5f;  // NaN (invalid pixel) takes plane 0, depth stays NaN
      lower[u] = position > 0.f ? std::min(static_cast<int>(position), last_lower) : 0;
    }
    int row_valid = 0;
    for (int start = 0; start < width;) {
      int end = start + 1;
      while (end < width && lower[end] == lower[start]) ++end;
      const float* p = planes + 4 * lower[start];
      const float* dp = deltas + 4 * lower[start];
      const float base = static_cast<float>(lower[start]) + 0.5f;
      const float a = p[0], b = p[1], c = p[2], d = p[3];
      const float da = dp[0], db = dp[1], dc = dp[2], dd = dp[3];
      for (int u = start; u < end; ++u) {
        const float f = s[u] - base;
        const float z = -(d + f * dd) / ((a + f * da) * ray_x[u] + (b + f * db) * ray_y[u] +
                                         (c + f * dc));          // eq 3.12
        const int in_range = (z > min_range) & (z < max_range);  // 0 for NaN
        depth[u] = in_range ? z : kNaN;
        row_valid += in_range;
      }
      start = end;
    }
    valid += static_cast<size_t>(row_valid);
    float* points = out + row * point_stride;
    for (int u = 0; u < width; ++u) {
      float* point = points + u * point_stride;
      point[0] = ray_x[u] * depth[u];  // eq 3.10
      point[1] = ray_y[u] * depth[u];  // eq 3.11
      point[2] = depth[u];
    }
  }
  return valid;
}

}  // namespace

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
  const auto& planes = calibration.projector.planes;
  for (size_t k = 0; k < planes.size(); ++k)
    for (int i = 0; i < 4; ++i) {
      planes_.push_back(static_cast<float>(planes[k][i]));
      plane_deltas_.push_back(
          k + 1 < planes.size() ? static_cast<float>(planes[k + 1][i] - planes[k][i]) : 0.f);
    }
}

size_t Triangulator::triangulate(const cv::Mat1f& coordinate, float* out,
                                 size_t point_stride) const {
  const PinholeCamera& camera = calibration_.camera;
  if (coordinate.cols != camera.width || coordinate.rows != camera.height)
    throw std::invalid_argument("stripe image is " + std::to_string(coordinate.cols) + "x" +
                                std::to_string(coordinate.rows) + " but the calibration of '" +
                                calibration_.pair_id + "' is for " + std::to_string(camera.width) +
                                "x" + std::to_string(camera.height) +
                                ": use the calibration file of this camera and resolution");
  return triangulateRows(coordinate.ptr<float>(), coordinate.step1(), camera.width, camera.height,
                         ray_x_.data(), ray_y_.data(), planes_.data(), plane_deltas_.data(),
                         calibration_.projector.stripeCount(), min_range_, max_range_, out,
                         point_stride);
}

}  // namespace body_scan
