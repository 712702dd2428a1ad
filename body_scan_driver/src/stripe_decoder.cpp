#include <body_scan_driver/stripe_decoder.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "stripe_decoder_internal.h"

namespace body_scan_driver {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A stripe boundary on one image line: position (pixels along the line) and the stripe
// coordinate there (the larger of the two stripe ids it separates).
struct Boundary {
  float position = 0;
  float coordinate = 0;
  bool valid = false;
};

// Walk state of one image line (a column when stripes change along rows).
struct LineState {
  int segment_start = 0;  // first pixel of the current run of one stripe id
  Boundary previous;
  float stripe_width = 0;  // pixels between the last two boundaries, 0 = unknown
};

}  // namespace

void checkFrames(const PatternLayout& layout, const std::vector<cv::Mat>& frames) {
  if (static_cast<int>(frames.size()) != layout.frameCount())
    throw std::invalid_argument("pattern set has " + std::to_string(frames.size()) +
                                " frames but " + std::to_string(layout.bits()) + " bits" +
                                (layout.inverseFrames() ? " with" : " without") +
                                " inverse frames need " + std::to_string(layout.frameCount()));
  for (size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].type() != CV_8UC1)
      throw std::invalid_argument("frame " + std::to_string(i) +
                                  " is not 8-bit single channel (mono8); convert it first");
    if (frames[i].size() != frames[0].size() || frames[i].step != frames[0].step)
      throw std::invalid_argument(
          "frame " + std::to_string(i) + " is " + std::to_string(frames[i].cols) + "x" +
          std::to_string(frames[i].rows) + " but frame 0 is " + std::to_string(frames[0].cols) +
          "x" + std::to_string(frames[0].rows) + " (all frames must have one size and row step)");
  }
}

StripeDecoder::StripeDecoder(const PatternLayout& layout, const DecoderParams& params)
    : layout_(layout),
      params_(params),
      edge_ratio_q8_(
          static_cast<int>(std::lround(256 * std::clamp(params.edge_contrast_ratio, 0.0, 1.0)))),
      bit_between_(layout.stripeCount()) {
  for (uint32_t stripe = 0; stripe + 1 < bit_between_.size(); ++stripe)
    bit_between_[stripe] = static_cast<uint8_t>(layout.bitBetween(stripe));
}

void StripeDecoder::decode(const std::vector<cv::Mat>& frames, StripeImage& out) const {
  checkFrames(layout_, frames);
  out.stripe.create(frames[0].size());
  out.coordinate.create(frames[0].size());
  FrameRows rows;
  rows.lit = frames[PatternLayout::litFrame()].data;
  rows.dark = frames[PatternLayout::darkFrame()].data;
  rows.step = frames[0].step;
  for (int bit = 0; bit < layout_.bits(); ++bit) {
    rows.pattern.push_back(frames[layout_.patternFrame(bit)].data);
    if (layout_.inverseFrames()) rows.inverse.push_back(frames[layout_.inverseFrame(bit)].data);
  }
  if (params_.implementation == DecoderParams::Implementation::kFast) {
    decodeFast(frames, rows, out);
    return;
  }
  decodeIntegers(frames, rows, out);
  if (!params_.subpixel) return;
  const bool along_rows = params_.axis == DecoderParams::StripeAxis::kAuto
                              ? stripesChangeAlongRows(out)
                              : params_.axis == DecoderParams::StripeAxis::kAlongRows;
  if (along_rows) {
    interpolateBoundaries<true>(rows, out);
  } else {
    interpolateBoundaries<false>(rows, out);
  }
}

bool StripeDecoder::stripesChangeAlongRows(const StripeImage& out) const {
  // The stripe id changes more often along the direction the stripes are stacked in.
  long vertical_changes = 0, horizontal_changes = 0;
  for (int v = 0; v + 1 < out.stripe.rows; v += 8) {
    const uint16_t* row = out.stripe.ptr<uint16_t>(v);
    const uint16_t* below = out.stripe.ptr<uint16_t>(v + 1);
    for (int u = 0; u + 1 < out.stripe.cols; ++u) {
      vertical_changes += row[u] != below[u];
      horizontal_changes += row[u] != row[u + 1];
    }
  }
  return vertical_changes >= horizontal_changes;
}

void StripeDecoder::decodeIntegers(const std::vector<cv::Mat>& frames, const FrameRows& frame_rows,
                                   StripeImage& out) const {
  const int cols = frames[0].cols, rows = frames[0].rows;
  const int min_contrast = params_.min_contrast;
  const bool inverse = layout_.inverseFrames();
  // Lit - dark contrast, its 3x3 maximum (silhouette filter) and the number of bright pixels in
  // each 3x3 window (lone-pixel filter), in reused buffers.
  cv::subtract(frames[PatternLayout::litFrame()], frames[PatternLayout::darkFrame()], contrast_);
  if (edge_ratio_q8_ > 0) cv::dilate(contrast_, neighbourhood_max_, cv::Mat());
  cv::threshold(contrast_, bright_, min_contrast - 1, 1, cv::THRESH_BINARY);
  countBrightNeighbours();
  const int min_bright_window = params_.min_bright_neighbours + 1;
  const int ratio = edge_ratio_q8_;

  std::vector<uint8_t> tied(cols), valid(cols);  // tied: some bit's pattern equals its inverse
  for (int v = 0; v < rows; ++v) {
    const size_t row = static_cast<size_t>(v) * frame_rows.step;
    const uint8_t* lit = frame_rows.lit + row;
    const uint8_t* dark = frame_rows.dark + row;
    uint16_t* __restrict code = out.stripe.ptr<uint16_t>(v);
    float* __restrict coordinate = out.coordinate.ptr<float>(v);
    std::fill(code, code + cols, 0);
    std::fill(tied.begin(), tied.end(), 0);
    // One pass per bit over a whole row keeps the inner loops branch-free (vectorized).
    for (int bit = 0; bit < layout_.bits(); ++bit) {
      const uint8_t* pattern = frame_rows.pattern[bit] + row;
      if (inverse) {
        const uint8_t* inverted = frame_rows.inverse[bit] + row;
        for (int u = 0; u < cols; ++u) {
          code[u] = static_cast<uint16_t>((code[u] << 1) | (pattern[u] > inverted[u]));
          tied[u] |= pattern[u] == inverted[u];
        }
      } else {
        for (int u = 0; u < cols; ++u) {
          code[u] = static_cast<uint16_t>((code[u] << 1) | (2 * pattern[u] > lit[u] + dark[u]));
          tied[u] |= 2 * pattern[u] == lit[u] + dark[u];
        }
      }
    }
    const uint8_t* contrast = contrast_.ptr<uint8_t>(v);
    const uint8_t* support = bright_around_.ptr<uint8_t>(v);
    const uint8_t* local_max = ratio > 0 ? neighbourhood_max_.ptr<uint8_t>(v) : contrast;
    // 256 * contrast and ratio * maximum (ratio <= 256) fit 16 bits: 8 pixels per SSE vector.
    const uint16_t ratio16 = static_cast<uint16_t>(ratio);
    for (int u = 0; u < cols; ++u)
      valid[u] = (contrast[u] >= min_contrast) & (support[u] >= min_bright_window) &
                 (static_cast<uint16_t>(contrast[u] << 8) >=
                  static_cast<uint16_t>(ratio16 * local_max[u]));
    uint8_t any_tie = 0;
    for (int u = 0; u < cols; ++u) any_tie |= tied[u] & valid[u];
    if (any_tie)
      for (int u = 0; u < cols; ++u)
        if (tied[u] & valid[u]) code[u] = breakTies(frame_rows, code[u], row + u, u, v, cols, rows);
    for (int u = 0; u < cols; ++u) code[u] = valid[u] ? grayDecode(code[u]) : kInvalidStripe;
    // Stripe centres until the subpixel pass refines them.
    for (int u = 0; u < cols; ++u) {
      const float centre = static_cast<float>(static_cast<int32_t>(code[u])) + 0.5f;
      coordinate[u] = code[u] == kInvalidStripe ? kNaN : centre;
    }
  }
}

void StripeDecoder::countBrightNeighbours() const {
  // Separable 3x3 sum of the 0/1 image bright_ (outside the image counts as dark).
  const int cols = bright_.cols, rows = bright_.rows;
  horizontal_sum_.create(bright_.size(), CV_8U);
  bright_around_.create(bright_.size(), CV_8U);
  for (int v = 0; v < rows; ++v) {
    const uint8_t* in = bright_.ptr<uint8_t>(v);
    uint8_t* out = horizontal_sum_.ptr<uint8_t>(v);
    out[0] = static_cast<uint8_t>(in[0] + (cols > 1 ? in[1] : 0));
    for (int u = 1; u + 1 < cols; ++u) out[u] = static_cast<uint8_t>(in[u - 1] + in[u] + in[u + 1]);
    if (cols > 1) out[cols - 1] = static_cast<uint8_t>(in[cols - 2] + in[cols - 1]);
  }
  for (int v = 0; v < rows; ++v) {
    const uint8_t* middle = horizontal_sum_.ptr<uint8_t>(v);
    const uint8_t* above = v > 0 ? horizontal_sum_.ptr<uint8_t>(v - 1) : nullptr;
    const uint8_t* below = v + 1 < rows ? horizontal_sum_.ptr<uint8_t>(v + 1) : nullptr;
    uint8_t* out = bright_around_.ptr<uint8_t>(v);
    if (above && below) {
      for (int u = 0; u < cols; ++u) out[u] = static_cast<uint8_t>(above[u] + middle[u] + below[u]);
    } else {
      for (int u = 0; u < cols; ++u)
        out[u] = static_cast<uint8_t>(middle[u] + (above ? above[u] : 0) + (below ? below[u] : 0));
    }
  }
}

uint16_t StripeDecoder::breakTies(const FrameRows& rows, uint16_t code, size_t index, int u, int v,
                                  int cols, int rows_count) const {
  // A pixel whose bit signal is exactly 0 sits on that bit's edge (within 8-bit quantization).
  // The neighbour on the pixel's own side is a little farther from the edge, so its signal is
  // larger: the sign of the neighbours' sum tells the side.
  const int bits = layout_.bits();
  for (int bit = 0; bit < bits; ++bit) {
    const uint16_t mask = static_cast<uint16_t>(1u << (bits - 1 - bit));
    if (rows.signal(bit, index) != 0) continue;
    int signal = 0;
    if (u > 0) signal += rows.signal(bit, index - 1);
    if (u + 1 < cols) signal += rows.signal(bit, index + 1);
    if (v > 0) signal += rows.signal(bit, index - rows.step);
    if (v + 1 < rows_count) signal += rows.signal(bit, index + rows.step);
    code = signal > 0 ? (code | mask) : (code & ~mask);
  }
  return code;
}

template <bool kAlongRows>
void StripeDecoder::interpolateBoundaries(const FrameRows& frame_rows, StripeImage& out) const {
  // Lines run along the direction in which the stripe id changes; "position" is the index
  // along a line. For kAlongRows a line is an image column, walked row by row for every column
  // at once so that memory is read in order.
  const int lines = kAlongRows ? out.stripe.cols : out.stripe.rows;
  const int length = kAlongRows ? out.stripe.rows : out.stripe.cols;
  const size_t stripe_step = out.stripe.step1(), coordinate_step = out.coordinate.step1();
  const size_t frame_step = frame_rows.step;
  auto at = [](size_t step, int line, int position) -> size_t {
    return kAlongRows ? static_cast<size_t>(position) * step + line
                      : static_cast<size_t>(line) * step + position;
  };
  const uint16_t* stripes = out.stripe.ptr<uint16_t>();
  float* coordinates = out.coordinate.ptr<float>();
  const float max_width = static_cast<float>(params_.max_stripe_width_px);

  // Rewrites the run [segment_start, end] of one stripe id between two boundaries.
  auto flush = [&](LineState& state, int line, int end, const Boundary& next) {
    const Boundary& previous = state.previous;
    const float stripe = stripes[at(stripe_step, line, end)];
    if (previous.valid && next.valid && std::abs(next.coordinate - previous.coordinate) == 1.f &&
        next.position - previous.position <= max_width) {
      const float slope =
          (next.coordinate - previous.coordinate) / (next.position - previous.position);
      for (int position = state.segment_start; position <= end; ++position)
        coordinates[at(coordinate_step, line, position)] =
            previous.coordinate + (position - previous.position) * slope;
    } else if (state.stripe_width > 0 && (previous.valid || next.valid)) {
      // One boundary known: extrapolate with the width of the neighbouring stripe.
      const Boundary& known = previous.valid ? previous : next;
      const float slope = (known.coordinate == stripe ? 1.f : -1.f) / state.stripe_width;
      for (int position = state.segment_start; position <= end; ++position)
        coordinates[at(coordinate_step, line, position)] = std::clamp(
            known.coordinate + std::abs(position - known.position) * slope, stripe, stripe + 1.f);
    }  // else: the stripe centres written by the integer pass stay.
  };

  std::vector<LineState> states(lines);
  auto step = [&](int line, int position) {
    const uint16_t current = stripes[at(stripe_step, line, position)];
    const uint16_t last = stripes[at(stripe_step, line, position - 1)];
    if (current == last) return;
    LineState& state = states[line];
    Boundary boundary;
    if (last != kInvalidStripe && current != kInvalidStripe && std::abs(current - last) == 1) {
      const int bit = bit_between_[std::min(current, last)];
      const float a = frame_rows.signal(bit, at(frame_step, line, position - 1));
      const float b = frame_rows.signal(bit, at(frame_step, line, position));
      const float t = a == b ? 0.5f : std::clamp(a / (a - b), 0.f, 1.f);
      boundary = {position - 1 + t, static_cast<float>(std::max(current, last)), true};
    }
    if (last != kInvalidStripe) flush(state, line, position - 1, boundary);
    if (boundary.valid && state.previous.valid &&
        std::abs(boundary.coordinate - state.previous.coordinate) == 1.f)
      state.stripe_width = boundary.position - state.previous.position;
    state.previous = boundary;
    state.segment_start = position;
  };
  if (kAlongRows) {
    for (int position = 1; position < length; ++position)
      for (int line = 0; line < lines; ++line) step(line, position);
  } else {
    for (int line = 0; line < lines; ++line)
      for (int position = 1; position < length; ++position) step(line, position);
  }
  for (int line = 0; line < lines; ++line)
    if (stripes[at(stripe_step, line, length - 1)] != kInvalidStripe)
      flush(states[line], line, length - 1, Boundary{});
}

}  // namespace body_scan_driver
