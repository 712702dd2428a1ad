// The offline layout of calibration captures, one folder per target:
//   FOLDER/pose_00/frame_00.png .. frame_NN.png   pattern frames of board pose 0 (PatternSet order)
//   FOLDER/pose_01/...                            ... at least 3 poses
//   FOLDER/spheres/frame_*.png                    optional: the five evaluation spheres
#pragma once

#include <body_scan_driver/gray_code.h>

#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace body_scan_calib {

std::string poseFolderName(int pose);  // "pose_00"

// Writes an 8-bit image as a PNG file atomically (body_scan_driver::writeFileAtomically), creating
// the folder. Throws std::runtime_error if the image cannot be encoded as PNG.
void writePngAtomically(const std::string& path, const cv::Mat& image);

// Writes frames as 8-bit PNG files (each atomically) into folder, creating it.
void savePatternFrames(const std::string& folder, const std::vector<cv::Mat>& frames);

// Reads the layout's frame count from folder. Throws std::runtime_error naming the missing or
// unreadable file and what the folder must hold.
std::vector<cv::Mat> loadPatternFrames(const std::string& folder,
                                       const body_scan_driver::PatternLayout& layout);

// Every pose_NN folder from pose_00 on, in order (stops at the first gap). Throws
// std::runtime_error if there is no pose_00.
std::vector<std::vector<cv::Mat>> loadPoseCaptures(const std::string& folder,
                                                   const body_scan_driver::PatternLayout& layout);

}  // namespace body_scan_calib
