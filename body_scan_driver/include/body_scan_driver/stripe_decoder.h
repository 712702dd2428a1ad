// Decodes a captured pattern set into the projector's stripe coordinate at every camera pixel
// (thesis sec. 4.2.1): shadow mask from the lit/dark frames, one decision per bit against the
// inverse frame (or the lit/dark midpoint), Gray -> binary, then a subpixel coordinate from the
// stripe boundaries located where a bit's signal changes sign between two pixels.
#pragma once

#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/simd.h>

#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <vector>

namespace body_scan_driver {

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
  // kReference: the plain scalar formulation below, kept as the specification and the test
  // oracle. kFast: the same computation as three vectorized row passes (integer pass,
  // boundary flags, subpixel work only at flagged pixels); bit-identical output (stripe id,
  // coordinate, mask), asserted by test_stripe_decoder for every SIMD level.
  enum class Implementation { kReference, kFast };
  Implementation implementation = Implementation::kFast;
  // Highest instruction set kFast may use; it falls back to what the CPU supports.
  SimdLevel max_simd = SimdLevel::kAvx512;
};

struct StripeImage {
  cv::Mat1w stripe;      // integer stripe id, kInvalidStripe where not decoded
  cv::Mat1f coordinate;  // stripe i spans [i, i+1); NaN where not decoded
};

// Not safe to call decode() on one decoder from two threads at once (it keeps scratch
// buffers between calls so that a stream of pattern sets allocates nothing).
class StripeDecoder {
 public:
  StripeDecoder(const PatternLayout& layout, const DecoderParams& params = {});

  // frames: CV_8UC1 images of one size in PatternLayout order (no copy is made). Reuses the
  // buffers of out. Throws std::invalid_argument naming the problem on a bad frame set.
  void decode(const std::vector<cv::Mat>& frames, StripeImage& out) const;

  const PatternLayout& layout() const { return layout_; }
  const DecoderParams& params() const { return params_; }

 private:
  struct FrameRows;  // per-bit frame pointers of one pattern set
  void decodeIntegers(const std::vector<cv::Mat>& frames, const FrameRows& rows,
                      StripeImage& out) const;
  template <bool kAlongRows>
  void interpolateBoundaries(const FrameRows& rows, StripeImage& out) const;
  bool stripesChangeAlongRows(const StripeImage& out) const;
  void countBrightNeighbours() const;
  uint16_t breakTies(const FrameRows& rows, uint16_t code, size_t index, int u, int v, int cols,
                     int rows_count) const;
  // kFast (stripe_decoder_fast.cpp).
  void decodeFast(const std::vector<cv::Mat>& frames, const FrameRows& rows,
                  StripeImage& out) const;
  template <bool kAlongRows>
  void interpolateBoundariesFast(const FrameRows& rows, StripeImage& out, SimdLevel level) const;
  // Boundary walk state of one line (a column when stripes change along rows).
  struct LineWalk {
    int segment_start = 0;  // first pixel of the current run of one stripe id
    float previous_position = 0, previous_coordinate = 0;
    bool previous_valid = false;
    float stripe_width = 0;  // pixels between the last two boundaries, 0 = unknown
  };

  PatternLayout layout_;
  DecoderParams params_;
  int edge_ratio_q8_;                 // edge_contrast_ratio in 1/256 units
  std::vector<uint8_t> bit_between_;  // stripe k -> the bit that flips between k and k+1
  mutable cv::Mat contrast_, neighbourhood_max_, bright_, horizontal_sum_, bright_around_;
  mutable std::vector<uint8_t> fast_rows_;      // kFast: rolling contrast and 3x3 rows
  mutable std::vector<uint32_t> tied_pixels_;   // kFast: valid pixels with a tied bit
  mutable std::vector<uint64_t> changed_bits_;  // kFast: boundary flags of one row
  mutable std::vector<LineWalk> line_walks_;    // kFast: one per line
  mutable std::vector<float> walk_floats_;      // kFast: the same as arrays (lines = columns)
  mutable std::vector<int32_t> walk_ints_;
  mutable std::vector<int16_t> flip_signals_;  // kFast: per pixel, see IntegerPass
};

// Throws std::invalid_argument unless frames match the layout (count, type, equal sizes).
void checkFrames(const PatternLayout& layout, const std::vector<cv::Mat>& frames);

}  // namespace body_scan_driver
