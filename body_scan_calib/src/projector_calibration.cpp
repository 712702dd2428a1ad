#include <body_scan_calib/projector_calibration.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace body_scan_calib {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Mean absolute coordinate change along rows vs along columns: the stripes change along the
// axis with the larger one (rows for the pole's vertical baseline).
bool stripesChangeAlongRows(const cv::Mat1f& coordinate) {
  double along_rows = 0, along_columns = 0;
  for (int v = 0; v + 1 < coordinate.rows; v += 4)
    for (int u = 0; u + 1 < coordinate.cols; u += 4) {
      const float c = coordinate(v, u), below = coordinate(v + 1, u), right = coordinate(v, u + 1);
      if (std::isfinite(c) && std::isfinite(below) && std::abs(below - c) < 2)
        along_rows += std::abs(below - c);
      if (std::isfinite(c) && std::isfinite(right) && std::abs(right - c) < 2)
        along_columns += std::abs(right - c);
    }
  return along_rows >= along_columns;
}

}  // namespace

std::vector<StripeCentreSample> extractStripeCentres(const cv::Mat1f& coordinate, int stripe_count,
                                                     const cv::Mat1b& region) {
  if (!region.empty() && region.size() != coordinate.size())
    throw std::invalid_argument("extractStripeCentres: region " + std::to_string(region.cols) +
                                "x" + std::to_string(region.rows) +
                                " does not match the coordinate image; pass an empty region or "
                                "one of the image size");
  const bool along_rows = stripesChangeAlongRows(coordinate);
  const int lines = along_rows ? coordinate.cols : coordinate.rows;
  const int steps = along_rows ? coordinate.rows : coordinate.cols;
  auto at = [&](int line, int step) -> float {
    const int v = along_rows ? step : line, u = along_rows ? line : step;
    if (!region.empty() && !region(v, u)) return std::numeric_limits<float>::quiet_NaN();
    return coordinate(v, u);
  };
  std::vector<StripeCentreSample> samples;
  for (int line = 0; line < lines; ++line)
    for (int step = 0; step + 1 < steps; ++step) {
      const double c0 = at(line, step), c1 = at(line, step + 1);
      if (!std::isfinite(c0) || !std::isfinite(c1) || c0 == c1 || std::abs(c1 - c0) > 1.0) continue;
      // Stripe centres t = i + 0.5 in [min, max): each crossing is counted once.
      const double low = std::min(c0, c1), high = std::max(c0, c1);
      for (int stripe = static_cast<int>(std::ceil(low - 0.5)); stripe + 0.5 < high; ++stripe) {
        if (stripe < 0 || stripe >= stripe_count) continue;
        const double position = step + (stripe + 0.5 - c0) / (c1 - c0);
        samples.push_back({stripe, along_rows ? Eigen::Vector2d(line, position)
                                              : Eigen::Vector2d(position, line)});
      }
    }
  return samples;
}

Eigen::Matrix<double, 4, 3> imageToCameraTransform(const Eigen::Isometry3d& board_to_camera) {
  const Eigen::Vector3d r3 = board_to_camera.linear().col(2);
  const Eigen::Vector3d t = board_to_camera.translation();
  Eigen::Matrix<double, 4, 3> transform;
  transform.topRows<3>().setIdentity();
  transform.row(3) = r3.transpose() / r3.dot(t);
  return transform;
}

std::vector<Eigen::Vector3d> liftStripePixels(const body_scan_driver::PinholeCamera& camera,
                                              const Eigen::Isometry3d& board_to_camera,
                                              const std::vector<StripeCentreSample>& samples) {
  const Eigen::Matrix<double, 4, 3> transform = imageToCameraTransform(board_to_camera);
  std::vector<Eigen::Vector3d> points;
  points.reserve(samples.size());
  for (const StripeCentreSample& sample : samples) {
    const Eigen::Vector4d homogeneous =
        transform * camera.normalizedPoint(sample.pixel).homogeneous();
    const Eigen::Vector3d point = homogeneous.head<3>() / homogeneous[3];
    points.push_back(point.z() > 0 ? point : Eigen::Vector3d::Constant(kNaN));
  }
  return points;
}

PlaneFit fitPlane(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 3) return {Eigen::Vector4d::Constant(kNaN), kNaN};
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) scatter += (p - centroid) * (p - centroid).transpose();
  // The normal is the direction of least spread (smallest eigenvalue, sorted first).
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  const Eigen::Vector3d normal = solver.eigenvectors().col(0);
  const double rms = std::sqrt(std::max(0.0, solver.eigenvalues()(0)) / points.size());
  return {orientPlane(Eigen::Vector4d(normal.x(), normal.y(), normal.z(), -normal.dot(centroid))),
          rms};
}

Eigen::Vector4d orientPlane(const Eigen::Vector4d& plane) {
  const int dominant = std::abs(plane[1]) > std::abs(plane[0]) ? 1 : 0;
  return plane[dominant] > 0 ? Eigen::Vector4d(-plane) : plane;
}

ProjectorCalibrationResult calibrateStripePlanes(
    const body_scan_driver::PinholeCamera& camera,
    const std::vector<ReferencePlaneObservation>& observations,
    const ProjectorCalibrationOptions& options) {
  if (observations.size() < 3)
    throw std::invalid_argument("projector calibration needs at least 3 reference-plane poses (" +
                                std::to_string(observations.size()) +
                                " given): a stripe seen on fewer poses has no unique plane; "
                                "capture more board poses");
  const int stripes = options.stripe_count;
  ProjectorCalibrationResult result;
  std::vector<std::vector<int>> stripe_points(stripes);
  std::vector<std::vector<char>> seen(stripes, std::vector<char>(observations.size(), 0));
  for (size_t pose = 0; pose < observations.size(); ++pose) {
    const ReferencePlaneObservation& observation = observations[pose];
    if (observation.stripe_coordinate.empty())
      throw std::invalid_argument("reference-plane pose " + std::to_string(pose) +
                                  " has an empty stripe image; decode its pattern set first");
    const std::vector<StripeCentreSample> samples =
        extractStripeCentres(observation.stripe_coordinate, stripes, observation.region);
    const std::vector<Eigen::Vector3d> points =
        liftStripePixels(camera, observation.board_to_camera, samples);
    for (size_t i = 0; i < samples.size(); ++i) {
      if (!points[i].allFinite()) continue;
      stripe_points[samples[i].stripe].push_back(static_cast<int>(result.points.size()));
      seen[samples[i].stripe][pose] = 1;
      result.points.push_back(points[i]);
      result.point_stripes.push_back(samples[i].stripe);
      result.point_poses.push_back(static_cast<int>(pose));
      result.point_pixels.push_back(samples[i].pixel);
    }
  }

  result.projector.planes.assign(stripes, Eigen::Vector4d::Constant(kNaN));
  result.poses_per_stripe.assign(stripes, 0);
  result.points_per_stripe.assign(stripes, 0);
  result.rms_per_stripe_m.assign(stripes, kNaN);
  double squared_sum = 0;
  size_t fitted_points = 0;
  for (int stripe = 0; stripe < stripes; ++stripe) {
    result.poses_per_stripe[stripe] =
        static_cast<int>(std::count(seen[stripe].begin(), seen[stripe].end(), 1));
    if (result.poses_per_stripe[stripe] < options.min_poses_per_stripe) {
      result.missing_stripes.push_back(stripe);
      continue;
    }
    std::vector<Eigen::Vector3d> points;
    for (int index : stripe_points[stripe]) points.push_back(result.points[index]);
    PlaneFit fit = fitPlane(points);
    const double limit = options.outlier_rms_factor * fit.rms;
    std::vector<Eigen::Vector3d> inliers;
    for (const Eigen::Vector3d& p : points)
      if (std::abs(fit.plane.head<3>().dot(p) + fit.plane[3]) <= limit) inliers.push_back(p);
    const bool refit = inliers.size() >= 3 && inliers.size() < points.size();
    if (refit) fit = fitPlane(inliers);
    const size_t used = refit ? inliers.size() : points.size();
    result.projector.planes[stripe] = fit.plane;
    result.points_per_stripe[stripe] = static_cast<int>(used);
    result.rms_per_stripe_m[stripe] = fit.rms;
    squared_sum += fit.rms * fit.rms * used;
    fitted_points += used;
  }
  result.rms_m = fitted_points ? std::sqrt(squared_sum / fitted_points) : kNaN;
  return result;
}

}  // namespace body_scan_calib
