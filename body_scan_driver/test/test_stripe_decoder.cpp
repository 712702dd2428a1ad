#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/stripe_decoder.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <opencv2/structured_light/graycodepattern.hpp>

#include "sim_fixtures.h"

using namespace body_scan_driver;

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

namespace {

// Pixels where two decodings differ in stripe id or in the coordinate's bits (NaN == NaN).
long differingPixels(const StripeImage& a, const StripeImage& b) {
  long differing = 0;
  for (int v = 0; v < a.stripe.rows; ++v)
    for (int u = 0; u < a.stripe.cols; ++u) {
      const float x = a.coordinate(v, u), y = b.coordinate(v, u);
      differing += a.stripe(v, u) != b.stripe(v, u) || std::memcmp(&x, &y, sizeof x) != 0;
    }
  return differing;
}

std::shared_ptr<sim::Scene> personScene() {
  return std::make_shared<sim::Scene>(
      sim::loadScene(sim::driverConfigDir() + "/scenes/standing_person.yaml"));
}

sim::VirtualPairConfig defaultPair() {
  return sim::loadVirtualPairConfig(sim::driverConfigDir() + "/pairs/default_pair.yaml");
}

// kFast at every SIMD level this CPU has must reproduce kReference bit for bit.
void expectFastEqualsReference(const sim::VirtualPair& pair, const sim::RenderedPatternSet& set,
                               DecoderParams params, const std::string& what) {
  params.implementation = DecoderParams::Implementation::kReference;
  StripeImage reference;
  StripeDecoder(pair.layout(), params).decode(set.frames, reference);
  long valid = 0;
  for (int v = 0; v < reference.stripe.rows; ++v)
    for (int u = 0; u < reference.stripe.cols; ++u)
      valid += reference.stripe(v, u) != kInvalidStripe;
  EXPECT_GT(valid, 10000) << what;  // the comparison covers real decoded surfaces
  params.implementation = DecoderParams::Implementation::kFast;
  for (SimdLevel level : availableSimdLevels()) {
    params.max_simd = level;
    const StripeDecoder decoder(pair.layout(), params);
    StripeImage fast;
    for (int repeat = 0; repeat < 2; ++repeat) {  // the second call reuses every buffer
      decoder.decode(set.frames, fast);
      EXPECT_EQ(differingPixels(reference, fast), 0)
          << what << ", " << simdLevelName(level) << ", call " << repeat;
    }
  }
}

}  // namespace

TEST(StripeDecoder, FastImplementationIsBitIdenticalToReference) {
  std::cout << "[ figure ] SIMD levels tested:";
  for (SimdLevel level : availableSimdLevels()) std::cout << " " << simdLevelName(level);
  std::cout << "\n";
  for (bool inverse : {true, false}) {
    auto plane_config = test::pairLookingAlongX();
    plane_config.inverse_frames = inverse;
    const sim::VirtualPair plane(plane_config, test::planeScene(1.0));
    const sim::RenderedPatternSet plane_set = plane.render(17);
    const std::string inverse_text = inverse ? " with inverses" : " without inverses";
    expectFastEqualsReference(plane, plane_set, {}, "plane" + inverse_text);
    DecoderParams across;  // the other walk direction: lines along image rows
    across.axis = DecoderParams::StripeAxis::kAlongColumns;
    expectFastEqualsReference(plane, plane_set, across, "plane, walk along rows" + inverse_text);
    DecoderParams integer;
    integer.subpixel = false;
    expectFastEqualsReference(plane, plane_set, integer, "plane, no subpixel" + inverse_text);

    auto person_config = defaultPair();
    person_config.inverse_frames = inverse;
    const sim::VirtualPair person(person_config, personScene());
    expectFastEqualsReference(person, person.render(23), {}, "person" + inverse_text);
  }
  // 10 bits (16-bit codes) and the filters switched off.
  auto config = test::pairLookingAlongX();
  config.bits = 10;
  const sim::VirtualPair ten_bits(config, test::planeScene(1.2, 0.3));
  DecoderParams unfiltered;
  unfiltered.edge_contrast_ratio = 0;
  unfiltered.min_bright_neighbours = 0;
  unfiltered.min_contrast = 0;
  expectFastEqualsReference(ten_bits, ten_bits.render(29), unfiltered, "10 bits, unfiltered");
}
