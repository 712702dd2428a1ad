#include <body_scan_driver/hw/pattern_sequencer.h>

#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace body_scan_driver::hw {

int stripeOfProjectorPixel(int pixel, int pixels_along_axis, int stripe_count) {
  return static_cast<int>(static_cast<int64_t>(pixel) * stripe_count / pixels_along_axis);
}

cv::Mat renderPatternFrame(const PatternLayout& layout, int frame, cv::Size size,
                           StripeDirection direction) {
  if (size.width <= 0 || size.height <= 0)
    throw std::invalid_argument("projector resolution must be positive");
  const bool along_rows = direction == StripeDirection::kAlongRows;
  const int pixels = along_rows ? size.height : size.width;
  if (pixels < layout.stripeCount())
    throw std::invalid_argument("the projector has " + std::to_string(pixels) +
                                " pixels along the stripe axis, fewer "
                                "than the " +
                                std::to_string(layout.stripeCount()) + " stripes of " +
                                std::to_string(layout.bits()) + " bits: lower pattern bits");
  cv::Mat1b image(size, uint8_t{0});
  for (int p = 0; p < pixels; ++p) {
    const uint8_t level =
        layout.lights(frame, stripeOfProjectorPixel(p, pixels, layout.stripeCount())) ? 255 : 0;
    if (along_rows)
      image.row(p).setTo(level);
    else
      image.col(p).setTo(level);
  }
  return image;
}

PatternSequencer::PatternSequencer(const PatternLayout& layout, cv::Size projector_size,
                                   const SequencerSettings& settings)
    : layout_(layout), settings_(settings), dark_(projector_size, CV_8UC1, cv::Scalar(0)) {
  setSettleFrames(settings.settle_frames);
  for (int frame = 0; frame < layout_.frameCount(); ++frame)
    patterns_.push_back(renderPatternFrame(layout_, frame, projector_size, settings_.direction));
}

void PatternSequencer::setSettleFrames(int settle_frames) {
  if (settle_frames < 0)
    throw std::invalid_argument("settle_frames must be >= 0 (camera frames to skip)");
  settings_.settle_frames = settle_frames;
}

PatternCapture PatternSequencer::capture(PatternProjector& projector, FrameCamera& camera) const {
  PatternCapture capture;
  for (int frame = 0; frame < layout_.frameCount(); ++frame) {
    projector.show(patterns_[frame]);
    camera.discardReceived();
    // Frame counting: frames exposed while the old pattern was still up are dropped.
    for (int skip = 0; skip < settings_.settle_frames; ++skip)
      camera.nextFrame(settings_.frame_timeout_s);
    const cv::Mat rgb = camera.nextFrame(settings_.frame_timeout_s);
    if (rgb.type() != CV_8UC3)
      throw std::runtime_error("the camera delivered a frame that is not 8-bit RGB");
    if (!capture.frames.empty() && rgb.size() != capture.frames.front().size())
      throw std::runtime_error("the camera changed its resolution during a pattern set");
    cv::Mat grey;
    cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);
    capture.frames.push_back(grey);
    if (frame == PatternLayout::litFrame()) capture.texture = rgb.clone();
  }
  projector.show(dark_);
  return capture;
}

int measureDisplayLatency(PatternProjector& projector, FrameCamera& camera, int max_frames,
                          double frame_timeout_s) {
  const auto mean_grey = [&] {
    cv::Mat grey;
    cv::cvtColor(camera.nextFrame(frame_timeout_s), grey, cv::COLOR_RGB2GRAY);
    return cv::mean(grey)[0];
  };
  const cv::Size size = projector.resolution();
  projector.show(cv::Mat(size, CV_8UC1, cv::Scalar(0)));
  // Let black settle: as many frames as we would wait for the flash.
  for (int i = 0; i < max_frames; ++i) camera.nextFrame(frame_timeout_s);
  const double black = mean_grey();
  projector.show(cv::Mat(size, CV_8UC1, cv::Scalar(255)));
  camera.discardReceived();
  std::vector<double> levels;
  for (int i = 0; i < max_frames; ++i) levels.push_back(mean_grey());
  const double white = levels.back();
  if (white - black < 10)
    throw std::runtime_error("the camera does not see the projector's flash (black " +
                             std::to_string(black) + ", white " + std::to_string(white) +
                             " grey levels): point the camera at the "
                             "projected area, or raise max_frames if the latency is longer than " +
                             std::to_string(max_frames) + " frames");
  for (int i = 0; i < max_frames; ++i)
    if (levels[i] > (black + white) / 2) return i;
  return max_frames;  // unreachable: the last level is white
}

}  // namespace body_scan_driver::hw
