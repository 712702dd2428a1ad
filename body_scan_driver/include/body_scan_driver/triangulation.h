// Triangulation of a decoded stripe image into camera-frame points (thesis eqs 3.9-3.12):
// each pixel's undistorted ray meets the plane of its (fractional) stripe coordinate.
#pragma once

#include <body_scan_driver/pair_model.h>
#include <body_scan_driver/simd.h>

#include <cstddef>
#include <opencv2/core/mat.hpp>
#include <vector>

namespace body_scan_driver {

// triangulate() is const and keeps no state between calls: one instance may be used from
// several threads at once.
class Triangulator {
 public:
  // Precomputes the undistorted ray of every pixel (the costly part of eq 3.3's inverse).
  // max_simd caps the vector instruction set (simd.h); every level gives the same floats.
  explicit Triangulator(const PairCalibration& calibration, double min_range = 0.2,
                        double max_range = 5.0, SimdLevel max_simd = SimdLevel::kAvx512);

  // Writes x, y, z (metres, camera optical frame) for every pixel of `coordinate` (row-major)
  // into out[i * point_stride + 0..2]; NaN where the pixel is invalid or out of range.
  // Other floats of a point (e.g. rgb at index 3) are left as they are. Returns the number of
  // valid points. coordinate must match the calibration's image size.
  size_t triangulate(const cv::Mat1f& coordinate, float* out, size_t point_stride) const;

  const PairCalibration& calibration() const { return calibration_; }

 private:
  PairCalibration calibration_;
  SimdLevel simd_;
  float min_range_, max_range_;
  std::vector<float> ray_x_, ray_y_;  // ideal normalized coordinates per pixel
  std::vector<float> planes_;         // stripe planes, 4 floats each
  std::vector<float> plane_deltas_;   // planes_[i + 1] - planes_[i], for interpolation
};

}  // namespace body_scan_driver
