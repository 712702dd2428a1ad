// Camera calibration files: the camera part uses the keys of camera_calibration_parsers
// (image_width, camera_matrix, distortion_model plumb_bob, ...) exactly as the driver's pair
// calibration files do, so ROS tools read it; a `calibration_report` section adds what the
// estimate is worth (reprojection RMS overall and per view, parameter standard deviations).
#pragma once

#include <body_scan_calib/camera_calibration.h>

#include <string>
#include <vector>

namespace body_scan_calib {

struct CameraCalibrationReport {
  std::string camera_name;
  Checkerboard board;
  std::vector<std::string> view_names;  // one per view (e.g. image file names); may be empty
  CameraCalibrationResult result;
};

// The YAML text of a report (what saveCameraCalibration writes).
std::string cameraCalibrationYaml(const CameraCalibrationReport& report);

// Writes atomically (body_scan_driver::writeFileAtomically): readers never see a partial file.
// Throws CameraCalibrationError naming the file and the fix.
void saveCameraCalibration(const std::string& path, const CameraCalibrationReport& report);

// Reads the camera part of a camera calibration file or of a pair calibration file.
// Throws CameraCalibrationError naming the file, the problem and the fix.
body_scan_driver::PinholeCamera loadCameraCalibration(const std::string& path);

}  // namespace body_scan_calib
