// Leave-one-pose-out validation of a pair calibration on real captures: calibrate without board
// pose k, triangulate pose k's board pixels, and compare them with the board plane from its
// corners (PnP with the calibrated camera). The peer in the same run is the pinhole-projector
// calibration users of other tools make with OpenCV: the projector as an inverse camera from the
// decoded column + row codes at the corners (local homographies), cv::stereoCalibrate, and the
// same decoded column image triangulated against its column surfaces.
#pragma once

#include <body_scan_calib/pair_calibration_run.h>

#include <string>
#include <vector>

namespace body_scan_calib {

// Board pixels of one held-out pose (or all of them pooled) triangulated by one model.
struct PlaneErrorStatistics {
  size_t board_pixels = 0, points = 0;
  double coverage = 0;  // points / board_pixels
  double median_mm = 0, rms_mm = 0, p95_mm = 0;
  double gross_share = 0;  // points farther than gross_mm from the board plane
};

struct ModelValidation {
  std::string model;
  std::vector<PlaneErrorStatistics> per_pose;
  PlaneErrorStatistics pooled;
  std::vector<std::string> failures;  // poses the model could not be calibrated without
};

struct PairValidation {
  double gross_mm = 20;
  ModelValidation ours, peer;
  int stripes_on_board = 0, stripes_calibrated = 0;  // the all-pose calibration
};

struct ValidationOptions {
  double gross_mm = 20;
  bool with_peer = true;  // needs the row frames (views.pose_cross_frames)
};

// Throws PairCalibrationError with fewer than 4 poses (3 must remain to calibrate).
PairValidation validateLeaveOnePoseOut(const PairViews& views,
                                       const PairCalibrationOptions& options,
                                       const ValidationOptions& validation = {},
                                       const Progress& progress = {});

// Distances (metres) of points to a plane, summarized against the board's pixel count.
PlaneErrorStatistics planeErrorStatistics(const std::vector<double>& distances_m,
                                          size_t board_pixels, double gross_mm);

std::string validationYaml(const PairValidation& validation);

}  // namespace body_scan_calib
