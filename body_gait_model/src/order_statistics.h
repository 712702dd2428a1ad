// Order statistics shared by the fitting stages (axes, torso, limbs): robust to stray points.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <vector>

namespace body_gait_model {

// The value with fraction * (n - 1) values below it (0.995: the far end but stray points).
// Reorders values; values must not be empty.
inline double quantile(std::vector<double>& values, double fraction) {
  const auto index = static_cast<size_t>(fraction * (values.size() - 1));
  std::nth_element(values.begin(), values.begin() + index, values.end());
  return values[index];
}

// Component-wise median (the upper one of an even count); points must not be empty.
inline Eigen::Vector3d componentMedian(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d median;
  std::vector<double> values;
  values.reserve(points.size());
  for (int axis = 0; axis < 3; ++axis) {
    values.clear();
    for (const auto& p : points) values.push_back(p[axis]);
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    median[axis] = values[values.size() / 2];
  }
  return median;
}

}  // namespace body_gait_model
