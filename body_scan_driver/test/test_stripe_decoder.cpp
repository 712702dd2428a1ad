#include <body_scan_driver/stripe_decoder.h>
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/structured_light/graycodepattern.hpp>

#include "sim_fixtures.h"

using namespace body_scan;

namespace {

struct DecodeStats {
  long lit = 0, correct = 0, valid = 0, off_by_more_than_one = 0;
};

DecodeStats decodeAndCompare(const sim::RenderedPatternSet& set, const PatternLayout& layout,
                             StripeImage& image, DecoderParams params = {}) {
  StripeDecoder(layout, params).decode(set.frames, image);
  DecodeStats stats;
  for (int v = 0; v < image.stripe.rows; ++v)
    for (int u = 0; u < image.stripe.cols; ++u) {
      const float truth = set.truth.stripe(v, u);
      const int decoded = image.stripe(v, u);
      if (!std::isnan(truth)) {
        ++stats.lit;
        stats.correct += decoded == static_cast<int>(std::floor(truth));
      }
      if (decoded != kInvalidStripe) {
        ++stats.valid;
        stats.off_by_more_than_one +=
            std::isnan(truth) || std::abs(decoded - static_cast<int>(std::floor(truth))) > 1;
      }
    }
  return stats;
}

}  // namespace

TEST(StripeDecoder, NoiseFreePlaneDecodesTheTrueStripe) {
  const sim::VirtualPair pair(test::pairLookingAlongX(0.0), test::planeScene(1.0));
  StripeImage image;
  const DecodeStats stats = decodeAndCompare(pair.render(), pair.layout(), image);
  const double fraction = static_cast<double>(stats.correct) / stats.lit;
  std::cout << "[ figure ] noise-free plane: decoded == true stripe for " << 100 * fraction
            << " % of " << stats.lit << " lit pixels\n";
  EXPECT_GT(stats.lit, 300000);
  EXPECT_GE(fraction, 0.999);
}

TEST(StripeDecoder, DefaultNoiseRarelyMissesByMoreThanOneStripe) {
  for (bool inverse : {true, false}) {
    auto config = test::pairLookingAlongX();
    config.inverse_frames = inverse;
    const sim::VirtualPair pair(config, test::planeScene(1.0, 0.6));
    StripeImage image;
    const DecodeStats stats = decodeAndCompare(pair.render(7), pair.layout(), image);
    const double fraction = static_cast<double>(stats.off_by_more_than_one) / stats.valid;
    std::cout << "[ figure ] default noise, inverse frames " << inverse << ": " << 100 * fraction
              << " % of " << stats.valid << " valid pixels off by more than one stripe; exact "
              << 100.0 * stats.correct / stats.lit << " %\n";
    EXPECT_GT(stats.valid, 0.99 * stats.lit);
    EXPECT_LE(fraction, 0.001);
  }
}

TEST(StripeDecoder, DarkSurfacesStillDecode) {
  // Dark hair and clothing (albedo 0.15) return little light but must decode.
  const sim::VirtualPair pair(test::pairLookingAlongX(), test::planeScene(1.2, 0.15));
  StripeImage image;
  const DecodeStats stats = decodeAndCompare(pair.render(3), pair.layout(), image);
  EXPECT_GT(stats.valid, 0.98 * stats.lit);
  EXPECT_LE(static_cast<double>(stats.off_by_more_than_one) / stats.valid, 0.001);
}

TEST(StripeDecoder, AgreesWithOpenCvGrayCodeDecoder) {
  // Peer: OpenCV's structured_light decodes the same frames. Its getProjPixel reads the
  // column (x) code from the first 2 * ceil(log2(width)) images, pattern then inverse, and the
  // row code from the next ones: a 256 x 2 projector decodes our 8 pattern/inverse pairs as x
  // (its 1-bit y code reads a repeated pair and is ignored).
  const sim::VirtualPair pair(test::pairLookingAlongX(), test::planeScene(1.0));
  const sim::RenderedPatternSet set = pair.render(11);
  StripeImage image;
  StripeDecoder(pair.layout(), {}).decode(set.frames, image);
  auto opencv = cv::structured_light::GrayCodePattern::create(256, 2);
  std::vector<cv::Mat> opencv_frames(set.frames.begin() + 2, set.frames.end());
  opencv_frames.insert(opencv_frames.end(), set.frames.begin() + 2, set.frames.begin() + 4);
  ASSERT_EQ(opencv->getNumberOfPatternImages(), opencv_frames.size());
  long compared = 0, equal = 0, tie_broken = 0;
  for (int v = 0; v < image.stripe.rows; v += 3)
    for (int u = 0; u < image.stripe.cols; u += 3) {
      if (image.stripe(v, u) == kInvalidStripe) continue;
      cv::Point projector_pixel;
      opencv->getProjPixel(opencv_frames, u, v, projector_pixel);
      ++compared;
      if (projector_pixel.x == image.stripe(v, u)) {
        ++equal;
        continue;
      }
      // Where pattern == inverse OpenCV always reads 0; we break the tie from the neighbours.
      bool tied = false;
      for (int bit = 0; bit < 8; ++bit)
        tied |=
            set.frames[2 + 2 * bit].at<uint8_t>(v, u) == set.frames[3 + 2 * bit].at<uint8_t>(v, u);
      tie_broken += tied;
    }
  std::cout << "[ figure ] OpenCV agrees on " << equal << " of " << compared
            << " pixels; the other " << compared - equal
            << " are pattern == inverse ties we resolve (" << tie_broken << ")\n";
  EXPECT_GT(compared, 30000);
  EXPECT_EQ(equal + tie_broken, compared);
  EXPECT_LT(compared - equal, compared / 500);
}

TEST(StripeDecoder, SubpixelCoordinateIsCloserToTruthThanStripeCentres) {
  const sim::VirtualPair pair(test::pairLookingAlongX(), test::planeScene(1.0));
  const sim::RenderedPatternSet set = pair.render(5);
  double error[2] = {0, 0};
  long count = 0;
  for (bool subpixel : {false, true}) {
    DecoderParams params;
    params.subpixel = subpixel;
    StripeImage image;
    StripeDecoder(pair.layout(), params).decode(set.frames, image);
    count = 0;
    for (int v = 0; v < image.stripe.rows; ++v)
      for (int u = 0; u < image.stripe.cols; ++u)
        if (!std::isnan(image.coordinate(v, u)) && !std::isnan(set.truth.stripe(v, u))) {
          error[subpixel] += std::abs(image.coordinate(v, u) - set.truth.stripe(v, u));
          ++count;
        }
    error[subpixel] /= count;
  }
  std::cout << "[ figure ] mean |coordinate - true| in stripes: centres " << error[0]
            << ", subpixel " << error[1] << "\n";
  EXPECT_NEAR(error[0], 0.25, 0.02);  // uniform within a stripe
  EXPECT_LT(error[1], 0.05);
}

TEST(StripeDecoder, RejectsBadFrameSetsWithClearErrors) {
  const PatternLayout layout(8, true);
  StripeDecoder decoder(layout);
  StripeImage image;
  std::vector<cv::Mat> frames(17, cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)));
  try {
    decoder.decode(frames, image);
    FAIL() << "17 frames accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("need 18"), std::string::npos) << e.what();
  }
  frames.push_back(cv::Mat(480, 640, CV_8UC3));
  EXPECT_THROW(decoder.decode(frames, image), std::invalid_argument);
  frames.back() = cv::Mat(240, 320, CV_8UC1);
  EXPECT_THROW(decoder.decode(frames, image), std::invalid_argument);
}
