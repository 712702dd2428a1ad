// Camera calibration from views of a planar checkerboard (thesis sec. 3.3.1, Zhang's method):
// corner detection, Zhang's closed form (eqs 3.14-3.26), linear radial distortion, then a
// maximum-likelihood refinement of every parameter and pose (Levenberg-Marquardt, Ceres).
// Ceres stays inside the .cpp files: this header is cheap to include.
#pragma once

#include <body_scan_driver/pair_model.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
#include <stdexcept>
#include <vector>

namespace body_scan_calib {

struct CameraCalibrationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A printed checkerboard counted by its INNER corners (where four squares meet).
struct Checkerboard {
  int inner_cols = 9, inner_rows = 6;
  double square_size = 0.025;  // metres
  // Corner (c, r) at (c, r, 0) * square_size, row-major: index r * inner_cols + c.
  std::vector<Eigen::Vector3d> objectPoints() const;
};

// Corners with subpixel refinement, row-major as objectPoints(); false if not found. The
// whole board with its white margin must be in view (OpenCV findChessboardCorners finds it).
// The 180-degree ambiguity of the board is resolved so the first corner is the one nearer
// the image's top-left.
bool detectCheckerboardCorners(const cv::Mat& gray, const Checkerboard& board,
                               std::vector<Eigen::Vector2d>& corners);

struct CameraCalibrationOptions {
  // Skew gamma (eq 3.1) is ~0 on every modern sensor and poorly separable from u0 with few
  // views; by default it is held at 0 (as OpenCV does) and its standard deviation reported 0.
  bool estimate_skew = false;
  int max_iterations = 200;
};

struct CameraCalibrationResult {
  body_scan_driver::PinholeCamera camera;          // fx=alpha, fy=beta, gamma, u0, v0, k1, k2
  std::vector<Eigen::Isometry3d> board_to_camera;  // one per view
  double rms_px = 0;                               // sqrt(mean squared reprojection error)
  std::vector<double> per_view_rms_px;
  // Standard deviations of alpha, beta, gamma, u0, v0, k1, k2 from (J^T J)^-1 s^2.
  Eigen::Matrix<double, 7, 1> std_devs = Eigen::Matrix<double, 7, 1>::Zero();
  int iterations = 0;  // Levenberg-Marquardt iterations of the refinement
};

// Throws CameraCalibrationError (fewer than 3 views, wrong corner counts, degenerate views).
CameraCalibrationResult calibrateCamera(
    const std::vector<std::vector<Eigen::Vector2d>>& image_corners_per_view,
    const Checkerboard& board, int image_width, int image_height,
    const CameraCalibrationOptions& options = {});

// Pose of a board of known camera (PnP, refined): used per reference-plane pose.
Eigen::Isometry3d estimateBoardPose(const body_scan_driver::PinholeCamera& camera,
                                    const std::vector<Eigen::Vector2d>& corners,
                                    const Checkerboard& board);

// ---- The stages, exposed for tests and for tools that want the closed form alone. ----

// Plane-to-image homography by the normalized DLT (Hartley normalization of both point sets),
// eq 3.14: image ~ H [x_p, y_p, 1]^T. Needs >= 4 points in general position.
Eigen::Matrix3d estimateHomography(const std::vector<Eigen::Vector2d>& plane_points,
                                   const std::vector<Eigen::Vector2d>& image_points);

// Zhang's closed form: intrinsics from V b = 0 (eqs 3.16-3.22), then each view's pose
// (eqs 3.23-3.26, rotation projected onto SO(3)). No distortion (k1 = k2 = 0).
struct ClosedFormCalibration {
  body_scan_driver::PinholeCamera camera;
  std::vector<Eigen::Isometry3d> board_to_camera;
};
ClosedFormCalibration zhangClosedForm(const std::vector<Eigen::Matrix3d>& homographies,
                                      int image_width, int image_height, bool estimate_skew);

// Radial k1, k2 by linear least squares (Zhang sec. 3.3) given the ideal projections.
Eigen::Vector2d estimateRadialDistortion(
    const body_scan_driver::PinholeCamera& camera,
    const std::vector<Eigen::Isometry3d>& board_to_camera,
    const std::vector<std::vector<Eigen::Vector2d>>& image_corners_per_view,
    const Checkerboard& board);

}  // namespace body_scan_calib
