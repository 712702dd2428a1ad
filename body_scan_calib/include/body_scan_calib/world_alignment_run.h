// One align_world run, shared by the folder tool (align_world) and the simulated one
// (align_simulated_rig): every pair's capture of the calibration cylinder in; each pair's
// calibration file with its world_alignment section, the E_h report (YAML) and plot (PNG) out.
#pragma once

#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/pair_model.h>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <vector>

namespace body_scan_calib {

// One pair's capture of the cylinder.
struct CylinderCapture {
  std::string pair_id;
  std::vector<cv::Mat> frames;  // PatternLayout order
  cv::Mat gray;                 // the texture, 8-bit grey
  body_scan_driver::PatternLayout layout{8, true};
  body_scan_driver::PairCalibration calibration;               // to align
  std::optional<Eigen::Isometry3d> true_cylinder_from_camera;  // known only to a simulator
};

// "pole_a/pair_1" -> "pole_a_pair_1": the stem of the pair's files.
std::string calibrationFileStem(const std::string& pair_id);

// folder/<stem>.yaml without its alignment (re-aligned from scratch); nullopt if `folder` is
// empty or holds no file for the pair.
std::optional<body_scan_driver::PairCalibration> calibrationToAlign(const std::string& folder,
                                                                    const std::string& pair_id);

// Writes folder/<stem>/: frame_NN.png, texture.png, capture.yaml (pair_id, bits,
// inverse_frames): what loadCylinderCaptures reads.
void saveCylinderCapture(const CylinderCapture& capture, const std::string& folder);

// Every pair folder of `images` (with a capture.yaml), sorted, each with its calibration from
// `calibration_in`. Throws std::runtime_error naming the missing folder, file or calibration.
std::vector<CylinderCapture> loadCylinderCaptures(const std::string& images,
                                                  const std::string& calibration_in);

struct WorldAlignmentFiles {
  std::string calibration_out;  // aligned <stem>.yaml per pair
  std::string report = "world_alignment_report.yaml";
  std::string plot;  // empty: the report's path with .png
};

// Aligns each capture (observeCylinder, fitWorldAffine), writes its aligned calibration, the
// report (its `mode` entry: `mode`) with E_h over the shared points, and the plot; prints a
// line per pair. A pair that fails is reported and skipped. Returns how many failed.
int alignWorld(const std::vector<CylinderCapture>& captures, const std::string& mode,
               const WorldAlignmentFiles& files);

}  // namespace body_scan_calib
