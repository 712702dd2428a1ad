// Decoding of one recorded pattern set (capture_layout.h) into the stripe coordinate, and the
// point cloud files of the offline scan (scan_folder): the same decoding for calibration,
// validation and scanning.
#pragma once

#include <body_scan_calib/capture_layout.h>
#include <body_scan_driver/pair_model.h>
#include <body_scan_driver/robust_decoding.h>
#include <body_scan_driver/stripe_decoder.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace body_scan_calib {

// The robust decoding for real captures lives with the driver's decoder (robust_decoding.h).
using body_scan_driver::decodePatternFrames;
using body_scan_driver::RobustDecoding;

// decodePatternFrames of one loaded set with `bits` stripe bits.
body_scan_driver::StripeImage decodeCapturedSet(const CapturedPatternSet& set, int bits,
                                                const RobustDecoding& robust = {});

// Triangulated points (camera optical frame, metres) of a decoded stripe image.
std::vector<Eigen::Vector3f> triangulateStripes(
    const body_scan_driver::PairCalibration& calibration, const cv::Mat1f& coordinate);

// Writes points as binary PLY (.ply) or PCD (.pcd) by the extension, atomically. Throws
// std::invalid_argument for another extension.
void writePointCloud(const std::string& path, const std::vector<Eigen::Vector3f>& points);

}  // namespace body_scan_calib
