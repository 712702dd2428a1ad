#include <body_scan_driver/pair_model.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace body_scan_driver {

Eigen::Vector2d PinholeCamera::distortedPixel(const Eigen::Vector2d& normalized) const {
  const double r2 = normalized.squaredNorm();
  const Eigen::Vector2d distorted = normalized * (1.0 + k1 * r2 + k2 * r2 * r2);
  return {alpha * distorted.x() + gamma * distorted.y() + u0, beta * distorted.y() + v0};
}

Eigen::Vector2d PinholeCamera::normalizedPoint(const Eigen::Vector2d& pixel) const {
  const double y_distorted = (pixel.y() - v0) / beta;
  const Eigen::Vector2d distorted((pixel.x() - u0 - gamma * y_distorted) / alpha, y_distorted);
  Eigen::Vector2d ideal = distorted;
  // Fixed-point iteration converges fast for the mild distortion of real lenses.
  for (int iteration = 0; iteration < 20; ++iteration) {
    const double r2 = ideal.squaredNorm();
    const Eigen::Vector2d next = distorted / (1.0 + k1 * r2 + k2 * r2 * r2);
    if ((next - ideal).squaredNorm() < 1e-24) return next;
    ideal = next;
  }
  return ideal;
}

Eigen::Vector4d StripePlaneProjector::planeAt(double stripe_coordinate) const {
  const double position = stripe_coordinate - 0.5;
  const int last = stripeCount() - 1;
  const int lower = std::clamp(static_cast<int>(std::floor(position)), 0, std::max(0, last - 1));
  if (last <= 0) return planes.front();
  const double fraction = position - lower;  // may leave [0, 1] at the ends: extrapolate
  return planes[lower] + fraction * (planes[lower + 1] - planes[lower]);
}

StripePlaneProjector::Explicit StripePlaneProjector::explicitParameters(int stripe) const {
  const Eigen::Vector4d& p = planes.at(stripe);
  // Swap the roles of x and y when the plane normal is mostly along y (vertical baseline).
  const bool vertical = std::abs(p[1]) > std::abs(p[0]);
  const double lead = vertical ? p[1] : p[0], side = vertical ? p[0] : p[1];
  return {p[3] / lead, std::atan(-p[2] / lead), std::atan(-side / lead)};
}

WorldAlignment WorldAlignment::fromAffine(const Eigen::Matrix<double, 3, 4>& affine) {
  const Eigen::Matrix3d linear = affine.leftCols<3>();
  if (!linear.allFinite() || !affine.col(3).allFinite())
    throw std::invalid_argument("world alignment: the affine transform has non-finite entries");
  // Polar decomposition from the SVD A = U S V^T: R = U D V^T, L = V D S V^T, with D flipping
  // the last axis if needed so that R is a proper rotation.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(linear, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d singular_values = svd.singularValues();
  if (!(singular_values.minCoeff() > 1e-9 * singular_values.maxCoeff()))
    throw std::invalid_argument(
        "world alignment: the affine transform is singular (the calibration points are "
        "coplanar or too few); observe the cylinder over a larger area");
  Eigen::Vector3d flip(1, 1, 1);
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) flip[2] = -1;
  WorldAlignment alignment;
  alignment.world_from_camera.linear() =
      svd.matrixU() * flip.asDiagonal() * svd.matrixV().transpose();
  alignment.world_from_camera.translation() = affine.col(3);
  alignment.residual_linear =
      svd.matrixV() * flip.asDiagonal() * singular_values.asDiagonal() * svd.matrixV().transpose();
  return alignment;
}

Eigen::Matrix<double, 3, 4> WorldAlignment::affine() const {
  Eigen::Matrix<double, 3, 4> result;
  result << world_from_camera.linear() * residual_linear, world_from_camera.translation();
  return result;
}

Eigen::Vector3d intersectRayPlane(const Eigen::Vector2d& normalized, const Eigen::Vector4d& plane) {
  const double denominator = plane[0] * normalized.x() + plane[1] * normalized.y() + plane[2];
  const double z = -plane[3] / denominator;
  if (!(z > 0) || !std::isfinite(z))
    return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  return {normalized.x() * z, normalized.y() * z, z};
}

}  // namespace body_scan_driver
