// The one Gray code codec of the suite (thesis sec. 4.2.1, Table 4.1) and the frame layout of a
// pattern set. Every encoder and decoder (simulator, triangulation, calibration, benchmarks)
// goes through these functions.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace body_scan_driver {

constexpr int kMinBits = 1;
constexpr int kMaxBits = 10;

// Reflected binary Gray code: adjacent stripes differ in exactly one bit.
inline uint32_t grayEncode(uint32_t stripe) { return stripe ^ (stripe >> 1); }
// Prefix XOR from the most significant bit down (Table 4.1, "decoding"). Branch-free and
// generic in the width, so loops over uint16_t pixels vectorize in 16-bit lanes.
template <typename Unsigned>
constexpr Unsigned grayDecode(Unsigned gray) {
  static_assert(sizeof(Unsigned) <= 4, "up to 32-bit codes");
  gray = static_cast<Unsigned>(gray ^ (gray >> 1));
  gray = static_cast<Unsigned>(gray ^ (gray >> 2));
  gray = static_cast<Unsigned>(gray ^ (gray >> 4));
  if constexpr (sizeof(Unsigned) > 1) gray = static_cast<Unsigned>(gray ^ (gray >> 8));
  if constexpr (sizeof(Unsigned) > 2) gray = static_cast<Unsigned>(gray ^ (gray >> 16));
  return gray;
}

// Frame order of a pattern set (also documented in body_scan_msgs/PatternSet.msg):
//   0: all stripes lit, 1: all dark, then per bit b (0 = most significant):
//   with inverses 2+2b pattern and 3+2b inverse, without 2+b pattern.
// Pattern b lights stripe i where bit (bits-1-b) of grayEncode(i) is 1 (OpenCV's convention).
class PatternLayout {
 public:
  PatternLayout(int bits, bool inverse_frames);

  int bits() const { return bits_; }
  bool inverseFrames() const { return inverse_frames_; }
  int stripeCount() const { return 1 << bits_; }
  int frameCount() const { return 2 + (inverse_frames_ ? 2 : 1) * bits_; }

  static constexpr int litFrame() { return 0; }
  static constexpr int darkFrame() { return 1; }
  int patternFrame(int bit) const { return 2 + (inverse_frames_ ? 2 * bit : bit); }
  int inverseFrame(int bit) const;  // throws if the layout has no inverse frames

  // Whether frame `frame` lights stripe `stripe` (stripe in [0, stripeCount())).
  bool lights(int frame, uint32_t stripe) const;
  // Index of the bit (0 = most significant) that differs between adjacent stripes s and s+1.
  int bitBetween(uint32_t stripe) const;

 private:
  int bits_;
  bool inverse_frames_;
};

}  // namespace body_scan_driver
