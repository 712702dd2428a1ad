// Private to the decoder's two implementations (stripe_decoder.cpp, stripe_decoder_fast.cpp).
#pragma once

#include <body_scan_driver/stripe_decoder.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace body_scan_driver {

// Row-major byte pointers of the frames a bit decision reads. The signed bit signal is
// pattern - inverse, or 2 pattern - (lit + dark) without inverse frames: its sign is the bit
// and its zero crossing the stripe edge.
struct StripeDecoder::FrameRows {
  std::vector<const uint8_t*> pattern, inverse;
  const uint8_t *lit, *dark;
  size_t step;
  int signal(int bit, size_t index) const {
    if (!inverse.empty()) return pattern[bit][index] - inverse[bit][index];
    return 2 * pattern[bit][index] - lit[index] - dark[index];
  }
};

}  // namespace body_scan_driver
