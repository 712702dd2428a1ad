// Decoding for real captures (an optional stage after StripeDecoder): dark printed albedo leaves
// a few grey levels of contrast, and blooming, interreflection and noise flip single bits. Every
// pixel with a little contrast is decoded (each bit against its inverse), codes that disagree
// with their neighbourhood are rejected instead of triangulated, the projector's other axis (if
// recorded) must decode as well, and each coordinate is re-estimated from a contrast-weighted
// local plane fit. The Triangulate nodelet (PatternSetCloud) and the offline calibration tools
// share it.
#pragma once

#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/stripe_decoder.h>

#include <cstddef>
#include <opencv2/core/mat.hpp>
#include <vector>

namespace body_scan_driver {

struct RobustDecoding {
  bool enabled = false;  // false: StripeDecoder as is (tuned on the simulator)
  // lit - dark below this (grey levels) is shadow; the inverse frames decide every bit above it.
  int min_contrast = 3;
  // The decoder's silhouette filter (DecoderParams::edge_contrast_ratio): a dark square's pixel
  // beside a white one has a small fraction of its neighbour's contrast and is still surface.
  double edge_contrast_ratio = 0.4;
  // A pixel's stripe coordinate may differ from the median of its 5x5 neighbourhood by at most
  // this many stripes (a linear ramp has its centre at the median): farther, it is no surface.
  double max_neighbour_deviation = 3.0;
  // ... and needs this many decoded pixels in that neighbourhood.
  int min_neighbours = 12;
  // Each pixel's coordinate becomes the value at the pixel of a plane s = a + b u + c v fitted
  // to the decoded pixels of a window around it, weighted by contrast squared (the inverse noise
  // variance of a bit decision): on a smooth surface the stripe coordinate is locally linear, so
  // noise and single wrong codes average out, and a dark pixel takes its coordinate mostly from
  // brighter neighbours. A fit farther than max_neighbour_deviation from the pixel's own code
  // (its inliers off to one side) leaves the pixel invalid. Half sizes in pixels along and
  // across the stripes; 0 and 0: no fit.
  int fit_radius_along = 8;
  int fit_radius_across = 6;
  // Pixels farther than this (stripes) from the fit are left out of the refit (fit_passes fits).
  double fit_outlier = 0.75;
  int fit_passes = 3;
  // Such an outlier takes the fit (a wrong code re-decided) if its 3x3 neighbourhood holds at
  // most max_isolated_outliers outliers (itself included), or if its contrast is below
  // redecide_contrast_share of its window's inliers' (rms): a dark pixel among bright ones.
  // Other outliers are another surface (a depth edge) and are left invalid rather than blended.
  int max_isolated_outliers = 3;
  double redecide_contrast_share = 0.5;

  // The StripeDecoder parameters of this decoding (base as is when not enabled).
  DecoderParams decoderParams(DecoderParams base = {}) const;
};

// StripeDecoder with robust.decoderParams(), then refineDecoding.
StripeImage decodePatternFrames(const std::vector<cv::Mat>& frames,
                                const std::vector<cv::Mat>& cross_frames,
                                const PatternLayout& layout, const RobustDecoding& robust);

// The stages after StripeDecoder (nothing unless robust.enabled): rejectSignalless,
// rejectInconsistentCodes, the cross check (cross_frames: the projector's other axis in
// PatternLayout order with inverse frames, or empty), fitLocalPlanes. frames: the set (in
// layout) that stripes was decoded from.
void refineDecoding(const std::vector<cv::Mat>& frames, const PatternLayout& layout,
                    const std::vector<cv::Mat>& cross_frames, StripeImage& stripes,
                    const RobustDecoding& robust);

// With inverse frames: rejects pixels where no bit's pattern and inverse differ by
// robust.min_contrast (lit by something, but not by the projector's patterns). Returns how many.
size_t rejectSignalless(const std::vector<cv::Mat>& frames, const PatternLayout& layout,
                        StripeImage& stripes, const RobustDecoding& robust);

// Rejects (NaN, kInvalidStripe) pixels whose coordinate deviates from their 5x5 neighbourhood's
// median by more than robust.max_neighbour_deviation or that have too few decoded neighbours.
// Returns how many were rejected.
size_t rejectInconsistentCodes(StripeImage& stripes, const RobustDecoding& robust);

// The local plane fit (RobustDecoding::fit_radius_along/across); the contrast is lit - dark of
// frames. Pixels whose window keeps no inlier, or whose fit is too far from their own code,
// become invalid; returns how many.
size_t fitLocalPlanes(StripeImage& stripes, const std::vector<cv::Mat>& frames,
                      const RobustDecoding& robust);

// Whether a decoded stripe coordinate changes more down the image (along rows) than across it:
// mean absolute change between neighbours (steps under 2 stripes), sampled every sample_step
// pixels. Rows for the pole's vertical baseline.
bool stripesChangeAlongRows(const cv::Mat1f& coordinate, int sample_step = 4);

}  // namespace body_scan_driver
