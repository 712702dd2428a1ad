// Least-squares sphere fit for accuracy tests (algebraic start, then Gauss-Newton on the
// geometric distance).
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace body_scan_driver::test {

struct SphereFit {
  Eigen::Vector3d center;
  double radius;
  double rms;  // of the point-to-surface distances
};

inline SphereFit fitSphere(const std::vector<Eigen::Vector3d>& points) {
  // |p|^2 = 2 c . p + (r^2 - |c|^2) is linear in (c, k); centring the points keeps it well
  // conditioned for a small cap far from the origin.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) centroid += p / static_cast<double>(points.size());
  Eigen::MatrixXd a(points.size(), 4);
  Eigen::VectorXd b(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d p = points[i] - centroid;
    a.row(i) << 2 * p.transpose(), 1.0;
    b(i) = p.squaredNorm();
  }
  const Eigen::Vector4d x = a.colPivHouseholderQr().solve(b);
  SphereFit fit{centroid + x.head<3>(), std::sqrt(x(3) + x.head<3>().squaredNorm()), 0};
  for (int iteration = 0; iteration < 10; ++iteration) {
    Eigen::MatrixXd jacobian(points.size(), 4);
    Eigen::VectorXd residual(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d offset = points[i] - fit.center;
      const double distance = offset.norm();
      residual(i) = distance - fit.radius;
      jacobian.row(i) << -offset.transpose() / distance, -1.0;
    }
    const Eigen::Vector4d step = jacobian.colPivHouseholderQr().solve(-residual);
    fit.center += step.head<3>();
    fit.radius += step(3);
    fit.rms = std::sqrt(residual.squaredNorm() / points.size());
  }
  return fit;
}

}  // namespace body_scan_driver::test
