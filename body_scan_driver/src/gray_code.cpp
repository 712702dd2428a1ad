#include <body_scan_driver/gray_code.h>

#include <string>

namespace body_scan_driver {

PatternLayout::PatternLayout(int bits, bool inverse_frames)
    : bits_(bits), inverse_frames_(inverse_frames) {
  if (bits < kMinBits || bits > kMaxBits)
    throw std::invalid_argument("Gray code bits must be in [" + std::to_string(kMinBits) + ", " +
                                std::to_string(kMaxBits) + "], got " + std::to_string(bits));
}

int PatternLayout::inverseFrame(int bit) const {
  if (!inverse_frames_) throw std::logic_error("this pattern layout has no inverse frames");
  return 3 + 2 * bit;
}

bool PatternLayout::lights(int frame, uint32_t stripe) const {
  if (frame == litFrame()) return true;
  if (frame == darkFrame()) return false;
  const int index = frame - 2;
  const int bit = inverse_frames_ ? index / 2 : index;
  const bool inverse = inverse_frames_ && index % 2 == 1;
  const bool on = (grayEncode(stripe) >> (bits_ - 1 - bit)) & 1u;
  return on != inverse;
}

int PatternLayout::bitBetween(uint32_t stripe) const {
  const uint32_t differing = grayEncode(stripe) ^ grayEncode(stripe + 1);
  int position = 0;
  while ((differing >> position) != 1u) ++position;
  return bits_ - 1 - position;
}

}  // namespace body_scan_driver
