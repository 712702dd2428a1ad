// Calibration captures recorded in a bag: body_scan_msgs/PatternSet messages
// of one pair, converted to the image folder calibrate_pair reads (calibration_capture.h).
// The ROS layer of the workflow (rosbag C++ API); the calibration itself stays ROS-agnostic.
#pragma once

#include <body_scan_msgs/PatternSet.h>

#include <functional>
#include <opencv2/core/mat.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace body_scan_calib {

struct CalibrationBagError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The pattern frames of a set as 8-bit grey images (copies). Throws CalibrationBagError naming
// the scan and the field checkPatternSet (body_scan_driver/ros/message_checks.h) rejects.
std::vector<cv::Mat> patternFrames(const body_scan_msgs::PatternSet& set);

struct BagConversionOptions {
  std::string topic;          // empty: every body_scan_msgs/PatternSet topic of the bag
  std::string pair_id;        // empty: the bag must hold exactly one pair
  bool spheres_last = false;  // the last placement is the evaluation spheres
};

struct BagConversionResult {
  size_t pattern_sets = 0;
  std::vector<std::string> folders;  // written, in order (pose_00, ..., spheres)
  int bits = 0;                      // of the pattern sets (calibrate_pair --bits)
};

// Reads the pattern sets in recording order; each run of consecutive scan ids is one target
// placement whose sets are averaged per pattern (repeated exposures of a static target) and
// written to FOLDER/pose_NN (or FOLDER/spheres). Throws CalibrationBagError naming the
// problem and the fix (no pattern sets, several pairs, inconsistent sets).
BagConversionResult bagToCalibrationFolder(
    const std::string& bag_path, const std::string& folder, const BagConversionOptions& options,
    const std::function<void(const std::string&)>& progress = {});

}  // namespace body_scan_calib
