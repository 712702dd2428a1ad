// DecoderParams::Implementation::kFast: the reference decoder's computation (stripe_decoder.cpp)
// rearranged into three row passes, with bit-identical output (docs/ARCHITECTURE.md, "Decoder
// speed"):
//   1. integer pass: contrast, the 3x3 silhouette and lone-pixel filters from rolling row
//      buffers (no whole-image temporaries), per-bit decisions, Gray -> binary, stripe centres;
//      every loop is branch-free over a row, so it vectorizes. With AVX-512 it also keeps the
//      signals of the bit that flips between each pixel and the one above (for pass 3);
//   2. boundary flags: one bit per pixel "stripe id differs from the previous pixel along the
//      line", from vector compares (16-bit lanes -> bit masks);
//   3. subpixel pass: lines along image rows walk only the flagged pixels (count trailing
//      zeros); lines along image columns walk all columns of a row at once (AVX-512,
//      stripe_decoder_walk_row.inc) or, below AVX-512, with the reference walk.
// The vector loops are compiled for the x86-64 baseline (SSE2), AVX2 and AVX-512 and chosen at
// run time (simd.h). Every float operation is the reference's, in the same order, and the
// library builds with -ffp-contract=off (no fused multiply-add), so every level gives the same
// bits as the reference.
#include <body_scan_driver/stripe_decoder.h>
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "stripe_decoder_internal.h"

#define BODY_SCAN_ALWAYS_INLINE inline __attribute__((always_inline))
#define BODY_SCAN_TARGET_AVX2 __attribute__((target("avx2")))
#define BODY_SCAN_TARGET_AVX512 __attribute__((target("avx512f,avx512bw,avx512vl,avx512dq")))

namespace body_scan_driver {
namespace {

constexpr uint32_t kNaNBits = 0x7FC00000u;  // the reference's quiet_NaN()
constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Inputs and outputs of the integer pass over one pattern set.
struct IntegerPass {
  const uint8_t* lit;
  const uint8_t* dark;
  const uint8_t* const* pattern;
  const uint8_t* const* inverse;  // nullptr without inverse frames
  size_t frame_step;
  int cols, rows, bits;
  uint8_t min_contrast;     // contrast >= this is bright ...
  uint8_t contrast_usable;  // ... and 0 when min_contrast > 255 (nothing is)
  uint8_t min_bright_window;
  uint16_t ratio_q8;  // edge_contrast_ratio in 1/256
  uint16_t* stripe;
  size_t stripe_step;  // elements
  float* coordinate;
  size_t coordinate_step;  // elements
  uint8_t* scratch;        // scratchBytes(cols)
  // For the walk along image columns, per pixel (row-major, cols apart) of rows >= 1: the
  // signals above and at the pixel of the one bit whose raw code differs from the pixel above
  // (meaningful where the two stripe ids differ by one). nullptr: not wanted.
  int16_t* flip_before;
  int16_t* flip_here;
  std::vector<uint32_t>* tied;
};

size_t paddedWidth(int cols) { return (static_cast<size_t>(cols) + 2 + 63) & ~size_t{63}; }
// 3 ring rows of horizontal max and bright count, 3 padded contrast rows, one padded bright
// row, two 16-bit code rows (this one and the one above), tie and valid flags, two rows of
// 16-bit signals per bit, the 16-bit code difference to the row above.
size_t scratchBytes(int cols) {
  return paddedWidth(cols) * (3 + 3 + 3 + 1 + 2 * 2 + 1 + 1 + 2 * 2 * kMaxBits + 2);
}

// Horizontal 3-pixel max of the contrast and count of bright pixels of row r (outside the image
// counts as 0: OpenCV's dilate border and the reference's zero padding); zero rows outside.
BODY_SCAN_ALWAYS_INLINE void prepareRow(const IntegerPass& pass, int r, uint8_t* __restrict hmax,
                                        uint8_t* __restrict hsum, uint8_t* __restrict contrast,
                                        uint8_t* __restrict bright) {
  const int cols = pass.cols;
  if (r < 0 || r >= pass.rows) {
    std::memset(hmax, 0, cols);
    std::memset(hsum, 0, cols);
    return;
  }
  const uint8_t* __restrict lit = pass.lit + static_cast<size_t>(r) * pass.frame_step;
  const uint8_t* __restrict dark = pass.dark + static_cast<size_t>(r) * pass.frame_step;
  const uint8_t min_contrast = pass.min_contrast, usable = pass.contrast_usable;
  contrast[0] = contrast[cols + 1] = 0;
  bright[0] = bright[cols + 1] = 0;
  for (int u = 0; u < cols; ++u) {
    const uint8_t c = lit[u] > dark[u] ? static_cast<uint8_t>(lit[u] - dark[u]) : 0;  // saturated
    contrast[u + 1] = c;
    bright[u + 1] = static_cast<uint8_t>((c >= min_contrast) & usable);
  }
  for (int u = 0; u < cols; ++u) {
    hmax[u] = std::max(std::max(contrast[u], contrast[u + 1]), contrast[u + 2]);
    hsum[u] = static_cast<uint8_t>(bright[u] + bright[u + 1] + bright[u + 2]);
  }
}

// Per pixel, the signals (row above, this row) of the bit set in flipped_bits. Where exactly one
// bit is set (the only pixels the walk reads: stripe ids one apart) OR-ing the masked signals of
// all bits selects it. The bit count is a constant so that the bit loop unrolls and the pixel
// loop vectorizes.
template <int kBits>
BODY_SCAN_ALWAYS_INLINE void selectFlippedSignals(int cols, size_t width,
                                                  const int16_t* __restrict flipped_bits,
                                                  const int16_t* __restrict signals,
                                                  const int16_t* __restrict signals_above,
                                                  int16_t* __restrict before,
                                                  int16_t* __restrict here) {
  constexpr int bits = kBits;
  for (int u = 0; u < cols; ++u) {
    int16_t signal_above = 0, signal = 0;
#pragma GCC unroll 10
    for (int bit = 0; bit < bits; ++bit) {
      const int16_t bit_mask = static_cast<int16_t>(1 << (bits - 1 - bit));
      const int16_t selected = static_cast<int16_t>(-((flipped_bits[u] & bit_mask) != 0));
      signal_above =
          static_cast<int16_t>(signal_above | (signals_above[bit * width + u] & selected));
      signal = static_cast<int16_t>(signal | (signals[bit * width + u] & selected));
    }
    before[u] = signal_above;
    here[u] = signal;
  }
}

template <typename Code>
BODY_SCAN_ALWAYS_INLINE void integerPassCoded(const IntegerPass& pass) {
  const int cols = pass.cols, rows = pass.rows;
  const size_t width = paddedWidth(cols);
  uint8_t* hmax[3] = {pass.scratch, pass.scratch + width, pass.scratch + 2 * width};
  uint8_t* hsum[3] = {hmax[2] + width, hmax[2] + 2 * width, hmax[2] + 3 * width};
  uint8_t* contrast[3] = {hsum[2] + width, hsum[2] + 2 * width, hsum[2] + 3 * width};
  uint8_t* bright = contrast[2] + width;
  Code* code_rows[2] = {reinterpret_cast<Code*>(bright + width),
                        reinterpret_cast<Code*>(bright + 3 * width)};
  uint8_t* __restrict tied = bright + 5 * width;
  uint8_t* __restrict valid = tied + width;
  int16_t* signal_rows[2] = {reinterpret_cast<int16_t*>(valid + width),
                             reinterpret_cast<int16_t*>(valid + width) + kMaxBits * width};
  int16_t* __restrict flipped_bits = signal_rows[1] + kMaxBits * width;
  const uint8_t min_contrast = pass.min_contrast, usable = pass.contrast_usable;
  const uint8_t min_window = pass.min_bright_window;
  const uint16_t ratio = pass.ratio_q8;

  prepareRow(pass, -1, hmax[2], hsum[2], contrast[2], bright);  // ring slot of row -1
  prepareRow(pass, 0, hmax[0], hsum[0], contrast[0], bright);
  for (int v = 0; v < rows; ++v) {
    const int above = (v + 2) % 3, middle = v % 3, below = (v + 1) % 3;
    prepareRow(pass, v + 1, hmax[below], hsum[below], contrast[below], bright);
    const uint8_t* __restrict c = contrast[middle] + 1;
    const uint8_t* __restrict max_a = hmax[above], * __restrict max_m = hmax[middle], * __restrict max_b = hmax[below];
    const uint8_t* __restrict sum_a = hsum[above], * __restrict sum_m = hsum[middle], * __restrict sum_b = hsum[below];
    // Shadow mask, silhouette filter and lone-pixel filter (see decodeIntegers).
    for (int u = 0; u < cols; ++u) {
      const uint8_t local_max = std::max(std::max(max_a[u], max_m[u]), max_b[u]);
      const uint8_t support = static_cast<uint8_t>(sum_a[u] + sum_m[u] + sum_b[u]);
      valid[u] = static_cast<uint8_t>(
          (c[u] >= min_contrast) & usable & (support >= min_window) &
          (static_cast<uint16_t>(c[u] << 8) >= static_cast<uint16_t>(ratio * local_max)));
    }
    const size_t row = static_cast<size_t>(v) * pass.frame_step;
    if (v + 2 < rows) {  // the next rows of all frames: 18 streams are too many for the prefetcher
      const size_t ahead = row + 2 * pass.frame_step;
      for (int bit = 0; bit < pass.bits; ++bit)
        for (int u = 0; u < cols; u += 64) {
          __builtin_prefetch(pass.pattern[bit] + ahead + u);
          if (pass.inverse) __builtin_prefetch(pass.inverse[bit] + ahead + u);
        }
    }
    Code* __restrict code = code_rows[v & 1];
    const Code* __restrict code_above = code_rows[(v + 1) & 1];
    for (int u = 0; u < cols; ++u) {
      code[u] = 0;
      tied[u] = 0;
    }
    for (int bit = 0; bit < pass.bits; ++bit) {
      const uint8_t* __restrict pattern = pass.pattern[bit] + row;
      if (pass.inverse) {
        const uint8_t* __restrict inverted = pass.inverse[bit] + row;
        for (int u = 0; u < cols; ++u) {
          code[u] = static_cast<Code>((code[u] << 1) | (pattern[u] > inverted[u]));
          tied[u] |= pattern[u] == inverted[u];
        }
      } else {
        const uint8_t* __restrict lit = pass.lit + row;
        const uint8_t* __restrict dark = pass.dark + row;
        for (int u = 0; u < cols; ++u) {
          const int16_t signal = static_cast<int16_t>(2 * pattern[u] - lit[u] - dark[u]);
          code[u] = static_cast<Code>((code[u] << 1) | (signal > 0));
          tied[u] |= signal == 0;
        }
      }
    }
    if (pass.flip_before) {
      // Signals of every bit (kept for the row below), then per pixel the flipped bit's pair.
      int16_t* signals = signal_rows[v & 1];
      const int16_t* signals_above = signal_rows[(v + 1) & 1];
      for (int bit = 0; bit < pass.bits; ++bit) {
        const uint8_t* __restrict pattern = pass.pattern[bit] + row;
        const uint8_t* __restrict other = pass.inverse ? pass.inverse[bit] + row : nullptr;
        const uint8_t* __restrict lit = pass.lit + row;
        const uint8_t* __restrict dark = pass.dark + row;
        int16_t* __restrict signal = signals + bit * width;
        if (other) {
          for (int u = 0; u < cols; ++u) signal[u] = static_cast<int16_t>(pattern[u] - other[u]);
        } else {
          for (int u = 0; u < cols; ++u)
            signal[u] = static_cast<int16_t>(2 * pattern[u] - lit[u] - dark[u]);
        }
      }
      if (v > 0) {
        int16_t* __restrict before = pass.flip_before + static_cast<size_t>(v) * cols;
        int16_t* __restrict here = pass.flip_here + static_cast<size_t>(v) * cols;
        // 16-bit lanes throughout (x86 has no byte shifts).
        for (int u = 0; u < cols; ++u)
          flipped_bits[u] = static_cast<int16_t>(code[u] ^ code_above[u]);
        if (pass.bits == 8) {  // the default: a constant bit count unrolls, the pixels vectorize
          selectFlippedSignals<8>(cols, width, flipped_bits, signals, signals_above, before, here);
        } else {  // one vectorized pass per bit
          for (int u = 0; u < cols; ++u) {
            before[u] = 0;
            here[u] = 0;
          }
          for (int bit = 0; bit < pass.bits; ++bit) {
            const int16_t bit_mask = static_cast<int16_t>(1 << (pass.bits - 1 - bit));
            const int16_t* __restrict signal = signals + bit * width;
            const int16_t* __restrict signal_above = signals_above + bit * width;
            for (int u = 0; u < cols; ++u) {
              const int16_t selected = static_cast<int16_t>(-((flipped_bits[u] & bit_mask) != 0));
              before[u] = static_cast<int16_t>(before[u] | (signal_above[u] & selected));
              here[u] = static_cast<int16_t>(here[u] | (signal[u] & selected));
            }
          }
        }
      }
    }
    // Valid pixels with a tie (rare, resolved by the caller), 8 flags per step.
    for (int u = 0; u < cols; u += 8) {
      uint64_t tied_word, valid_word;
      std::memcpy(&tied_word, tied + u, sizeof tied_word);
      std::memcpy(&valid_word, valid + u, sizeof valid_word);
      for (uint64_t both = tied_word & valid_word; both != 0; both &= both - 1) {
        const int pixel = u + __builtin_ctzll(both) / 8;
        if (pixel < cols) pass.tied->push_back(static_cast<uint32_t>(v * cols + pixel));
      }
    }
    uint16_t* __restrict stripe = pass.stripe + v * pass.stripe_step;
    float* __restrict coordinate = pass.coordinate + v * pass.coordinate_step;
    for (int u = 0; u < cols; ++u) {
      const uint16_t keep = static_cast<uint16_t>(0 - valid[u]);  // 0xFFFF where valid
      stripe[u] = static_cast<uint16_t>((grayDecode(static_cast<uint16_t>(code[u])) & keep) |
                                        static_cast<uint16_t>(~keep & kInvalidStripe));
    }
    // A bitwise select: GCC does not vectorize "invalid ? NaN : centre" (the float add could
    // trap), so the NaN is merged into the centre's bits.
    uint32_t* __restrict coordinate_bits = reinterpret_cast<uint32_t*>(coordinate);
    for (int u = 0; u < cols; ++u) {
      const float centre = static_cast<float>(static_cast<int32_t>(stripe[u])) + 0.5f;
      uint32_t centre_bits;
      std::memcpy(&centre_bits, &centre, sizeof centre_bits);
      const uint32_t invalid = 0u - static_cast<uint32_t>(stripe[u] == kInvalidStripe);
      coordinate_bits[u] = (centre_bits & ~invalid) | (kNaNBits & invalid);
    }
  }
}

BODY_SCAN_ALWAYS_INLINE void integerPassInline(const IntegerPass& pass) {
  if (pass.bits <= 8) {
    integerPassCoded<uint8_t>(pass);
  } else {
    integerPassCoded<uint16_t>(pass);
  }
}

void integerPassSse2(const IntegerPass& pass) { integerPassInline(pass); }
BODY_SCAN_TARGET_AVX2 void integerPassAvx2(const IntegerPass& pass) { integerPassInline(pass); }
BODY_SCAN_TARGET_AVX512 void integerPassAvx512(const IntegerPass& pass) { integerPassInline(pass); }

// bits[i / 64] bit (i % 64) = a[i] != b[i] for i < n.
void changedTail(const uint16_t* a, const uint16_t* b, int begin, int n, uint64_t* bits) {
  if (begin >= n) return;
  uint64_t mask = 0;
  for (int k = 0; begin + k < n; ++k)
    mask |= static_cast<uint64_t>(a[begin + k] != b[begin + k]) << k;
  bits[begin / 64] = mask;
}

void changedSse2(const uint16_t* a, const uint16_t* b, int n, uint64_t* bits) {
  int i = 0;
  for (; i + 64 <= n; i += 64) {
    uint64_t mask = 0;
    for (int k = 0; k < 64; k += 16) {
      const __m128i low =
          _mm_cmpeq_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(a + i + k)),
                          _mm_loadu_si128(reinterpret_cast<const __m128i*>(b + i + k)));
      const __m128i high =
          _mm_cmpeq_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(a + i + k + 8)),
                          _mm_loadu_si128(reinterpret_cast<const __m128i*>(b + i + k + 8)));
      const uint32_t equal = static_cast<uint32_t>(_mm_movemask_epi8(_mm_packs_epi16(low, high)));
      mask |= static_cast<uint64_t>(~equal & 0xFFFFu) << k;
    }
    bits[i / 64] = mask;
  }
  changedTail(a, b, i, n, bits);
}

BODY_SCAN_TARGET_AVX2 void changedAvx2(const uint16_t* a, const uint16_t* b, int n,
                                       uint64_t* bits) {
  int i = 0;
  for (; i + 64 <= n; i += 64) {
    uint64_t mask = 0;
    for (int k = 0; k < 64; k += 32) {
      const __m256i low =
          _mm256_cmpeq_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(a + i + k)),
                             _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + i + k)));
      const __m256i high =
          _mm256_cmpeq_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(a + i + k + 16)),
                             _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + i + k + 16)));
      // packs works within 128-bit lanes: restore the pixel order of the 64-bit quarters.
      const __m256i packed = _mm256_permute4x64_epi64(_mm256_packs_epi16(low, high), 0xD8);
      const uint32_t equal = static_cast<uint32_t>(_mm256_movemask_epi8(packed));
      mask |= static_cast<uint64_t>(~equal) << k;
    }
    bits[i / 64] = mask;
  }
  changedTail(a, b, i, n, bits);
}

BODY_SCAN_TARGET_AVX512 void changedAvx512(const uint16_t* a, const uint16_t* b, int n,
                                           uint64_t* bits) {
  int i = 0;
  for (; i + 64 <= n; i += 64) {
    const uint64_t low =
        _mm512_cmpneq_epi16_mask(_mm512_loadu_si512(a + i), _mm512_loadu_si512(b + i));
    const uint64_t high =
        _mm512_cmpneq_epi16_mask(_mm512_loadu_si512(a + i + 32), _mm512_loadu_si512(b + i + 32));
    bits[i / 64] = low | (high << 32);
  }
  changedTail(a, b, i, n, bits);
}

// std::clamp(value, low, high), NaN included, written as the two selects that x86 has as
// maxss/minss, so that it compiles without branches.
inline float clampLikeStd(float value, float low, float high) {
  const float at_least_low = low > value ? low : value;  // value < low ? low : value
  return high < at_least_low ? high : at_least_low;      // then high < value ? high : value
}

// One row of the boundary walk along image columns (kAlongRows) for every column at once: the
// reference's step() as selects over SoA state, evaluated for all columns and kept where the
// stripe id changed. A run is rewritten when its closing boundary arrives; runs longer than
// kVectorRun pixels are left to the scalar step (needs_scalar), which also keeps their state.
constexpr int kVectorRun = 4;

struct WalkRow {
  const uint16_t* current;        // stripe ids of row `position`
  const uint16_t* last;           // ... and of the row before
  const int16_t* signal_before;   // the flipped bit's signal above and at the boundary (where
  const int16_t* signal_here;     // the stripe id changed by one; anything elsewhere)
  float* coordinate[kVectorRun];  // rows position - 1 ... - kVectorRun (spares where < 0)
  int32_t* segment_start;
  int32_t* previous_valid;
  float* previous_position;
  float* previous_coordinate;
  float* stripe_width;
  int32_t* needs_scalar;   // out
  bool* any_needs_scalar;  // out: some column of this row needs the scalar step
  int cols, position;
  float max_width;
};

#pragma GCC push_options
#pragma GCC target("avx512f,avx512bw,avx512vl,avx512dq")
namespace avx512 {
#include "stripe_decoder_walk_row.inc"
}  // namespace avx512
#pragma GCC pop_options

// Only AVX-512 runs the row-parallel walk; below it decodeFast uses the reference walk. With SSE2
// GCC lowers these selects badly (no blends; 4.5-6.6 ms per set against the reference's
// 1.6-1.9 ms), and with AVX2 (8 lanes) the walk plus the flipped-bit signals of the integer
// pass took longer than the reference walk.
BODY_SCAN_TARGET_AVX512 int walkRowAvx512(const WalkRow& row) {
  return avx512::walkRowLanes<16>(row);
}

}  // namespace

void StripeDecoder::decodeFast(const std::vector<cv::Mat>& frames, const FrameRows& rows,
                               StripeImage& out) const {
  const SimdLevel level = effectiveSimdLevel(params_.max_simd);
  const int cols = frames[0].cols, rows_count = frames[0].rows;
  IntegerPass pass;
  pass.lit = rows.lit;
  pass.dark = rows.dark;
  pass.pattern = rows.pattern.data();
  pass.inverse = rows.inverse.empty() ? nullptr : rows.inverse.data();
  pass.frame_step = rows.step;
  pass.cols = cols;
  pass.rows = rows_count;
  pass.bits = layout_.bits();
  pass.min_contrast = static_cast<uint8_t>(std::clamp(params_.min_contrast, 0, 255));
  pass.contrast_usable = params_.min_contrast <= 255;
  pass.min_bright_window =
      static_cast<uint8_t>(std::clamp(params_.min_bright_neighbours + 1, 0, 10));
  pass.ratio_q8 = static_cast<uint16_t>(edge_ratio_q8_);
  pass.stripe = out.stripe.ptr<uint16_t>();
  pass.stripe_step = out.stripe.step1();
  pass.coordinate = out.coordinate.ptr<float>();
  pass.coordinate_step = out.coordinate.step1();
  fast_rows_.resize(scratchBytes(cols));
  pass.scratch = fast_rows_.data();
  tied_pixels_.clear();
  pass.tied = &tied_pixels_;
  // The vectorized walk along image columns (AVX-512) reads the flipped bit's signals from the
  // integer pass (the frames are in cache there); the scalar walk reads the frames itself.
  const bool flips_wanted = params_.subpixel && level == SimdLevel::kAvx512 &&
                            params_.axis != DecoderParams::StripeAxis::kAlongColumns;
  const size_t pixels = static_cast<size_t>(cols) * rows_count;
  flip_signals_.resize(flips_wanted ? 2 * pixels : 0);
  pass.flip_before = flips_wanted ? flip_signals_.data() : nullptr;
  pass.flip_here = flips_wanted ? flip_signals_.data() + pixels : nullptr;
  switch (level) {
    case SimdLevel::kAvx512:
      integerPassAvx512(pass);
      break;
    case SimdLevel::kAvx2:
      integerPassAvx2(pass);
      break;
    case SimdLevel::kSse2:
      integerPassSse2(pass);
      break;
  }
  // The integer pass decoded tied pixels without their tied bits; redo them as the reference
  // does (grayEncode inverts grayDecode, giving back the raw code).
  for (const uint32_t pixel : tied_pixels_) {
    const int v = static_cast<int>(pixel / cols), u = static_cast<int>(pixel % cols);
    uint16_t& stripe = out.stripe(v, u);
    const uint16_t raw = static_cast<uint16_t>(grayEncode(stripe));
    stripe = grayDecode(
        breakTies(rows, raw, static_cast<size_t>(v) * rows.step + u, u, v, cols, rows_count));
    out.coordinate(v, u) = static_cast<float>(static_cast<int32_t>(stripe)) + 0.5f;
  }
  // The flipped bit of a pair involving a tied pixel came from its untied code: redo both pairs.
  if (flips_wanted)
    for (const uint32_t pixel : tied_pixels_) {
      const int v = static_cast<int>(pixel / cols), u = static_cast<int>(pixel % cols);
      for (int below = std::max(v, 1); below <= std::min(v + 1, rows_count - 1); ++below) {
        const int here = out.stripe(below, u), above = out.stripe(below - 1, u);
        if (here == kInvalidStripe || above == kInvalidStripe || std::abs(here - above) != 1)
          continue;
        const int bit = bit_between_[std::min(here, above)];
        const size_t index = static_cast<size_t>(below) * cols + u;
        const size_t frame_index = static_cast<size_t>(below) * rows.step + u;
        pass.flip_before[index] = static_cast<int16_t>(rows.signal(bit, frame_index - rows.step));
        pass.flip_here[index] = static_cast<int16_t>(rows.signal(bit, frame_index));
      }
    }
  if (!params_.subpixel) return;
  const bool along_rows = params_.axis == DecoderParams::StripeAxis::kAuto
                              ? stripesChangeAlongRows(out)
                              : params_.axis == DecoderParams::StripeAxis::kAlongRows;
  if (along_rows) {
    // Below AVX-512 the reference walk is the fastest measured (see walkRowAvx512).
    const bool flips_ready = flip_signals_.size() == 2 * pixels;
    if (flips_ready) {
      interpolateBoundariesFast<true>(rows, out, level);
    } else {
      interpolateBoundaries<true>(rows, out);
    }
  } else {
    interpolateBoundariesFast<false>(rows, out, level);
  }
}

template <bool kAlongRows>
void StripeDecoder::interpolateBoundariesFast(const FrameRows& frame_rows, StripeImage& out,
                                              SimdLevel level) const {
  // The reference's walk (interpolateBoundaries), visiting only the pixels whose stripe id
  // differs from the previous one along the line; see there for the meaning of each step.
  const int cols = out.stripe.cols, rows = out.stripe.rows;
  const int lines = kAlongRows ? cols : rows;
  const int length = kAlongRows ? rows : cols;
  const size_t stripe_step = out.stripe.step1(), coordinate_step = out.coordinate.step1();
  const size_t frame_step = frame_rows.step;
  auto at = [](size_t step, int line, int position) -> size_t {
    return kAlongRows ? static_cast<size_t>(position) * step + line
                      : static_cast<size_t>(line) * step + position;
  };
  const uint16_t* stripes = out.stripe.ptr<uint16_t>();
  float* coordinates = out.coordinate.ptr<float>();
  const float max_width = static_cast<float>(params_.max_stripe_width_px);
  const size_t along = kAlongRows ? coordinate_step : 1;  // coordinate stride along a line
  void (*changed)(const uint16_t*, const uint16_t*, int, uint64_t*) =
      level == SimdLevel::kAvx512 ? changedAvx512
      : level == SimdLevel::kAvx2 ? changedAvx2
                                  : changedSse2;

  // Rewrites the run [segment_start, end] of one stripe id between two boundaries. The two
  // cases of the reference (interpolation between two boundaries, extrapolation from one) are
  // one formula with selected constants, so the only branch left is "write nothing".
  auto flush = [&](const LineWalk& walk, int line, int end, bool next_valid, float next_position,
                   float next_coordinate) {
    const float stripe = stripes[at(stripe_step, line, end)];
    const bool interpolate = walk.previous_valid && next_valid &&
                             std::abs(next_coordinate - walk.previous_coordinate) == 1.f &&
                             next_position - walk.previous_position <= max_width;
    if (!interpolate && !(walk.stripe_width > 0 && (walk.previous_valid || next_valid))) return;
    const bool from_previous = interpolate || walk.previous_valid;
    const float origin_coordinate = from_previous ? walk.previous_coordinate : next_coordinate;
    const float origin_position = from_previous ? walk.previous_position : next_position;
    const float rise = interpolate ? next_coordinate - walk.previous_coordinate
                                   : (origin_coordinate == stripe ? 1.f : -1.f);
    const float run = interpolate ? next_position - walk.previous_position : walk.stripe_width;
    const float slope = rise / run;
    // clamp(x, -inf, inf) == x, NaN included: the interpolation is not clamped.
    const float low = interpolate ? -kInfinity : stripe;
    const float high = interpolate ? kInfinity : stripe + 1.f;
    float* line_coordinates = coordinates + at(coordinate_step, line, 0);
    auto value = [&](int position) {
      const float offset = static_cast<float>(position) - origin_position;
      return clampLikeStd(origin_coordinate + (interpolate ? offset : std::abs(offset)) * slope,
                          low, high);
    };
    // Runs are mostly 1-3 pixels: the first kShortRun positions are written branch-free
    // (positions past the run go to a sink), so the run length is not a mispredicted branch.
    constexpr int kShortRun = 3;
    const int start = walk.segment_start;
    float sink;
    for (int k = 0; k < kShortRun; ++k) {
      const int position = start + k;
      float* target = position <= end ? line_coordinates + position * along : &sink;
      *target = value(position);
    }
    for (int position = start + kShortRun; position <= end; ++position)
      line_coordinates[position * along] = value(position);
  };

  auto step = [&](LineWalk& walk, int line, int position) {
    const uint16_t current = stripes[at(stripe_step, line, position)];
    const uint16_t last = stripes[at(stripe_step, line, position - 1)];
    const bool valid =
        last != kInvalidStripe && current != kInvalidStripe && std::abs(current - last) == 1;
    float position_here = 0, coordinate_here = 0;
    if (valid) {
      const int bit = bit_between_[std::min(current, last)];
      const float a = frame_rows.signal(bit, at(frame_step, line, position - 1));
      const float b = frame_rows.signal(bit, at(frame_step, line, position));
      const float t = a == b ? 0.5f : clampLikeStd(a / (a - b), 0.f, 1.f);
      position_here = static_cast<float>(position - 1) + t;
      coordinate_here = static_cast<float>(std::max(current, last));
    }
    if (last != kInvalidStripe)
      flush(walk, line, position - 1, valid, position_here, coordinate_here);
    if (valid && walk.previous_valid && std::abs(coordinate_here - walk.previous_coordinate) == 1.f)
      walk.stripe_width = position_here - walk.previous_position;
    walk.previous_valid = valid;
    walk.previous_position = position_here;
    walk.previous_coordinate = coordinate_here;
    walk.segment_start = position;
  };

  changed_bits_.resize((static_cast<size_t>(std::max(cols, 1)) + 63) / 64);
  uint64_t* bits = changed_bits_.data();
  if (kAlongRows) {
    // Per column state as arrays (WalkRow), the flipped bit's signals, two spare rows.
    walk_floats_.assign((3 + kVectorRun - 1) * static_cast<size_t>(cols), 0.f);
    walk_ints_.assign(3 * static_cast<size_t>(cols), 0);
    float* previous_position = walk_floats_.data();
    float* previous_coordinate = previous_position + cols;
    float* stripe_width = previous_coordinate + cols;
    float* spare_rows[kVectorRun - 1];  // stand-ins for the rows above row 0
    for (int k = 0; k < kVectorRun - 1; ++k) spare_rows[k] = stripe_width + (k + 1) * cols;
    const size_t pixels = static_cast<size_t>(cols) * rows;
    const int16_t* flips_before = flip_signals_.data();
    const int16_t* flips_here = flips_before + pixels;
    int32_t* segment_start = walk_ints_.data();
    int32_t* previous_valid = segment_start + cols;
    int32_t* needs_scalar = previous_valid + cols;
    auto load = [&](int u) {
      LineWalk walk;
      walk.segment_start = segment_start[u];
      walk.previous_position = previous_position[u];
      walk.previous_coordinate = previous_coordinate[u];
      walk.previous_valid = previous_valid[u] != 0;
      walk.stripe_width = stripe_width[u];
      return walk;
    };
    auto store = [&](int u, const LineWalk& walk) {
      segment_start[u] = walk.segment_start;
      previous_position[u] = walk.previous_position;
      previous_coordinate[u] = walk.previous_coordinate;
      previous_valid[u] = walk.previous_valid;
      stripe_width[u] = walk.stripe_width;
    };
    const int words = (cols + 63) / 64;
    for (int position = 1; position < length; ++position) {
      const uint16_t* current = stripes + position * stripe_step;
      const uint16_t* last = current - stripe_step;
      WalkRow row;
      bool any_needs_scalar = false;
      row.any_needs_scalar = &any_needs_scalar;
      row.current = current;
      row.last = last;
      row.signal_before = flips_before + static_cast<size_t>(position) * cols;
      row.signal_here = flips_here + static_cast<size_t>(position) * cols;
      for (int k = 0; k < kVectorRun; ++k)
        row.coordinate[k] = position - 1 - k >= 0
                                ? coordinates + (position - 1 - k) * coordinate_step
                                : spare_rows[k - 1];
      row.segment_start = segment_start;
      row.previous_valid = previous_valid;
      row.previous_position = previous_position;
      row.previous_coordinate = previous_coordinate;
      row.stripe_width = stripe_width;
      row.needs_scalar = needs_scalar;
      row.cols = cols;
      row.position = position;
      row.max_width = max_width;
      const int vector_end = walkRowAvx512(row);
      if (!any_needs_scalar) continue;
      for (int u = vector_end; u < cols; ++u) needs_scalar[u] = 1;  // columns left over
      changed(current, last, cols, bits);
      for (int word = 0; word < words; ++word)
        for (uint64_t mask = bits[word]; mask != 0; mask &= mask - 1) {
          const int u = 64 * word + __builtin_ctzll(mask);
          if (!needs_scalar[u]) continue;
          LineWalk walk = load(u);
          step(walk, u, position);
          store(u, walk);
        }
    }
    for (int u = 0; u < cols; ++u)
      if (stripes[at(stripe_step, u, length - 1)] != kInvalidStripe)
        flush(load(u), u, length - 1, false, 0.f, 0.f);
  } else if (length > 1) {
    line_walks_.assign(lines, LineWalk{});
    const int words = (length - 1 + 63) / 64;
    for (int line = 0; line < lines; ++line) {
      const uint16_t* row = stripes + line * stripe_step;
      changed(row + 1, row, length - 1, bits);
      for (int word = 0; word < words; ++word)
        for (uint64_t mask = bits[word]; mask != 0; mask &= mask - 1)
          step(line_walks_[line], line, 64 * word + __builtin_ctzll(mask) + 1);
      if (row[length - 1] != kInvalidStripe)
        flush(line_walks_[line], line, length - 1, false, 0.f, 0.f);
    }
  } else {
    for (int line = 0; line < lines; ++line)  // one-pixel lines: a run without boundaries
      if (stripes[at(stripe_step, line, 0)] != kInvalidStripe)
        flush(LineWalk{}, line, 0, false, 0.f, 0.f);
  }
}

}  // namespace body_scan_driver
