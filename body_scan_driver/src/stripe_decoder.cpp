#include <body_scan_driver/stripe_decoder.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

namespace body_scan {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A stripe boundary on one image line: position (pixels, along the line) and the stripe
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
    if (frames[i].size() != frames[0].size())
      throw std::invalid_argument("frame " + std::to_string(i) + " is " +
                                  std::to_string(frames[i].cols) + "x" +
                                  std::to_string(frames[i].rows) + " but frame 0 is " +
                                  std::to_string(frames[0].cols) + "x" +
                                  std::to_string(frames[0].rows));
  }
}

StripeDecoder::StripeDecoder(const PatternLayout& layout, const DecoderParams& params)
    : layout_(layout),
      params_(params),
      edge_ratio_q8_(static_cast<int>(std::lround(256 * params.edge_contrast_ratio))),
      gray_to_stripe_(layout.stripeCount()) {
  for (uint32_t gray = 0; gray < gray_to_stripe_.size(); ++gray)
    gray_to_stripe_[gray] = static_cast<uint16_t>(grayDecode(gray));
}

void StripeDecoder::decode(const std::vector<cv::Mat>& frames, StripeImage& out) const {
  checkFrames(layout_, frames);
  out.stripe.create(frames[0].size());
  out.coordinate.create(frames[0].size());
  decodeIntegers(frames, out);
  if (!params_.subpixel) return writeCentres(out);

  bool along_rows = params_.axis == DecoderParams::StripeAxis::kAlongRows;
  if (params_.axis == DecoderParams::StripeAxis::kAuto) {
    // The stripe id changes more often along the direction the stripes are stacked in.
    long vertical_changes = 0, horizontal_changes = 0;
    for (int v = 0; v + 1 < out.stripe.rows; v += 4) {
      const uint16_t* row = out.stripe.ptr<uint16_t>(v);
      const uint16_t* below = out.stripe.ptr<uint16_t>(v + 1);
      for (int u = 0; u + 1 < out.stripe.cols; ++u) {
        vertical_changes += row[u] != below[u];
        horizontal_changes += row[u] != row[u + 1];
      }
    }
    along_rows = vertical_changes >= horizontal_changes;
  }
  interpolateBoundaries(frames, along_rows, out);
}

void StripeDecoder::decodeIntegers(const std::vector<cv::Mat>& frames, StripeImage& out) const {
  const int cols = frames[0].cols;
  const int min_contrast = params_.min_contrast;
  const bool inverse = layout_.inverseFrames();
  // Largest lit - dark contrast around each pixel, for the silhouette filter.
  cv::Mat contrast, neighbourhood_max, bright, bright_around;
  cv::subtract(frames[PatternLayout::litFrame()], frames[PatternLayout::darkFrame()], contrast);
  if (edge_ratio_q8_ > 0) cv::dilate(contrast, neighbourhood_max, cv::Mat());
  // Count bright pixels in each 3x3 window (the pixel itself included).
  cv::threshold(contrast, bright, min_contrast - 1, 1, cv::THRESH_BINARY);
  cv::boxFilter(bright, bright_around, CV_8U, cv::Size(3, 3), cv::Point(-1, -1), false,
                cv::BORDER_CONSTANT);
  const int min_bright_window = params_.min_bright_neighbours + 1;
  std::vector<uint8_t> tied(cols);
  for (int v = 0; v < frames[0].rows; ++v) {
    const uint8_t* lit = frames[PatternLayout::litFrame()].ptr<uint8_t>(v);
    const uint8_t* dark = frames[PatternLayout::darkFrame()].ptr<uint8_t>(v);
    uint16_t* code = out.stripe.ptr<uint16_t>(v);
    std::fill(code, code + cols, 0);
    std::fill(tied.begin(), tied.end(), 0);
    // One pass per bit over a whole row keeps the inner loops branch-free (vectorized).
    for (int bit = 0; bit < layout_.bits(); ++bit) {
      const uint8_t* pattern = frames[layout_.patternFrame(bit)].ptr<uint8_t>(v);
      if (inverse) {
        const uint8_t* inverted = frames[layout_.inverseFrame(bit)].ptr<uint8_t>(v);
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
    const uint8_t* local = contrast.ptr<uint8_t>(v);
    const uint8_t* support = bright_around.ptr<uint8_t>(v);
    const uint8_t* local_max = edge_ratio_q8_ > 0 ? neighbourhood_max.ptr<uint8_t>(v) : local;
    const int ratio = edge_ratio_q8_;
    for (int u = 0; u < cols; ++u) {
      const bool bright = local[u] >= min_contrast && support[u] >= min_bright_window &&
                          256 * local[u] >= ratio * local_max[u];
      if (bright && tied[u]) code[u] = breakTies(frames, u, v);
      code[u] = bright ? gray_to_stripe_[code[u]] : kInvalidStripe;
    }
  }
}

float StripeDecoder::bitSignal(const std::vector<cv::Mat>& frames, int bit, int u, int v) const {
  const int p = frames[layout_.patternFrame(bit)].at<uint8_t>(v, u);
  if (layout_.inverseFrames())
    return static_cast<float>(p - frames[layout_.inverseFrame(bit)].at<uint8_t>(v, u));
  return static_cast<float>(2 * p - frames[PatternLayout::litFrame()].at<uint8_t>(v, u) -
                            frames[PatternLayout::darkFrame()].at<uint8_t>(v, u));
}

uint16_t StripeDecoder::breakTies(const std::vector<cv::Mat>& frames, int u, int v) const {
  // A pixel whose bit signal is exactly 0 sits on that bit's edge (within 8-bit quantization).
  // The neighbour on the pixel's own side is a little farther from the edge, so its signal is
  // larger: the sign of the neighbours' sum tells the side.
  const int cols = frames[0].cols, rows = frames[0].rows;
  uint16_t code = 0;
  for (int bit = 0; bit < layout_.bits(); ++bit) {
    float signal = bitSignal(frames, bit, u, v);
    if (signal == 0) {
      if (u > 0) signal += bitSignal(frames, bit, u - 1, v);
      if (u + 1 < cols) signal += bitSignal(frames, bit, u + 1, v);
      if (v > 0) signal += bitSignal(frames, bit, u, v - 1);
      if (v + 1 < rows) signal += bitSignal(frames, bit, u, v + 1);
    }
    code = static_cast<uint16_t>((code << 1) | (signal > 0));
  }
  return code;
}

void StripeDecoder::writeCentres(StripeImage& out) const {
  for (int v = 0; v < out.stripe.rows; ++v) {
    const uint16_t* stripe = out.stripe.ptr<uint16_t>(v);
    float* coordinate = out.coordinate.ptr<float>(v);
    for (int u = 0; u < out.stripe.cols; ++u)
      coordinate[u] = stripe[u] == kInvalidStripe ? kNaN : stripe[u] + 0.5f;
  }
}

void StripeDecoder::interpolateBoundaries(const std::vector<cv::Mat>& frames, bool along_rows,
                                          StripeImage& out) const {
  // Lines run along the direction in which the stripe id changes; "position" is the index
  // along a line. Pixel (line, position) maps to image (u, v) by the axis.
  const int lines = along_rows ? out.stripe.cols : out.stripe.rows;
  const int length = along_rows ? out.stripe.rows : out.stripe.cols;
  auto at = [along_rows](const cv::Mat& image, int line, int position) -> size_t {
    return along_rows ? static_cast<size_t>(position) * image.step1() + line
                      : static_cast<size_t>(line) * image.step1() + position;
  };
  const uint16_t* stripes = out.stripe.ptr<uint16_t>();
  float* coordinates = out.coordinate.ptr<float>();
  const float max_width = static_cast<float>(params_.max_stripe_width_px);


  // Writes the coordinates of the run [state.segment_start, end] of stripe id `stripe`.
  auto flush = [&](LineState& state, int line, int end, const Boundary& next) {
    const Boundary& previous = state.previous;
    for (int position = state.segment_start; position <= end; ++position) {
      const size_t index = at(out.coordinate, line, position);
      const float stripe = stripes[index];
      float value = stripe + 0.5f;
      if (previous.valid && next.valid && std::abs(next.coordinate - previous.coordinate) == 1.f &&
          next.position - previous.position <= max_width) {
        value = previous.coordinate + (position - previous.position) *
                                          (next.coordinate - previous.coordinate) /
                                          (next.position - previous.position);
      } else if (state.stripe_width > 0 && (previous.valid || next.valid)) {
        // One boundary known: extrapolate with the width of the neighbouring stripe.
        const Boundary& known = previous.valid ? previous : next;
        const float direction = known.coordinate == stripe ? 1.f : -1.f;
        value = std::clamp(
            known.coordinate + direction * std::abs(position - known.position) / state.stripe_width,
            stripe, stripe + 1.f);
      }
      coordinates[index] = value;
    }
  };

  std::vector<LineState> states(lines);
  for (int line = 0; line < lines; ++line)
    if (stripes[at(out.stripe, line, 0)] == kInvalidStripe) coordinates[at(out.coordinate, line, 0)] = kNaN;
  // Row-major walk: for along_rows each step advances every column by one row.
  auto step = [&](int line, int position) {
    LineState& state = states[line];
    const size_t here = at(out.stripe, line, position);
    const size_t before = at(out.stripe, line, position - 1);
    const uint16_t current = stripes[here], last = stripes[before];
    if (current == last) {
      if (current == kInvalidStripe) coordinates[here] = kNaN;
      return;
    }
    Boundary boundary;
    if (last != kInvalidStripe && current != kInvalidStripe && std::abs(current - last) == 1) {
      const int bit = layout_.bitBetween(std::min(current, last));
      const int u = along_rows ? line : position, v = along_rows ? position : line;
      const float a = along_rows ? bitSignal(frames, bit, u, v - 1) : bitSignal(frames, bit, u - 1, v);
      const float b = bitSignal(frames, bit, u, v);
      const float t = a == b ? 0.5f : std::clamp(a / (a - b), 0.f, 1.f);
      boundary = {position - 1 + t, static_cast<float>(std::max(current, last)), true};
    }
    if (last != kInvalidStripe) flush(state, line, position - 1, boundary);
    if (boundary.valid && state.previous.valid &&
        std::abs(boundary.coordinate - state.previous.coordinate) == 1.f)
      state.stripe_width = boundary.position - state.previous.position;
    state.previous = boundary;
    state.segment_start = position;
    if (current == kInvalidStripe) {
      coordinates[here] = kNaN;
      state.previous.valid = false;
    }
  };
  if (along_rows) {
    for (int position = 1; position < length; ++position)
      for (int line = 0; line < lines; ++line) step(line, position);
  } else {
    for (int line = 0; line < lines; ++line)
      for (int position = 1; position < length; ++position) step(line, position);
  }
  for (int line = 0; line < lines; ++line) {
    LineState& state = states[line];
    if (stripes[at(out.stripe, line, length - 1)] != kInvalidStripe)
      flush(state, line, length - 1, Boundary{});
  }
}

}  // namespace body_scan
