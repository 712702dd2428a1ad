#include <body_scan_calib/sphere_accuracy.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>

namespace body_scan_calib {

IdealSphereFit fitIdealSphere(const std::vector<Eigen::Vector3d>& points, double radius) {
  const size_t count = points.size();
  if (count < 4)
    throw std::invalid_argument("sphere fit needs at least 4 points, got " + std::to_string(count) +
                                ": is the sphere in the camera's view and lit by the projector?");
  // Algebraic start: |p|^2 = 2 c . p + k is linear in (c, k); centred for conditioning.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) centroid += p / static_cast<double>(count);
  Eigen::MatrixXd design(count, 4);
  Eigen::VectorXd rhs(count);
  for (size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d p = points[i] - centroid;
    design.row(i) << 2 * p.transpose(), 1.0;
    rhs(i) = p.squaredNorm();
  }
  Eigen::Vector3d center = centroid + design.colPivHouseholderQr().solve(rhs).head<3>();
  // A visible cap constrains the free radius poorly; with the radius fixed, the centre moves
  // along the viewing direction until the points' distances match it.
  for (int iteration = 0; iteration < 30; ++iteration) {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : points) {
      const Eigen::Vector3d offset = p - center;
      const double distance = offset.norm();
      const Eigen::Vector3d jacobian = -offset / distance;  // d(distance - r)/d(center)
      normal += jacobian * jacobian.transpose();
      gradient += jacobian * (distance - radius);
    }
    const Eigen::Vector3d step = normal.ldlt().solve(-gradient);
    center += step;
    if (step.norm() < 1e-12) break;
  }
  double squared = 0;
  for (const Eigen::Vector3d& p : points) {
    const double error = (p - center).norm() - radius;
    squared += error * error;
  }
  return {center, squared / count, static_cast<int>(count)};
}

std::vector<std::vector<Eigen::Vector3d>> segmentSpheres(
    const std::vector<Eigen::Vector3d>& cloud, const std::vector<Eigen::Vector3d>& nominal_centers,
    double capture_radius) {
  std::vector<std::vector<Eigen::Vector3d>> spheres(nominal_centers.size());
  for (const Eigen::Vector3d& p : cloud) {
    if (!p.allFinite()) continue;
    for (size_t k = 0; k < nominal_centers.size(); ++k)
      if ((p - nominal_centers[k]).norm() <= capture_radius) {
        spheres[k].push_back(p);
        break;
      }
  }
  return spheres;
}

}  // namespace body_scan_calib
