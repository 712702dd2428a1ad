#include <body_scan_driver/gray_code.h>
#include <gtest/gtest.h>

#include <bitset>

using body_scan_driver::grayDecode;
using body_scan_driver::grayEncode;
using body_scan_driver::PatternLayout;

TEST(GrayCode, RoundTripForEveryBitCount) {
  for (int bits = body_scan_driver::kMinBits; bits <= body_scan_driver::kMaxBits; ++bits) {
    const PatternLayout layout(bits, true);
    for (uint32_t stripe = 0; stripe < static_cast<uint32_t>(layout.stripeCount()); ++stripe) {
      const uint32_t gray = grayEncode(stripe);
      ASSERT_LT(gray, static_cast<uint32_t>(layout.stripeCount())) << bits << " bits";
      ASSERT_EQ(grayDecode(gray), stripe) << bits << " bits";
      // Frames -> bits -> stripe: rebuild the code from what each pattern frame lights.
      uint32_t code = 0;
      for (int bit = 0; bit < bits; ++bit) {
        code = (code << 1) | layout.lights(layout.patternFrame(bit), stripe);
        ASSERT_NE(layout.lights(layout.patternFrame(bit), stripe),
                  layout.lights(layout.inverseFrame(bit), stripe));
      }
      ASSERT_EQ(grayDecode(code), stripe);
      if (stripe + 1 < static_cast<uint32_t>(layout.stripeCount())) {
        // Adjacent stripes differ in exactly one bit, the one bitBetween names.
        ASSERT_EQ(std::bitset<32>(gray ^ grayEncode(stripe + 1)).count(), 1u);
        const int bit = layout.bitBetween(stripe);
        EXPECT_NE(layout.lights(layout.patternFrame(bit), stripe),
                  layout.lights(layout.patternFrame(bit), stripe + 1));
      }
    }
  }
}

TEST(GrayCode, MatchesThesisTable41) {
  // Table 4.1, patterns (a)..(d) for stripes 0..15 (the thesis draws 0 as lit).
  const char* rows[] = {"0000000011111111", "0000111111110000", "0011110000111100",
                        "0110011001100110"};
  for (int bit = 0; bit < 4; ++bit)
    for (uint32_t stripe = 0; stripe < 16; ++stripe)
      EXPECT_EQ((grayEncode(stripe) >> (3 - bit)) & 1u,
                static_cast<uint32_t>(rows[bit][stripe] - '0'))
          << "pattern " << bit << " stripe " << stripe;
}

TEST(GrayCode, LayoutCountsAndOrder) {
  const PatternLayout with_inverse(8, true), without(8, false);
  EXPECT_EQ(with_inverse.frameCount(), 18);
  EXPECT_EQ(without.frameCount(), 10);
  EXPECT_EQ(with_inverse.patternFrame(0), 2);
  EXPECT_EQ(with_inverse.inverseFrame(0), 3);
  EXPECT_EQ(without.patternFrame(7), 9);
  EXPECT_TRUE(with_inverse.lights(PatternLayout::litFrame(), 17));
  EXPECT_FALSE(with_inverse.lights(PatternLayout::darkFrame(), 17));
  EXPECT_THROW(without.inverseFrame(0), std::logic_error);
  EXPECT_THROW(PatternLayout(0, true), std::invalid_argument);
  EXPECT_THROW(PatternLayout(11, true), std::invalid_argument);
}
