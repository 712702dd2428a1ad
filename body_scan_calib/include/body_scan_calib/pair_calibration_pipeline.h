// Calibration of one projector-camera pair from reference-plane poses, end to end (thesis
// sec. 3.3): camera + board poses from the checker corners, projector planes (eq 3.30 + plane
// fits), the pinhole-projector baseline from the same data, and the sphere accuracy evaluation
// of both models (sec. 3.4.2) with its YAML report and the Fig 3.6 plot.
#pragma once

#include <body_scan_calib/camera_calibration.h>
#include <body_scan_calib/capture_decoding.h>
#include <body_scan_calib/pinhole_projector.h>
#include <body_scan_calib/projector_calibration.h>
#include <body_scan_calib/sphere_accuracy.h>
#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/pair_model.h>

#include <Eigen/Geometry>
#include <functional>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace body_scan_calib {

struct PairCalibrationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The pair's printed reference board: 9x6 inner corners, 50 mm squares (a 1 m scene needs the
// larger squares; its albedos and white margin are the rig's, calibration_rig.h).
inline Checkerboard referenceBoard() { return Checkerboard{9, 6, 0.05}; }

struct CameraAndBoardPoses {
  body_scan_driver::PinholeCamera camera;
  std::vector<Eigen::Isometry3d> board_to_camera;  // board frame at the first inner corner
  std::vector<std::vector<Eigen::Vector2d>> corners;
  double rms_px = 0;
  // Standard deviations of alpha, beta, gamma, u0, v0, k1, k2 (before any joint refinement).
  Eigen::Matrix<double, 7, 1> std_devs = Eigen::Matrix<double, 7, 1>::Zero();
};

// Camera intrinsics and the pose of the board in every image (8-bit grey images of the board
// under the projector's all-lit frame): detectCheckerboardCorners + calibrateCamera (Zhang and
// the maximum-likelihood refinement, camera_calibration.h). Throws PairCalibrationError naming
// the image whose corners were not found, or why the camera calibration failed.
CameraAndBoardPoses estimateCameraAndBoardPoses(const std::vector<cv::Mat>& board_images,
                                                const Checkerboard& board);

// Pixels of the board inside its inner corners plus half a square (the printed area that is
// surely board: the board's own border and background are excluded).
cv::Mat1b boardRegion(const body_scan_driver::PinholeCamera& camera,
                      const Eigen::Isometry3d& board_to_camera, const Checkerboard& board);

using Progress = std::function<void(const std::string&)>;

struct PairCalibrationOptions {
  Checkerboard board = referenceBoard();
  ProjectorCalibrationOptions projector;
  bool joint_refinement = true;  // Ceres: camera + board poses + planes together
  RobustDecoding decoding;       // capture_decoding.h (off: the driver's decoder as is)
  std::string pair_id = "pair";
};

struct PairCalibrationOutcome {
  CameraAndBoardPoses camera;
  ProjectorCalibrationResult planes;
  PinholeProjectorFit pinhole;
  body_scan_driver::PairCalibration calibration;  // the plane model (approach iii): what is saved
  body_scan_driver::PairCalibration
      pinhole_calibration;         // the baseline (approach i), planes p1 - s p2
  std::string refinement_summary;  // empty when not refined
};

// pose_frames: per reference-plane pose the pattern set's frames (CV_8UC1, PatternLayout order).
// pose_cross_frames: per pose the projector's other axis if recorded (capture_decoding.h), or
// empty.
PairCalibrationOutcome calibratePair(
    const std::vector<std::vector<cv::Mat>>& pose_frames,
    const body_scan_driver::PatternLayout& layout, const PairCalibrationOptions& options,
    const Progress& progress = {}, const std::vector<std::vector<cv::Mat>>& pose_cross_frames = {});

struct SphereAccuracy {
  int number;  // 1..5, top left to bottom right (Fig 3.7)
  IdealSphereFit plane_model, pinhole_model;
  double plane_center_error_m = std::numeric_limits<double>::quiet_NaN();  // vs truth, if known
  double pinhole_center_error_m = std::numeric_limits<double>::quiet_NaN();
};

struct AccuracyEvaluation {
  int exposures = 1;  // frames averaged per pattern
  double radius_m = 0.025;
  std::vector<SphereAccuracy> spheres;
  double meanPlaneEs() const;
  double meanPinholeEs() const;
  // (pinhole - plane) / pinhole of the mean E_s, percent
  double improvementPercent() const;
};

// Decodes the sphere capture, triangulates it with both models and fits the ideal spheres.
// nominal_centers place the spheres (to within capture_radius); true_centers (optional, the
// simulator's) add the centre error. Throws PairCalibrationError if a sphere has no points.
AccuracyEvaluation evaluateSphereAccuracy(const body_scan_driver::PairCalibration& plane_model,
                                          const body_scan_driver::PairCalibration& pinhole_model,
                                          const std::vector<cv::Mat>& frames,
                                          const body_scan_driver::PatternLayout& layout,
                                          const std::vector<Eigen::Vector3d>& nominal_centers,
                                          const std::vector<Eigen::Vector3d>& true_centers,
                                          double radius, int exposures);

// The YAML report: calibration summary (camera, planes, missing stripes, pinhole fit) and one
// accuracy table per capture protocol (Table 3.2 layout, E_s in mm^2), plus free-text notes.
std::string accuracyReportYaml(const PairCalibrationOutcome& outcome,
                               const std::vector<AccuracyEvaluation>& evaluations,
                               const std::vector<std::string>& notes);

}  // namespace body_scan_calib
