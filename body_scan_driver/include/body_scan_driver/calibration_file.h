// Pair calibration files (YAML). The camera part uses the keys of camera_calibration_parsers
// (image_width, camera_matrix, distortion_model plumb_bob, ...) so standard ROS tools read it;
// the projector part lists one plane per stripe in the camera optical frame (metres).
#pragma once

#include <body_scan_driver/pair_model.h>

#include <stdexcept>
#include <string>

namespace body_scan_driver {

struct CalibrationFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws CalibrationFileError naming the file, the problem and the fix.
PairCalibration loadCalibration(const std::string& path);
// The camera part alone, shared with camera-only calibration files (body_scan_calib): read
// from a camera or pair calibration file (throws CalibrationFileError), or as YAML text with
// the camera_calibration_parsers keys.
PinholeCamera loadCameraPart(const std::string& path);
std::string cameraPartYaml(const std::string& camera_name, const PinholeCamera& camera);
// Writes to a temporary file in the same folder and renames it: readers never see a partial
// file. Creates missing parent folders.
void saveCalibration(const std::string& path, const PairCalibration& calibration);

}  // namespace body_scan_driver
