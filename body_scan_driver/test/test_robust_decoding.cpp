// The robust decoding for real captures (robust_decoding.h) on a synthetic checkerboard whose
// dark squares return a few grey levels, with stripes under two camera pixels wide (as a DLP
// projector a few metres away): against the truth, and against the decoder alone with the same
// contrast thresholds.
#include <body_scan_driver/robust_decoding.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>

#include "sim_fixtures.h"

using namespace body_scan_driver;

namespace {

constexpr int kWidth = 320, kHeight = 160, kSquare = 40;
constexpr double kNoise = 2.0;  // grey levels
const PatternLayout kLayout(8, true);

double trueCoordinate(double u) { return 30.0 + 0.6 * u; }  // stripes 1.67 px wide

struct Board {
  std::vector<cv::Mat> frames;
  cv::Mat1b signalless;  // pixels lit, but not by the patterns
};

// Area-sampled stripes, albedo 0.8 / 0.03 checker, ambient 2 grey levels, sensor noise.
Board renderBoard() {
  cv::RNG rng(7);
  Board board;
  for (int frame = 0; frame < kLayout.frameCount(); ++frame) {
    cv::Mat1b image(kHeight, kWidth);
    for (int v = 0; v < kHeight; ++v)
      for (int u = 0; u < kWidth; ++u) {
        const bool dark_square = ((u / kSquare) + (v / kSquare)) % 2 == 1;
        const double albedo = dark_square ? 0.03 : 0.8;
        double lit_share = 0;
        constexpr int kSamples = 16;
        for (int k = 0; k < kSamples; ++k) {
          const double stripe = trueCoordinate(u - 0.5 + (k + 0.5) / kSamples);
          lit_share += kLayout.lights(frame, static_cast<uint32_t>(stripe)) ? 1.0 : 0.0;
        }
        double value = 2 + 250 * albedo * lit_share / kSamples + rng.gaussian(kNoise);
        // The last square column: lit by something else (patterns and inverses alike).
        if (u >= kWidth - kSquare / 2) value = frame == PatternLayout::darkFrame() ? 2 : 150;
        image(v, u) = cv::saturate_cast<uint8_t>(value);
      }
    board.frames.push_back(image);
  }
  return board;
}

struct Errors {
  long decoded = 0, gross = 0, in_signalless = 0;
  double share() const { return decoded ? static_cast<double>(gross) / decoded : 1.0; }
};

// Gross: more than 0.3 stripes off (about 20 mm for a board a few metres away).
Errors compare(const StripeImage& stripes) {
  Errors errors;
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u) {
      const float c = stripes.coordinate(v, u);
      if (!std::isfinite(c)) continue;
      if (u >= kWidth - kSquare / 2) {
        ++errors.in_signalless;
        continue;
      }
      ++errors.decoded;
      errors.gross += std::abs(c - trueCoordinate(u)) > 0.3;
    }
  return errors;
}

}  // namespace

TEST(RobustDecoding, DisabledIsTheDecoderAsIs) {
  const Board board = renderBoard();
  StripeImage plain;
  StripeDecoder(kLayout).decode(board.frames, plain);
  const StripeImage robust_off = decodePatternFrames(board.frames, {}, kLayout, RobustDecoding{});
  EXPECT_EQ(cv::norm(plain.stripe, robust_off.stripe, cv::NORM_INF), 0);
  long different = 0;
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u) {
      const float a = plain.coordinate(v, u), b = robust_off.coordinate(v, u);
      different += !(a == b || (std::isnan(a) && std::isnan(b)));
    }
  EXPECT_EQ(different, 0);
}

TEST(RobustDecoding, DarkSquaresDecodeWithoutGrossErrors) {
  const Board board = renderBoard();
  RobustDecoding robust;
  robust.enabled = true;
  StripeImage decoder_only;
  StripeDecoder(kLayout, robust.decoderParams()).decode(board.frames, decoder_only);
  const Errors before = compare(decoder_only);
  const StripeImage refined = decodePatternFrames(board.frames, {}, kLayout, robust);
  const Errors after = compare(refined);
  const long board_pixels = static_cast<long>(kHeight) * (kWidth - kSquare / 2);
  std::printf(
      "[ figure ] decoder alone: %ld pixels, %.2f %% > 0.3 stripes off; robust: %ld, %.3f %%\n",
      before.decoded, 100 * before.share(), after.decoded, 100 * after.share());
  // Recovered rather than rejected: about as many pixels as the decoder alone.
  EXPECT_GT(after.decoded, 0.85 * board_pixels);
  EXPECT_GT(after.decoded, 0.97 * before.decoded);
  EXPECT_LT(after.share(), 0.005);
  EXPECT_LT(after.share(), before.share() / 10);
  // Lit but not by the projector: the decoder alone decodes it, the robust decoding does not.
  EXPECT_GT(before.in_signalless, 0);
  EXPECT_EQ(after.in_signalless, 0);
}

// A sphere in front of a wall (the simulator, default noise): the fit must not blend the two
// depths at the silhouette (flying points) nor lose the surfaces.
TEST(RobustDecoding, DepthEdgesStaySharpOnTheSimulator) {
  auto scene = test::planeScene(1.3);
  scene->add(std::make_unique<sim::Sphere>(Eigen::Vector3d(1.0, 0, 0), 0.12,
                                           sim::Material{0.8, {0.8, 0.8, 0.8}}));
  const sim::VirtualPair pair(test::pairLookingAlongX(), scene);
  const sim::RenderedPatternSet set = pair.render(3);
  RobustDecoding robust;
  robust.enabled = true;
  StripeImage standard;
  StripeDecoder(pair.layout()).decode(set.frames, standard);
  const StripeImage refined = decodePatternFrames(set.frames, {}, pair.layout(), robust);
  struct Count {
    long decoded = 0, off_by_a_stripe = 0;
    double absolute_error = 0;
  };
  auto count = [&](const StripeImage& image) {
    Count c;
    for (int v = 0; v < image.coordinate.rows; ++v)
      for (int u = 0; u < image.coordinate.cols; ++u) {
        const float decoded = image.coordinate(v, u), truth = set.truth.stripe(v, u);
        if (!std::isfinite(decoded) || !std::isfinite(truth)) continue;
        ++c.decoded;
        c.absolute_error += std::abs(decoded - truth);
        c.off_by_a_stripe += std::abs(decoded - truth) > 1;
      }
    c.absolute_error /= std::max(1L, c.decoded);
    return c;
  };
  const Count before = count(standard), after = count(refined);
  std::printf(
      "[ figure ] sphere before a wall: standard %ld pixels, %ld > 1 stripe off, mean |error| "
      "%.3f; robust %ld, %ld, %.3f stripes\n",
      before.decoded, before.off_by_a_stripe, before.absolute_error, after.decoded,
      after.off_by_a_stripe, after.absolute_error);
  EXPECT_GT(after.decoded, 0.98 * before.decoded);
  EXPECT_LE(after.off_by_a_stripe, before.off_by_a_stripe + 0.0005 * before.decoded);
  EXPECT_LT(after.absolute_error, before.absolute_error);
}
