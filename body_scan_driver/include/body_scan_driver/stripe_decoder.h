// Decodes a captured pattern set into the projector's stripe coordinate at every camera pixel
// (thesis sec. 4.2.1): shadow mask from the lit/dark frames, one decision per bit against the
// inverse frame (or the lit/dark midpoint), Gray -> binary, then a subpixel coordinate from the
// stripe boundaries located where a bit's signal changes sign between two pixels.
#pragma once

#include <body_scan_driver/gray_code.h>

#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <vector>

namespace body_scan {

constexpr uint16_t kInvalidStripe = 0xFFFF;

struct DecoderParams {
  // Pixels whose lit - dark difference is below this (grey levels of 255) are shadow or too
  // dark to decode and are marked invalid.
  int min_contrast = 10;
  // Silhouette filter: blur spreads a surface's light onto the pixels around it, which would
  // decode its stripes at the wrong depth. A pixel whose contrast is below this fraction of the
  // largest contrast in its 3x3 neighbourhood mostly carries a neighbour's light: invalid.
  // 0 disables the filter.
  double edge_contrast_ratio = 0.5;
  // A pixel needs this many of its 8 neighbours above min_contrast: lone bright pixels are
  // sensor noise, not surfaces.
  int min_bright_neighbours = 2;
  // Interpolate a continuous coordinate between stripe boundaries; false gives stripe centres.
  bool subpixel = true;
  // Image direction along which the stripe id changes: kAuto decides from the decoded image
  // (rows for the pole's vertical baseline: stripes are horizontal bands).
  enum class StripeAxis { kAuto, kAlongRows, kAlongColumns };
  StripeAxis axis = StripeAxis::kAuto;
  // A stripe wider than this (pixels) between two boundaries is not interpolated.
  int max_stripe_width_px = 40;
};

struct StripeImage {
  cv::Mat1w stripe;      // integer stripe id, kInvalidStripe where not decoded
  cv::Mat1f coordinate;  // stripe i spans [i, i+1); NaN where not decoded
};

class StripeDecoder {
 public:
  StripeDecoder(const PatternLayout& layout, const DecoderParams& params = {});

  // frames: CV_8UC1 images of one size in PatternLayout order (no copy is made). Reuses the
  // buffers of out. Throws std::invalid_argument naming the problem on a bad frame set.
  void decode(const std::vector<cv::Mat>& frames, StripeImage& out) const;

  const PatternLayout& layout() const { return layout_; }
  const DecoderParams& params() const { return params_; }

 private:
  void decodeIntegers(const std::vector<cv::Mat>& frames, StripeImage& out) const;
  void interpolateBoundaries(const std::vector<cv::Mat>& frames, bool along_rows,
                             StripeImage& out) const;
  void writeCentres(StripeImage& out) const;
  // Signed signal of one bit at a pixel, zero on the bit's edge: pattern - inverse, or
  // 2 pattern - (lit + dark) without inverse frames.
  float bitSignal(const std::vector<cv::Mat>& frames, int bit, int u, int v) const;
  uint16_t breakTies(const std::vector<cv::Mat>& frames, int u, int v) const;

  PatternLayout layout_;
  DecoderParams params_;
  int edge_ratio_q8_;  // edge_contrast_ratio in 1/256 units, for integer arithmetic
  std::vector<uint16_t> gray_to_stripe_;
};

// Throws std::invalid_argument unless frames match the layout (count, type, equal sizes).
void checkFrames(const PatternLayout& layout, const std::vector<cv::Mat>& frames);

}  // namespace body_scan
