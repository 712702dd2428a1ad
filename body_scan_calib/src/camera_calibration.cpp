#include <body_scan_calib/camera_calibration.h>
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

namespace body_scan_calib {
namespace {

// Intrinsic parameter block of the refinement, in the order of CameraCalibrationResult::std_devs.
enum Intrinsic { kAlpha, kBeta, kGamma, kU0, kV0, kK1, kK2, kIntrinsicCount };

std::array<double, kIntrinsicCount> toIntrinsics(const body_scan_driver::PinholeCamera& c) {
  return {c.alpha, c.beta, c.gamma, c.u0, c.v0, c.k1, c.k2};
}

void fromIntrinsics(const std::array<double, kIntrinsicCount>& p,
                    body_scan_driver::PinholeCamera& c) {
  c.alpha = p[kAlpha], c.beta = p[kBeta], c.gamma = p[kGamma], c.u0 = p[kU0], c.v0 = p[kV0];
  c.k1 = p[kK1], c.k2 = p[kK2];
}

std::vector<Eigen::Vector2d> planeXY(const Checkerboard& board) {
  std::vector<Eigen::Vector2d> points;
  for (const Eigen::Vector3d& p : board.objectPoints()) points.push_back(p.head<2>());
  return points;
}

// Similarity that moves the centroid to 0 and the mean distance to sqrt(2) (Hartley).
Eigen::Matrix3d normalizingTransform(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  double mean_distance = 0;
  for (const Eigen::Vector2d& p : points) mean_distance += (p - centroid).norm();
  mean_distance /= static_cast<double>(points.size());
  const double scale = mean_distance > 0 ? std::sqrt(2.0) / mean_distance : 1.0;
  Eigen::Matrix3d t;
  t << scale, 0, -scale * centroid.x(), 0, scale, -scale * centroid.y(), 0, 0, 1;
  return t;
}

// Rotation closest to m in the Frobenius norm (Zhang, appendix C).
Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& m) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d r = svd.matrixU() * svd.matrixV().transpose();
  if (r.determinant() < 0) {
    Eigen::Matrix3d u = svd.matrixU();
    u.col(2) *= -1;
    r = u * svd.matrixV().transpose();
  }
  return r;
}

// Eqs 3.23-3.26: the board pose from its homography and A^-1. lambda uses both columns; the
// sign is chosen so the board lies in front of the camera.
Eigen::Isometry3d poseFromHomography(const Eigen::Matrix3d& a_inverse, const Eigen::Matrix3d& h) {
  const Eigen::Vector3d a1 = a_inverse * h.col(0), a2 = a_inverse * h.col(1);
  const Eigen::Vector3d a3 = a_inverse * h.col(2);
  double lambda = 2.0 / (a1.norm() + a2.norm());
  if (lambda * a3.z() < 0) lambda = -lambda;
  Eigen::Matrix3d r;
  r.col(0) = lambda * a1;               // eq 3.23
  r.col(1) = lambda * a2;               // eq 3.24
  r.col(2) = r.col(0).cross(r.col(1));  // eq 3.25
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = nearestRotation(r);
  pose.translation() = lambda * a3;  // eq 3.26
  return pose;
}

// Zhang's v_ij: h_i^T B h_j = v_ij^T b with b = (B11, B12, B22, B13, B23, B33).
Eigen::Matrix<double, 1, 6> zhangRow(const Eigen::Matrix3d& h, int i, int j) {
  const Eigen::Vector3d hi = h.col(i), hj = h.col(j);
  Eigen::Matrix<double, 1, 6> v;
  v << hi[0] * hj[0], hi[0] * hj[1] + hi[1] * hj[0], hi[1] * hj[1], hi[2] * hj[0] + hi[0] * hj[2],
      hi[2] * hj[1] + hi[1] * hj[2], hi[2] * hj[2];
  return v;
}

// Reprojection residual of one board corner (eqs 3.1-3.3): the refinement's cost.
struct ReprojectionError {
  ReprojectionError(const Eigen::Vector2d& observed, const Eigen::Vector3d& board_point)
      : observed_(observed), board_point_(board_point) {}

  template <typename T>
  bool operator()(const T* intrinsics, const T* rotation, const T* translation, T* residual) const {
    const T point[3] = {T(board_point_.x()), T(board_point_.y()), T(board_point_.z())};
    T camera_point[3];
    ceres::AngleAxisRotatePoint(rotation, point, camera_point);
    for (int i = 0; i < 3; ++i) camera_point[i] += translation[i];
    const T x = camera_point[0] / camera_point[2], y = camera_point[1] / camera_point[2];
    const T r2 = x * x + y * y;
    const T radial = T(1) + intrinsics[kK1] * r2 + intrinsics[kK2] * r2 * r2;  // eq 3.3
    const T xd = x * radial, yd = y * radial;
    residual[0] =
        intrinsics[kAlpha] * xd + intrinsics[kGamma] * yd + intrinsics[kU0] - T(observed_.x());
    residual[1] = intrinsics[kBeta] * yd + intrinsics[kV0] - T(observed_.y());
    return true;
  }

  static ceres::CostFunction* create(const Eigen::Vector2d& observed,
                                     const Eigen::Vector3d& board_point) {
    return new ceres::AutoDiffCostFunction<ReprojectionError, 2, kIntrinsicCount, 3, 3>(
        new ReprojectionError(observed, board_point));
  }

 private:
  Eigen::Vector2d observed_;
  Eigen::Vector3d board_point_;
};

struct PoseParameters {
  double rotation[3];  // angle-axis
  double translation[3];
};

PoseParameters toPoseParameters(const Eigen::Isometry3d& pose) {
  PoseParameters p;
  const Eigen::Matrix3d r = pose.linear();
  ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(r.data()), p.rotation);
  for (int i = 0; i < 3; ++i) p.translation[i] = pose.translation()[i];
  return p;
}

Eigen::Isometry3d fromPoseParameters(const PoseParameters& p) {
  Eigen::Matrix3d r;
  ceres::AngleAxisToRotationMatrix(p.rotation, ceres::ColumnMajorAdapter3x3(r.data()));
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = r;
  pose.translation() = Eigen::Vector3d(p.translation[0], p.translation[1], p.translation[2]);
  return pose;
}

struct RefinementSettings {
  bool refine_intrinsics = true;
  bool estimate_skew = false;
  int max_iterations = 200;
};

struct RefinementOutcome {
  int iterations = 0;
  Eigen::Matrix<double, 7, 1> std_devs = Eigen::Matrix<double, 7, 1>::Zero();
};

// Maximum-likelihood refinement (thesis sec. 3.3.1, last step): minimizes the summed squared
// reprojection error over all intrinsics and poses with Levenberg-Marquardt. With
// refine_intrinsics false only the poses move (PnP refinement). Standard deviations of the
// intrinsics come from (J^T J)^-1 s^2 at the optimum, s^2 = SSR / (observations - parameters).
RefinementOutcome refine(body_scan_driver::PinholeCamera& camera,
                         std::vector<Eigen::Isometry3d>& poses,
                         const std::vector<std::vector<Eigen::Vector2d>>& corners,
                         const std::vector<Eigen::Vector3d>& board_points,
                         const RefinementSettings& settings) {
  std::array<double, kIntrinsicCount> intrinsics = toIntrinsics(camera);
  if (!settings.estimate_skew && settings.refine_intrinsics) intrinsics[kGamma] = 0;
  std::vector<PoseParameters> pose_parameters;
  for (const Eigen::Isometry3d& pose : poses) pose_parameters.push_back(toPoseParameters(pose));

  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  std::vector<size_t> cost_view;
  for (size_t view = 0; view < corners.size(); ++view)
    for (size_t i = 0; i < board_points.size(); ++i) {
      costs.emplace_back(ReprojectionError::create(corners[view][i], board_points[i]));
      cost_view.push_back(view);
      problem.AddResidualBlock(costs.back().get(), nullptr, intrinsics.data(),
                               pose_parameters[view].rotation, pose_parameters[view].translation);
    }
  if (!settings.refine_intrinsics) {
    problem.SetParameterBlockConstant(intrinsics.data());
  } else if (!settings.estimate_skew) {
    problem.SetManifold(intrinsics.data(), new ceres::SubsetManifold(kIntrinsicCount, {kGamma}));
  }

  ceres::Solver::Options options;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = settings.max_iterations;
  options.function_tolerance = 1e-12;
  options.parameter_tolerance = 1e-12;
  options.gradient_tolerance = 1e-14;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable())
    throw CameraCalibrationError("camera calibration: the Levenberg-Marquardt refinement failed (" +
                                 summary.message + "); check that the corners are right");

  RefinementOutcome outcome;
  outcome.iterations = static_cast<int>(summary.iterations.size());
  fromIntrinsics(intrinsics, camera);
  for (size_t view = 0; view < poses.size(); ++view)
    poses[view] = fromPoseParameters(pose_parameters[view]);
  if (!settings.refine_intrinsics) return outcome;

  // Dense Jacobian of all residuals w.r.t. the free parameters (skew column dropped when fixed).
  const int views = static_cast<int>(poses.size());
  const int free_intrinsics = settings.estimate_skew ? kIntrinsicCount : kIntrinsicCount - 1;
  const int parameters = free_intrinsics + 6 * views;
  const int observations = static_cast<int>(2 * costs.size());
  if (observations <= parameters) return outcome;
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(observations, parameters);
  double squared_sum = 0;
  for (size_t k = 0; k < costs.size(); ++k) {
    const PoseParameters& pose = pose_parameters[cost_view[k]];
    const double* blocks[3] = {intrinsics.data(), pose.rotation, pose.translation};
    double residual[2];
    Eigen::Matrix<double, 2, kIntrinsicCount, Eigen::RowMajor> d_intrinsics;
    Eigen::Matrix<double, 2, 3, Eigen::RowMajor> d_rotation, d_translation;
    double* jacobians[3] = {d_intrinsics.data(), d_rotation.data(), d_translation.data()};
    costs[k]->Evaluate(blocks, residual, jacobians);
    squared_sum += residual[0] * residual[0] + residual[1] * residual[1];
    const int row = static_cast<int>(2 * k);
    for (int p = 0, column = 0; p < kIntrinsicCount; ++p) {
      if (p == kGamma && !settings.estimate_skew) continue;
      jacobian.block<2, 1>(row, column++) = d_intrinsics.col(p);
    }
    const int pose_column = free_intrinsics + 6 * static_cast<int>(cost_view[k]);
    jacobian.block<2, 3>(row, pose_column) = d_rotation;
    jacobian.block<2, 3>(row, pose_column + 3) = d_translation;
  }
  const double variance = squared_sum / (observations - parameters);
  const Eigen::MatrixXd information = jacobian.transpose() * jacobian;
  const Eigen::MatrixXd covariance =
      information.ldlt().solve(Eigen::MatrixXd::Identity(parameters, parameters)) * variance;
  for (int p = 0, column = 0; p < kIntrinsicCount; ++p) {
    if (p == kGamma && !settings.estimate_skew) continue;
    outcome.std_devs[p] = std::sqrt(std::max(0.0, covariance(column, column)));
    ++column;
  }
  return outcome;
}

double squaredReprojectionError(const body_scan_driver::PinholeCamera& camera,
                                const Eigen::Isometry3d& pose,
                                const std::vector<Eigen::Vector2d>& corners,
                                const std::vector<Eigen::Vector3d>& board_points) {
  double sum = 0;
  for (size_t i = 0; i < corners.size(); ++i)
    sum += (camera.project(pose * board_points[i]) - corners[i]).squaredNorm();
  return sum;
}

}  // namespace

std::vector<Eigen::Vector3d> Checkerboard::objectPoints() const {
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<size_t>(inner_cols) * inner_rows);
  for (int r = 0; r < inner_rows; ++r)
    for (int c = 0; c < inner_cols; ++c) points.emplace_back(c * square_size, r * square_size, 0);
  return points;
}

bool detectCheckerboardCorners(const cv::Mat& image, const Checkerboard& board,
                               std::vector<Eigen::Vector2d>& corners) {
  corners.clear();
  if (image.empty() || board.inner_cols < 2 || board.inner_rows < 2) return false;
  cv::Mat gray;
  if (image.channels() == 3)
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  else if (image.channels() == 4)
    cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  else
    gray = image;
  if (gray.depth() == CV_16U)
    gray.convertTo(gray, CV_8U, 1.0 / 256.0);
  else if (gray.depth() != CV_8U)
    gray.convertTo(gray, CV_8U);

  std::vector<cv::Point2f> found;
  const cv::Size pattern(board.inner_cols, board.inner_rows);
  if (!cv::findChessboardCorners(gray, pattern, found,
                                 cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
    return false;
  // The refinement window must stay inside the four squares around a corner: its half size is
  // below the smallest corner spacing (OpenCV's sample uses 11 for its ~30 px squares).
  double spacing = std::numeric_limits<double>::infinity();
  for (int r = 0; r < board.inner_rows; ++r)
    for (int c = 0; c < board.inner_cols; ++c) {
      const cv::Point2f& p = found[r * board.inner_cols + c];
      if (c + 1 < board.inner_cols)
        spacing = std::min(spacing, cv::norm(found[r * board.inner_cols + c + 1] - p));
      if (r + 1 < board.inner_rows)
        spacing = std::min(spacing, cv::norm(found[(r + 1) * board.inner_cols + c] - p));
    }
  const int half_window = std::clamp(static_cast<int>(0.5 * spacing), 2, 11);
  cv::cornerSubPix(gray, found, cv::Size(half_window, half_window), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-4));
  if (found.front().x + found.front().y > found.back().x + found.back().y)
    std::reverse(found.begin(), found.end());
  for (const cv::Point2f& p : found) corners.emplace_back(p.x, p.y);
  return true;
}

Eigen::Matrix3d estimateHomography(const std::vector<Eigen::Vector2d>& plane_points,
                                   const std::vector<Eigen::Vector2d>& image_points) {
  if (plane_points.size() != image_points.size() || plane_points.size() < 4)
    throw CameraCalibrationError("homography: needs >= 4 matching point pairs, got " +
                                 std::to_string(plane_points.size()) + " plane and " +
                                 std::to_string(image_points.size()) + " image points");
  const Eigen::Matrix3d t_plane = normalizingTransform(plane_points);
  const Eigen::Matrix3d t_image = normalizingTransform(image_points);
  const int n = static_cast<int>(plane_points.size());
  Eigen::MatrixXd system(2 * n, 9);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d x = t_plane * plane_points[i].homogeneous();
    const Eigen::Vector3d m = t_image * image_points[i].homogeneous();
    // m x (H x) = 0, two independent rows.
    system.row(2 * i) << x.transpose(), Eigen::RowVector3d::Zero(), -m.x() * x.transpose();
    system.row(2 * i + 1) << Eigen::RowVector3d::Zero(), x.transpose(), -m.y() * x.transpose();
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(system, Eigen::ComputeFullV);
  if (svd.singularValues()(7) < 1e-12 * svd.singularValues()(0))
    throw CameraCalibrationError(
        "homography: the points are degenerate (collinear or repeated); use a full board view");
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Eigen::Matrix3d normalized_h;
  normalized_h << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  Eigen::Matrix3d homography = t_image.inverse() * normalized_h * t_plane;
  return homography / homography(2, 2);
}

ClosedFormCalibration zhangClosedForm(const std::vector<Eigen::Matrix3d>& homographies,
                                      int image_width, int image_height, bool estimate_skew) {
  const int views = static_cast<int>(homographies.size());
  if (views < 3)
    throw CameraCalibrationError(
        "camera calibration needs >= 3 board views with different "
        "orientations (thesis sec. 3.3.1), got " +
        std::to_string(views));
  // Conditioning: solve for A' = N A with pixels mapped to about [-1, 1] by N, then undo it.
  // N A keeps the upper-triangular form of A, so eqs 3.17-3.22 apply to it unchanged.
  const double scale = 2.0 / (image_width + image_height);
  Eigen::Matrix3d n;
  n << scale, 0, -scale * 0.5 * (image_width - 1), 0, scale, -scale * 0.5 * (image_height - 1), 0,
      0, 1;
  // V b = 0: h1^T B h2 = 0 and h1^T B h1 = h2^T B h2 per view (from eqs 3.15-3.16).
  Eigen::MatrixXd v(2 * views, 6);
  for (int i = 0; i < views; ++i) {
    const Eigen::Matrix3d h = n * homographies[i];
    v.row(2 * i) = zhangRow(h, 0, 1);
    v.row(2 * i + 1) = zhangRow(h, 0, 0) - zhangRow(h, 1, 1);
  }
  // Zero skew <=> B12 = 0: drop that unknown.
  Eigen::MatrixXd system = v;
  if (!estimate_skew) {
    system.resize(2 * views, 5);
    system << v.col(0), v.rightCols(4);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(system, Eigen::ComputeFullV);
  const Eigen::VectorXd singular = svd.singularValues();
  const int unknowns = static_cast<int>(system.cols());
  // b is the null vector: a second (near-)null direction means the views do not constrain B.
  if (singular(unknowns - 2) < 1e-9 * singular(0))
    throw CameraCalibrationError(
        "camera calibration: the board views are degenerate (V b = 0 has no unique solution); "
        "tilt the board differently in each view - pure translations do not calibrate");
  const Eigen::VectorXd solution = svd.matrixV().col(unknowns - 1);
  Eigen::Matrix<double, 6, 1> b;
  if (estimate_skew)
    b = solution;
  else
    b << solution(0), 0, solution.tail(4);
  if (b(0) < 0) b = -b;  // B is a positive multiple of A^-T A^-1 (eq 3.16): B11 > 0
  const double b11 = b(0), b12 = b(1), b22 = b(2), b13 = b(3), b23 = b(4), b33 = b(5);
  const double determinant = b11 * b22 - b12 * b12;
  const double v0 = (b12 * b13 - b11 * b23) / determinant;                      // eq 3.18
  const double kappa = b33 - (b13 * b13 + v0 * (b12 * b13 - b11 * b23)) / b11;  // eq 3.22
  if (!(determinant > 0) || !(kappa / b11 > 0))
    throw CameraCalibrationError(
        "camera calibration: the board views are degenerate (B is not positive definite); "
        "tilt the board differently in each view - pure translations do not calibrate");
  const double alpha = std::sqrt(kappa / b11);               // eq 3.19
  const double beta = std::sqrt(kappa * b11 / determinant);  // eq 3.20
  const double gamma = -b12 * alpha * alpha * beta / kappa;  // eq 3.21
  // Eq 3.17; the thesis prints gamma v0 / alpha, but B13 = (gamma v0 - u0 beta)/(alpha^2 beta)
  // gives gamma v0 / beta (as in Zhang's report). Identical when gamma = 0.
  const double u0 = gamma * v0 / beta - b13 * alpha * alpha / kappa;
  Eigen::Matrix3d a_normalized;
  a_normalized << alpha, gamma, u0, 0, beta, v0, 0, 0, 1;
  const Eigen::Matrix3d a = n.inverse() * a_normalized;

  ClosedFormCalibration result;
  result.camera.width = image_width;
  result.camera.height = image_height;
  result.camera.alpha = a(0, 0), result.camera.gamma = a(0, 1), result.camera.u0 = a(0, 2);
  result.camera.beta = a(1, 1), result.camera.v0 = a(1, 2);
  result.camera.k1 = result.camera.k2 = 0;
  const Eigen::Matrix3d a_inverse = a.inverse();
  for (const Eigen::Matrix3d& h : homographies)
    result.board_to_camera.push_back(poseFromHomography(a_inverse, h));
  return result;
}

Eigen::Vector2d estimateRadialDistortion(
    const body_scan_driver::PinholeCamera& camera,
    const std::vector<Eigen::Isometry3d>& board_to_camera,
    const std::vector<std::vector<Eigen::Vector2d>>& image_corners_per_view,
    const Checkerboard& board) {
  const std::vector<Eigen::Vector3d> board_points = board.objectPoints();
  const size_t views = board_to_camera.size();
  Eigen::MatrixXd d(2 * views * board_points.size(), 2);
  Eigen::VectorXd residual(d.rows());
  Eigen::Index row = 0;
  for (size_t view = 0; view < views; ++view)
    for (size_t i = 0; i < board_points.size(); ++i) {
      const Eigen::Vector3d p = board_to_camera[view] * board_points[i];
      const Eigen::Vector2d x = p.head<2>() / p.z();
      const double r2 = x.squaredNorm();
      // Ideal (undistorted) pixel offset from the principal point; eq 3.3 scales it.
      const Eigen::Vector2d offset(camera.alpha * x.x() + camera.gamma * x.y(),
                                   camera.beta * x.y());
      const Eigen::Vector2d observed =
          image_corners_per_view[view][i] - Eigen::Vector2d(camera.u0, camera.v0);
      for (int axis = 0; axis < 2; ++axis, ++row) {
        d(row, 0) = offset[axis] * r2;
        d(row, 1) = offset[axis] * r2 * r2;
        residual(row) = observed[axis] - offset[axis];
      }
    }
  return d.colPivHouseholderQr().solve(residual);
}

CameraCalibrationResult calibrateCamera(
    const std::vector<std::vector<Eigen::Vector2d>>& image_corners_per_view,
    const Checkerboard& board, int image_width, int image_height,
    const CameraCalibrationOptions& options) {
  const size_t expected = static_cast<size_t>(board.inner_cols) * board.inner_rows;
  if (board.inner_cols < 2 || board.inner_rows < 2 || !(board.square_size > 0))
    throw CameraCalibrationError(
        "camera calibration: the board needs >= 2x2 inner corners and a "
        "positive square size");
  if (image_width <= 0 || image_height <= 0)
    throw CameraCalibrationError("camera calibration: image size must be positive, got " +
                                 std::to_string(image_width) + "x" + std::to_string(image_height));
  for (size_t view = 0; view < image_corners_per_view.size(); ++view)
    if (image_corners_per_view[view].size() != expected)
      throw CameraCalibrationError(
          "camera calibration: view " + std::to_string(view) + " has " +
          std::to_string(image_corners_per_view[view].size()) + " corners but the " +
          std::to_string(board.inner_cols) + "x" + std::to_string(board.inner_rows) +
          " board has " + std::to_string(expected) + "; pass --cols/--rows as inner corners");
  for (size_t view = 0; view < image_corners_per_view.size(); ++view)
    for (const Eigen::Vector2d& corner : image_corners_per_view[view])
      if (!corner.allFinite())
        throw CameraCalibrationError("camera calibration: view " + std::to_string(view) +
                                     " has a non-finite corner; pass only detected boards");

  const std::vector<Eigen::Vector2d> plane = planeXY(board);
  std::vector<Eigen::Matrix3d> homographies;
  for (const std::vector<Eigen::Vector2d>& corners : image_corners_per_view)
    homographies.push_back(estimateHomography(plane, corners));
  ClosedFormCalibration closed_form =
      zhangClosedForm(homographies, image_width, image_height, options.estimate_skew);
  const Eigen::Vector2d radial = estimateRadialDistortion(
      closed_form.camera, closed_form.board_to_camera, image_corners_per_view, board);
  closed_form.camera.k1 = radial.x();
  closed_form.camera.k2 = radial.y();

  CameraCalibrationResult result;
  result.camera = closed_form.camera;
  result.board_to_camera = closed_form.board_to_camera;
  const std::vector<Eigen::Vector3d> board_points = board.objectPoints();
  RefinementSettings settings;
  settings.estimate_skew = options.estimate_skew;
  settings.max_iterations = options.max_iterations;
  const RefinementOutcome outcome =
      refine(result.camera, result.board_to_camera, image_corners_per_view, board_points, settings);
  result.iterations = outcome.iterations;
  result.std_devs = outcome.std_devs;

  double total = 0;
  for (size_t view = 0; view < image_corners_per_view.size(); ++view) {
    const double squared = squaredReprojectionError(result.camera, result.board_to_camera[view],
                                                    image_corners_per_view[view], board_points);
    total += squared;
    result.per_view_rms_px.push_back(std::sqrt(squared / expected));
  }
  result.rms_px = std::sqrt(total / (expected * image_corners_per_view.size()));
  return result;
}

Eigen::Isometry3d estimateBoardPose(const body_scan_driver::PinholeCamera& camera,
                                    const std::vector<Eigen::Vector2d>& corners,
                                    const Checkerboard& board) {
  const size_t expected = static_cast<size_t>(board.inner_cols) * board.inner_rows;
  if (corners.size() != expected)
    throw CameraCalibrationError("board pose: got " + std::to_string(corners.size()) +
                                 " corners for a board of " + std::to_string(expected));
  // Initial pose from the homography of the board to undistorted normalized points (A = I).
  std::vector<Eigen::Vector2d> normalized;
  for (const Eigen::Vector2d& corner : corners)
    normalized.push_back(camera.normalizedPoint(corner));
  const Eigen::Matrix3d h = estimateHomography(planeXY(board), normalized);
  std::vector<Eigen::Isometry3d> poses{poseFromHomography(Eigen::Matrix3d::Identity(), h)};
  body_scan_driver::PinholeCamera fixed = camera;
  RefinementSettings settings;
  settings.refine_intrinsics = false;
  refine(fixed, poses, {corners}, board.objectPoints(), settings);
  return poses.front();
}

}  // namespace body_scan_calib
