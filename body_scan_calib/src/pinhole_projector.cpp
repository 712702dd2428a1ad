#include <body_scan_calib/pinhole_projector.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

namespace body_scan_calib {

double PinholeProjector::stripeAt(const Eigen::Vector3d& point) const {
  const Eigen::Vector2d projected = projection * point.homogeneous();
  return projected[0] / projected[1];
}

Eigen::Vector4d PinholeProjector::planeAt(double stripe_coordinate) const {
  return (projection.row(0) - stripe_coordinate * projection.row(1)).transpose();
}

body_scan_driver::StripePlaneProjector PinholeProjector::toStripePlanes(int stripe_count) const {
  body_scan_driver::StripePlaneProjector planes;
  for (int i = 0; i < stripe_count; ++i) planes.planes.push_back(planeAt(i + 0.5));
  // One overall sign so the planes face like the fitted ones (orientation of the suite).
  const Eigen::Vector4d& middle = planes.planes[stripe_count / 2];
  const int dominant = std::abs(middle[1]) > std::abs(middle[0]) ? 1 : 0;
  if (middle[dominant] > 0)
    for (Eigen::Vector4d& plane : planes.planes) plane = -plane;
  return planes;
}

namespace {

// Residuals s - (p1 . X) / (p2 . X) and their Jacobian with respect to the 8 entries of P
// (row-major: p1 then p2).
double residuals(const Eigen::Matrix<double, 2, 4>& projection,
                 const std::vector<Eigen::Vector4d>& points, const std::vector<double>& stripes,
                 Eigen::VectorXd* residual, Eigen::MatrixXd* jacobian) {
  double squared = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const double numerator = projection.row(0).dot(points[i]);
    const double denominator = projection.row(1).dot(points[i]);
    const double r = stripes[i] - numerator / denominator;
    squared += r * r;
    if (residual) (*residual)(i) = r;
    if (jacobian) {
      jacobian->block<1, 4>(i, 0) = -points[i].transpose() / denominator;
      jacobian->block<1, 4>(i, 4) = points[i].transpose() * numerator / (denominator * denominator);
    }
  }
  return squared;
}

}  // namespace

PinholeProjectorFit estimatePinholeProjector(const std::vector<Eigen::Vector3d>& points,
                                             const std::vector<double>& stripe_coordinates) {
  const size_t count = points.size();
  if (count < 7 || stripe_coordinates.size() != count)
    throw std::invalid_argument(
        "pinhole projector fit needs at least 7 points with one stripe coordinate each (" +
        std::to_string(count) + " points, " + std::to_string(stripe_coordinates.size()) +
        " coordinates): capture more reference-plane poses");
  // Hartley normalization: points centred with mean distance sqrt(3), coordinates centred with
  // unit spread, so the DLT's singular vectors are well conditioned.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double stripe_mean = 0;
  for (size_t i = 0; i < count; ++i) {
    centroid += points[i] / count;
    stripe_mean += stripe_coordinates[i] / count;
  }
  double spread = 0, stripe_spread = 0;
  for (size_t i = 0; i < count; ++i) {
    spread += (points[i] - centroid).norm() / count;
    stripe_spread += std::abs(stripe_coordinates[i] - stripe_mean) / count;
  }
  const double point_scale = std::sqrt(3.0) / spread, stripe_scale = 1.0 / stripe_spread;
  std::vector<Eigen::Vector4d> normalized(count);
  std::vector<double> stripes(count);
  Eigen::MatrixXd design(count, 8);
  for (size_t i = 0; i < count; ++i) {
    normalized[i] = (point_scale * (points[i] - centroid)).homogeneous();
    stripes[i] = stripe_scale * (stripe_coordinates[i] - stripe_mean);
    design.block<1, 4>(i, 0) = normalized[i].transpose();
    design.block<1, 4>(i, 4) = -stripes[i] * normalized[i].transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(design, Eigen::ComputeThinV);
  const Eigen::VectorXd smallest = svd.matrixV().col(7);
  Eigen::Matrix<double, 2, 4> projection;
  projection.row(0) = smallest.head<4>().transpose();
  projection.row(1) = smallest.tail<4>().transpose();

  // Levenberg-Marquardt on the geometric residual; |P| is renormalized after each step (the
  // scale is a gauge freedom, the damping keeps the normal equations regular).
  Eigen::VectorXd residual(count);
  Eigen::MatrixXd jacobian(count, 8);
  double cost = residuals(projection, normalized, stripes, nullptr, nullptr);
  double damping = 1e-3;
  int iteration = 0;
  for (; iteration < 50; ++iteration) {
    residuals(projection, normalized, stripes, &residual, &jacobian);
    const Eigen::Matrix<double, 8, 8> normal = jacobian.transpose() * jacobian;
    const Eigen::Matrix<double, 8, 1> gradient = jacobian.transpose() * residual;
    bool improved = false;
    for (int attempt = 0; attempt < 10 && !improved; ++attempt) {
      Eigen::Matrix<double, 8, 8> damped = normal;
      damped.diagonal() *= 1.0 + damping;
      const Eigen::Matrix<double, 8, 1> step = damped.ldlt().solve(-gradient);
      Eigen::Matrix<double, 2, 4> candidate = projection;
      candidate.row(0) += step.head<4>().transpose();
      candidate.row(1) += step.tail<4>().transpose();
      candidate /= candidate.norm();
      const double candidate_cost = residuals(candidate, normalized, stripes, nullptr, nullptr);
      if (candidate_cost < cost) {
        improved = cost - candidate_cost > 1e-12 * cost;
        projection = candidate;
        cost = candidate_cost;
        damping = std::max(1e-9, damping * 0.3);
        if (!improved) attempt = 10;
      } else {
        damping *= 10;
      }
    }
    if (!improved) break;
  }

  // Undo the normalization: s = s_mean + (p1 . Xn) / (stripe_scale p2 . Xn) with
  // Xn = T X, T = [k I, -k c; 0 1].
  Eigen::Matrix4d to_normalized = Eigen::Matrix4d::Identity();
  to_normalized.topLeftCorner<3, 3>() *= point_scale;
  to_normalized.topRightCorner<3, 1>() = -point_scale * centroid;
  Eigen::Matrix<double, 2, 2> from_stripe;
  from_stripe << 1.0 / stripe_scale, stripe_mean, 0, 1;
  PinholeProjectorFit fit;
  fit.projector.projection = from_stripe * projection * to_normalized;
  fit.projector.projection /= fit.projector.projection.norm();
  fit.rms_stripes = std::sqrt(cost / count) / stripe_scale;
  fit.iterations = iteration;
  return fit;
}

}  // namespace body_scan_calib
