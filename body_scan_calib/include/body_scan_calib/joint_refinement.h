// Optional joint maximum-likelihood refinement of a pair calibration (after thesis sec. 3.3):
// camera intrinsics, board poses and stripe planes together, so that the checker corners and
// the stripe points (lifted by eq 3.30 with the current camera and pose) agree at once.
// Ceres stays in the .cpp (heavy header).
#pragma once

#include <body_scan_calib/projector_calibration.h>
#include <body_scan_driver/pair_model.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace body_scan_calib {

struct JointRefinementInput {
  body_scan_driver::PinholeCamera camera;
  std::vector<Eigen::Isometry3d> board_to_camera;
  std::vector<std::vector<Eigen::Vector2d>> corners;   // per pose, row-major like board_points
  std::vector<Eigen::Vector3d> board_points;           // corner positions on the board (z = 0)
  const ProjectorCalibrationResult* planes = nullptr;  // initial planes and their stripe points
  int max_stripe_points = 60000;  // a spread subsample keeps it fast; thousands per plane anyway
  // Cap the stripe points' total weight at the corners' (see refineJointly).
  bool balance_groups = false;
};

struct JointRefinementResult {
  body_scan_driver::PinholeCamera camera;
  std::vector<Eigen::Isometry3d> board_to_camera;
  double corner_rms_px_before = 0, corner_rms_px_after = 0;
  double plane_rms_m_before = 0, plane_rms_m_after = 0;
  int iterations = 0;
  std::string summary;  // one line for reports
};

// Residuals are weighted by the initial corner and plane-fit rms (maximum likelihood with those
// noise levels); with balance_groups the stripe points as a group weigh at most as much as the
// corners (they are many and correlated). A Huber loss limits checker-edge outliers. Skew stays
// fixed at its input.
JointRefinementResult refineJointly(const JointRefinementInput& input);

}  // namespace body_scan_calib
