// Decoding of one recorded pattern set (capture_layout.h) into the stripe coordinate, and the
// point cloud files of the offline scan (scan_folder): the same decoding for calibration,
// validation and scanning.
#pragma once

#include <body_scan_calib/capture_layout.h>
#include <body_scan_driver/pair_model.h>
#include <body_scan_driver/stripe_decoder.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace body_scan_calib {

// Decoding of real captures, where dark printed albedo leaves a few grey levels of contrast and
// blooming, interreflection and noise flip single bits: every pixel with a little contrast is
// decoded (each bit against its inverse), then codes that disagree with their neighbourhood are
// rejected instead of triangulated, and where the projector's other axis was recorded its code
// must be consistent too. kStandard is the driver's StripeDecoder as is (tuned on the simulator).
struct RobustDecoding {
  bool enabled = false;
  // lit - dark below this (grey levels) is shadow; the inverse frames decide every bit above it.
  int min_contrast = 3;
  // The driver decoder's silhouette filter (DecoderParams::edge_contrast_ratio): a dark square's
  // pixel beside a white one has a small fraction of its neighbour's contrast and is still board.
  double edge_contrast_ratio = 0.4;
  // A pixel's stripe coordinate may differ from the median of its 5x5 neighbourhood by at most
  // this many stripes (a linear ramp has its centre at the median).
  double max_neighbour_deviation = 1.0;
  // ... and needs this many decoded pixels in that neighbourhood.
  int min_neighbours = 12;
  // The coordinate is replaced by the median over this many pixels either side along the
  // stripe (where it barely changes): single-pixel code errors and noise average out. 0: off.
  int along_stripe_radius = 8;
};

// Decodes a pattern set (PatternLayout order, inverse frames); cross_frames (the projector's
// other axis, PatternLayout order, or empty) check the decoding when robust.enabled.
body_scan_driver::StripeImage decodePatternFrames(const std::vector<cv::Mat>& frames,
                                                  const std::vector<cv::Mat>& cross_frames,
                                                  const body_scan_driver::PatternLayout& layout,
                                                  const RobustDecoding& robust = {});
// decodePatternFrames of one loaded set with `bits` stripe bits.
body_scan_driver::StripeImage decodeCapturedSet(const CapturedPatternSet& set, int bits,
                                                const RobustDecoding& robust = {});

// Rejects (NaN, kInvalidStripe) pixels whose coordinate deviates from their 5x5 neighbourhood's
// median by more than robust.max_neighbour_deviation or that have too few decoded neighbours.
// Returns how many were rejected.
size_t rejectInconsistentCodes(body_scan_driver::StripeImage& stripes,
                               const RobustDecoding& robust);

// Triangulated points (camera optical frame, metres) of a decoded stripe image.
std::vector<Eigen::Vector3f> triangulateStripes(
    const body_scan_driver::PairCalibration& calibration, const cv::Mat1f& coordinate);

// Writes points as binary PLY (.ply) or PCD (.pcd) by the extension, atomically. Throws
// std::invalid_argument for another extension.
void writePointCloud(const std::string& path, const std::vector<Eigen::Vector3f>& points);

}  // namespace body_scan_calib
