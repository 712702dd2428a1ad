// Projects a pattern set and captures it frame by frame. The projector and
// the camera are not hardware-synchronized, so the sequencer counts camera frames: after
// showing pattern frame k it discards `settle_frames` camera frames (the projector's display
// latency plus the camera's exposure of the old pattern) and keeps the next one.
#pragma once

#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/pair_device.h>

#include <cstdint>
#include <opencv2/core/mat.hpp>

namespace body_scan_driver::hw {

// Shows full-screen images (ProjectorWindow, or a fake in tests).
class PatternProjector {
 public:
  virtual ~PatternProjector() = default;
  virtual cv::Size resolution() const = 0;
  // Shows `image` (CV_8UC1 of resolution()) until the next call; returns once it was sent to
  // the display. Throws std::runtime_error if the display is gone.
  virtual void show(const cv::Mat& image) = 0;
};

// A camera delivering a continuous stream of frames (UvcCamera, or a fake in tests).
class FrameCamera {
 public:
  virtual ~FrameCamera() = default;
  // Drops the frames received so far: the next frame returned arrives after this call. The
  // sequencer counts frames from the moment a pattern was shown.
  virtual void discardReceived() = 0;
  // The next frame of the stream (CV_8UC3 RGB), waiting at most timeout_s for it. Throws
  // std::runtime_error on timeout or device failure.
  virtual cv::Mat nextFrame(double timeout_s) = 0;
};

// Which projector axis the stripe index runs along: rows for the pole's vertical baseline
// (stripes are horizontal bands), columns for a horizontal baseline.
enum class StripeDirection { kAlongRows, kAlongColumns };

// Projector pixel -> stripe: the `stripeCount()` stripes split the axis into equal bands,
// stripe i covering [i * n / stripes, (i + 1) * n / stripes) of the n pixels.
int stripeOfProjectorPixel(int pixel, int pixels_along_axis, int stripe_count);

// Pattern frame `frame` of `layout` rendered for a projector of `size`: 255 where the frame
// lights the stripe (PatternLayout::lights), 0 elsewhere.
cv::Mat renderPatternFrame(const PatternLayout& layout, int frame, cv::Size size,
                           StripeDirection direction);

struct SequencerSettings {
  int settle_frames = 2;         // camera frames discarded after every pattern change
  double frame_timeout_s = 1.0;  // per camera frame
  StripeDirection direction = StripeDirection::kAlongRows;
};

class PatternSequencer {
 public:
  // Pre-renders every pattern frame for `projector_size`.
  PatternSequencer(const PatternLayout& layout, cv::Size projector_size,
                   const SequencerSettings& settings);

  // Shows frames 0..frameCount()-1 in PatternLayout order and keeps camera frame settle+1 after
  // each: frames become CV_8UC1 (grey), the texture is the all-lit frame in RGB. Leaves the
  // projector dark. Throws std::runtime_error from the camera or the projector.
  PatternCapture capture(PatternProjector& projector, FrameCamera& camera) const;

  const PatternLayout& layout() const { return layout_; }
  const SequencerSettings& settings() const { return settings_; }
  void setSettleFrames(int settle_frames);

 private:
  PatternLayout layout_;
  SequencerSettings settings_;
  std::vector<cv::Mat> patterns_;
  cv::Mat dark_;
};

// The projector's display latency in camera frames, the settle_frames a pair needs (tool:
// measure_projector_latency). Shows black until the camera sees it, then white, and counts
// the frames after the flash that still show black: a frame sees the flash when its mean
// grey level rises more than half way from the black level to the final white level.
// Throws std::runtime_error if no flash is seen within max_frames or the contrast is too low.
int measureDisplayLatency(PatternProjector& projector, FrameCamera& camera, int max_frames,
                          double frame_timeout_s);

}  // namespace body_scan_driver::hw
