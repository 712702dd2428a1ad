// The pattern sequencer against a fake projector + camera with display latency: the captured
// set, decoded by the project's decoder, must give the exact projector stripe of every pixel
// when settle_frames covers the latency, and must not when it does not.
#include <body_scan_driver/hw/pattern_sequencer.h>
#include <body_scan_driver/stripe_decoder.h>
#include <gtest/gtest.h>

#include "fake_hardware.h"

using namespace body_scan_driver;
using namespace body_scan_driver::hw;

namespace {

// Pixels whose decoded stripe differs from the projector stripe they look at (the fake camera
// sees the projector image pixel for pixel).
int wrongStripes(const PatternCapture& capture, const PatternLayout& layout) {
  DecoderParams params;
  params.subpixel = false;
  params.axis = DecoderParams::StripeAxis::kAlongRows;
  StripeImage decoded;
  StripeDecoder(layout, params).decode(capture.frames, decoded);
  int wrong = 0;
  for (int v = 0; v < decoded.stripe.rows; ++v)
    for (int u = 0; u < decoded.stripe.cols; ++u)
      wrong += decoded.stripe(v, u) !=
               stripeOfProjectorPixel(v, decoded.stripe.rows, layout.stripeCount());
  return wrong;
}

}  // namespace

TEST(RenderPatternFrame, LightsExactlyTheStripesTheLayoutSays) {
  const PatternLayout layout(6, true);
  const cv::Size size(80, 200);
  for (int frame = 0; frame < layout.frameCount(); ++frame) {
    const cv::Mat1b image = renderPatternFrame(layout, frame, size, StripeDirection::kAlongRows);
    for (int v = 0; v < size.height; ++v) {
      const int stripe = v * 64 / 200;
      const uint8_t expected = layout.lights(frame, stripe) ? 255 : 0;
      EXPECT_EQ(image(v, 0), expected) << "frame " << frame << " row " << v;
      EXPECT_EQ(cv::countNonZero(image.row(v) != expected), 0);
    }
  }
  const cv::Mat1b columns =
      renderPatternFrame(layout, layout.patternFrame(0), size, StripeDirection::kAlongColumns);
  EXPECT_EQ(columns(0, 0), 0);  // most significant bit: first half dark, second lit
  EXPECT_EQ(columns(0, 79), 255);
}

TEST(RenderPatternFrame, StripesShareTheAxisEvenly) {
  std::vector<int> widths(256, 0);
  for (int p = 0; p < 1080; ++p) ++widths.at(stripeOfProjectorPixel(p, 1080, 256));
  for (int width : widths) {
    EXPECT_GE(width, 4);
    EXPECT_LE(width, 5);
  }
}

TEST(RenderPatternFrame, RefusesMoreStripesThanProjectorPixels) {
  try {
    renderPatternFrame(PatternLayout(9, true), 0, {640, 480}, StripeDirection::kAlongRows);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("lower pattern bits"), std::string::npos) << e.what();
  }
}

TEST(PatternSequencer, SettleFramesCoveringTheLatencyDecodeEveryPixelExactly) {
  for (bool inverse : {true, false}) {
    auto screen = std::make_shared<fakes::FakeScreen>();
    screen->latency_frames = 2;
    fakes::FakeProjector projector(screen);
    fakes::FakeCamera camera(screen);
    camera.startStreaming();
    const PatternLayout layout(7, inverse);
    SequencerSettings settings;
    settings.settle_frames = 2;
    const PatternSequencer sequencer(layout, screen->size, settings);
    const PatternCapture capture = sequencer.capture(projector, camera);

    ASSERT_EQ(static_cast<int>(capture.frames.size()), layout.frameCount());
    EXPECT_EQ(screen->frames_produced, layout.frameCount() * 3);  // settle + 1 per frame
    EXPECT_EQ(capture.texture.type(), CV_8UC3);
    EXPECT_EQ(capture.texture.at<cv::Vec3b>(0, 0), cv::Vec3b(208, 208, 208));  // lit: 30+0.7*255
    EXPECT_EQ(wrongStripes(capture, layout), 0) << "inverse frames " << inverse;
    // The projector is left dark after the set.
    EXPECT_EQ(cv::countNonZero(screen->history.back().image), 0);
  }
}

TEST(PatternSequencer, TooFewSettleFramesCaptureTheWrongPatterns) {
  auto screen = std::make_shared<fakes::FakeScreen>();
  screen->latency_frames = 2;
  fakes::FakeProjector projector(screen);
  fakes::FakeCamera camera(screen);
  camera.startStreaming();
  const PatternLayout layout(7, true);
  SequencerSettings settings;
  settings.settle_frames = 1;
  const PatternSequencer sequencer(layout, screen->size, settings);
  const int wrong = wrongStripes(sequencer.capture(projector, camera), layout);
  EXPECT_GT(wrong, screen->size.area() / 2) << "each frame shows the previous pattern";
}

TEST(PatternSequencer, RejectsNegativeSettleFrames) {
  SequencerSettings settings;
  settings.settle_frames = -1;
  EXPECT_THROW(PatternSequencer(PatternLayout(4, true), {64, 64}, settings), std::invalid_argument);
}

TEST(MeasureDisplayLatency, CountsTheFramesBeforeTheFlashIsSeen) {
  for (int latency = 0; latency <= 4; ++latency) {
    auto screen = std::make_shared<fakes::FakeScreen>();
    screen->latency_frames = latency;
    fakes::FakeProjector projector(screen);
    fakes::FakeCamera camera(screen);
    camera.startStreaming();
    EXPECT_EQ(measureDisplayLatency(projector, camera, 10, 1.0), latency);
  }
}

TEST(MeasureDisplayLatency, NoFlashSeenIsAnErrorSayingWhatToCheck) {
  auto screen = std::make_shared<fakes::FakeScreen>();
  screen->latency_frames = 20;  // longer than we look
  fakes::FakeProjector projector(screen);
  fakes::FakeCamera camera(screen);
  camera.startStreaming();
  try {
    measureDisplayLatency(projector, camera, 10, 1.0);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("does not see the projector"), std::string::npos);
  }
}
