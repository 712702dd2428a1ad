// One calibrate_pair run, shared by the folder tool (calibrate_pair) and the simulated one
// (calibrate_simulated_pair): a pair's views in; the calibration file, the accuracy report (YAML)
// and the Fig 3.6 plot (PNG) out, all written atomically.
#pragma once

#include <body_scan_calib/calibration_rig.h>
#include <body_scan_calib/capture_layout.h>
#include <body_scan_calib/pair_calibration_pipeline.h>
#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/pair_model.h>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <vector>

namespace body_scan_calib {

// What one pair saw of the rig's targets (calibration_rig.h).
struct PairViews {
  body_scan_driver::PatternLayout layout{8, true};
  std::vector<std::vector<cv::Mat>> pose_frames;  // per board pose, PatternLayout order
  // Per board pose, the projector's other axis (PatternLayout order; empty if not recorded).
  std::vector<std::vector<cv::Mat>> pose_cross_frames;
  std::vector<cv::Mat> sphere_frames;         // empty: accuracy not evaluated
  std::vector<cv::Mat> sphere_single_frames;  // optional: one exposure, a second table
  int exposures = 16;                         // frames averaged per pattern
  double sphere_radius_m = 0.025;
  std::vector<Eigen::Vector3d> nominal_centers = rig::defaultSphereCenters();
  std::vector<Eigen::Vector3d> true_centers;               // known only to a simulator
  std::optional<body_scan_driver::PairCalibration> truth;  // known only to a simulator
};

// A capture folder (capture_folder.h layout: pose_NN/, optional spheres/) taken with `bits` Gray
// code bits and inverse frames, `exposures` averaged per pattern. Throws std::runtime_error
// naming what the folder lacks.
PairViews loadPairViews(const std::string& folder, int bits, int exposures);
// The same for any capture layout (capture_layout.h); spheres/ is read in the project layout.
PairViews loadPairViews(const std::string& folder, const CaptureLayout& layout,
                        const CaptureBits& bits, int exposures);

struct PairCalibrationFiles {
  std::string calibration = "calibration/pair.yaml";
  std::string report = "calibration/pair_accuracy.yaml";
  std::string plot = "calibration/projector_parameters.png";
};

// calibratePair on the views, then the sphere evaluation of both models (with the decoding
// floor when the truth is known); writes `files` and prints the progress and the E_s tables.
PairCalibrationOutcome calibratePairToFiles(const PairViews& views,
                                            const PairCalibrationOptions& options,
                                            const PairCalibrationFiles& files);

}  // namespace body_scan_calib
