#include <body_scan_calib/pinhole_projector.h>
#include <body_scan_calib/projector_calibration.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace body_scan_calib {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Uniform cubic B-spline: the 4 basis weights at local parameter t in [0, 1) of a segment.
std::array<double, 4> cubicBasis(double t) {
  const double u = 1 - t;
  return {u * u * u / 6, (3 * t * t * t - 6 * t * t + 4) / 6,
          (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6, t * t * t / 6};
}

// The smooth model of StripePlaneModel (see the header): a pencil of planes through one line
// (the projector's centre line; a 1-D pinhole, pinhole_projector.h) fitted robustly to all
// points, whose stripe coordinate is then corrected by a smooth cubic B-spline of the stripe
// index (the projector's distortion). A stripe one pose saw is a line on that board: the
// pencil fixes its plane, which a plane per stripe cannot.
class SmoothStripePlanes {
 public:
  SmoothStripePlanes(int first, int last, int stripes_per_segment)
      : first_(first),
        segments_(std::max(1, (last - first + stripes_per_segment) / stripes_per_segment)),
        width_(static_cast<double>(last + 1 - first) / segments_),
        correction_(Eigen::VectorXd::Zero(segments_ + 3)) {}

  void fit(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& stripes) {
    std::vector<char> used(points.size(), 1);
    for (int round = 0; round < 4; ++round) {
      std::vector<Eigen::Vector3d> inliers;
      std::vector<double> coordinates;
      for (size_t i = 0; i < points.size(); ++i)
        if (used[i]) {
          inliers.push_back(points[i]);
          coordinates.push_back(stripes[i] + 0.5 + correctionAt(stripes[i] + 0.5));
        }
      pencil_ = estimatePinholeProjector(inliers, coordinates).projector;
      fitCorrection(points, stripes, used);
      // Residuals in stripes; inliers within 3 robust sigmas (median absolute deviation).
      std::vector<double> residuals(points.size()), magnitudes;
      for (size_t i = 0; i < points.size(); ++i) {
        residuals[i] = stripeResidual(points[i], stripes[i]);
        if (used[i]) magnitudes.push_back(std::abs(residuals[i]));
      }
      if (magnitudes.empty()) break;
      std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2,
                       magnitudes.end());
      const double sigma = std::max(1e-3, 1.4826 * magnitudes[magnitudes.size() / 2]);
      for (size_t i = 0; i < points.size(); ++i) used[i] = std::abs(residuals[i]) <= 3 * sigma;
    }
    double squared = 0;
    size_t count = 0;
    for (size_t i = 0; i < points.size(); ++i)
      if (used[i]) {
        squared += std::pow(distance(points[i], stripes[i]), 2);
        ++count;
      }
    rms_ = count ? std::sqrt(squared / count) : 0;
  }

  // Plane of stripe i's centre, unit normal, suite orientation.
  Eigen::Vector4d plane(int stripe) const {
    const Eigen::Vector4d p = pencil_.planeAt(stripe + 0.5 + correctionAt(stripe + 0.5));
    return orientPlane(p / p.head<3>().norm());
  }
  double distance(const Eigen::Vector3d& point, int stripe) const {
    const Eigen::Vector4d p = plane(stripe);
    return p.head<3>().dot(point) + p[3];
  }
  double rms() const { return rms_; }

 private:
  double stripeResidual(const Eigen::Vector3d& point, int stripe) const {
    return pencil_.stripeAt(point) - (stripe + 0.5 + correctionAt(stripe + 0.5));
  }
  std::array<double, 4> weights(double stripe_centre, int& segment) const {
    const double x = std::clamp((stripe_centre - first_) / width_, 0.0, segments_ - 1e-9);
    segment = std::min(segments_ - 1, static_cast<int>(x));
    return cubicBasis(x - segment);
  }
  double correctionAt(double stripe_centre) const {
    int segment;
    const std::array<double, 4> basis = weights(stripe_centre, segment);
    double value = 0;
    for (int j = 0; j < 4; ++j) value += basis[j] * correction_[segment + j];
    return value;
  }
  // Least squares of the pencil's coordinate minus the stripe centre, with a weak second-
  // difference penalty that only decides where no stripe was seen.
  void fitCorrection(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& stripes,
                     const std::vector<char>& used) {
    const int k = segments_ + 3;
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(k, k);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(k);
    size_t count = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      if (!used[i]) continue;
      ++count;
      int segment;
      const double centre = stripes[i] + 0.5;
      const std::array<double, 4> basis = weights(centre, segment);
      const double target = pencil_.stripeAt(points[i]) - centre;
      for (int r = 0; r < 4; ++r) {
        rhs[segment + r] += basis[r] * target;
        for (int c = 0; c < 4; ++c) normal(segment + r, segment + c) += basis[r] * basis[c];
      }
    }
    const double smoothing = 1e-3 * static_cast<double>(std::max<size_t>(count, 1)) / k;
    for (int j = 0; j + 2 < k; ++j) {
      const double w[3] = {1, -2, 1};
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) normal(j + r, j + c) += smoothing * w[r] * w[c];
    }
    correction_ = normal.ldlt().solve(rhs);
  }

  int first_, segments_;
  double width_;
  PinholeProjector pencil_;
  Eigen::VectorXd correction_;  // B-spline coefficients, stripes
  double rms_ = 0;
};

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
  if (options.model != StripePlaneModel::kPerStripe && !result.points.empty()) {
    const auto [low, high] =
        std::minmax_element(result.point_stripes.begin(), result.point_stripes.end());
    const int first = std::max(0, *low - options.extrapolation_margin);
    const int last = std::min(stripes - 1, *high + options.extrapolation_margin);
    SmoothStripePlanes smooth(first, last, std::max(4, options.stripes_per_spline_segment));
    smooth.fit(result.points, result.point_stripes);
    result.smooth_rms_m = smooth.rms();
    result.missing_stripes.clear();
    for (int stripe = 0; stripe < stripes; ++stripe) {
      const bool per_stripe = options.model == StripePlaneModel::kSmoothFillsGaps &&
                              result.poses_per_stripe[stripe] >= options.min_poses_per_stripe;
      if (per_stripe) continue;
      if (stripe < first || stripe > last) {
        result.projector.planes[stripe] = Eigen::Vector4d::Constant(kNaN);
        result.points_per_stripe[stripe] = 0;
        result.rms_per_stripe_m[stripe] = kNaN;
        result.missing_stripes.push_back(stripe);
        continue;
      }
      result.projector.planes[stripe] = smooth.plane(stripe);
      result.smooth_stripes.push_back(stripe);
      if (stripe_points[stripe].empty()) result.extrapolated_stripes.push_back(stripe);
      int used = 0;
      double squared = 0;
      for (int index : stripe_points[stripe]) {
        const double d = smooth.distance(result.points[index], stripe);
        if (std::abs(d) > 3 * smooth.rms()) continue;
        ++used;
        squared += d * d;
      }
      result.points_per_stripe[stripe] = used;
      result.rms_per_stripe_m[stripe] = used ? std::sqrt(squared / used) : kNaN;
      squared_sum += squared;
      fitted_points += used;
    }
  }
  result.rms_m = fitted_points ? std::sqrt(squared_sum / fitted_points) : kNaN;
  return result;
}

}  // namespace body_scan_calib
