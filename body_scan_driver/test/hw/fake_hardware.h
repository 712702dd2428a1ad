// Fakes of the hardware backend's interfaces: a USB bus whose devices tests plug and unplug,
// and a projector + camera pair that models the projector's display latency in camera frames
// (a pattern shown when the camera had produced p frames appears in frames > p + latency).
#pragma once

#include <body_scan_driver/hw/pattern_sequencer.h>
#include <body_scan_driver/hw/usb_bus.h>
#include <body_scan_driver/hw/uvc_camera.h>

#include <memory>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace body_scan_driver::hw::fakes {

class FakeBus : public UsbBus {
 public:
  std::vector<UsbDeviceInfo> attached;
  bool hotplug = true;
  bool pending_change = false;
  std::function<void()> on_change;

  std::vector<UsbDeviceInfo> devices() override { return attached; }
  bool hasHotplug() const override { return hotplug; }
  void setChangeCallback(std::function<void()> callback) override { on_change = callback; }
  void handleEvents() override {
    if (hotplug && pending_change && on_change) on_change();
    pending_change = false;
  }
  void plug(const UsbDeviceInfo& device) {
    attached.push_back(device);
    pending_change = true;
  }
  void unplugAll() {
    attached.clear();
    pending_change = true;
  }
};

// What the projector shows and when, shared by the fake projector and the fake camera.
struct FakeScreen {
  cv::Size size{320, 240};
  int latency_frames = 1;  // camera frames before a shown pattern is seen
  long frames_produced = 0;
  struct Shown {
    cv::Mat image;
    long at_frame;
  };
  std::vector<Shown> history;
  bool connected = true;  // false: camera and projector fail as if unplugged

  cv::Mat visibleIn(long frame) const {
    cv::Mat visible(size, CV_8UC1, cv::Scalar(0));
    for (const Shown& shown : history)
      if (shown.at_frame + latency_frames < frame) visible = shown.image;
    return visible;
  }
};

class FakeProjector : public PatternProjector {
 public:
  explicit FakeProjector(std::shared_ptr<FakeScreen> screen) : screen_(std::move(screen)) {}
  cv::Size resolution() const override { return screen_->size; }
  void show(const cv::Mat& image) override {
    if (!screen_->connected) throw std::runtime_error("fake display gone");
    screen_->history.push_back({image.clone(), screen_->frames_produced});
  }

 private:
  std::shared_ptr<FakeScreen> screen_;
};

class FakeCamera : public StreamingCamera {
 public:
  explicit FakeCamera(std::shared_ptr<FakeScreen> screen) : screen_(std::move(screen)) {}
  void startStreaming() override {
    if (fail_start) throw std::runtime_error("fake camera refuses to stream");
    streaming = true;
  }
  void stopStreaming() override { streaming = false; }
  void applySettings(const UvcSettings& s) override { settings = s; }
  StreamStatistics statistics() const override {
    StreamStatistics stats;
    stats.frame_rate_hz = 30;
    stats.frames = static_cast<uint64_t>(screen_->frames_produced);
    stats.dropped_frames = 3;
    return stats;
  }
  void discardReceived() override {}
  cv::Mat nextFrame(double /*timeout_s*/) override {
    if (!streaming) throw std::runtime_error("fake camera is not streaming");
    if (!screen_->connected) throw std::runtime_error("fake camera delivered no frame");
    const long frame = ++screen_->frames_produced;
    // The surface reflects part of the projector's light over some ambient light.
    cv::Mat grey = screen_->visibleIn(frame) * 0.7 + 30, rgb;
    cv::cvtColor(grey, rgb, cv::COLOR_GRAY2RGB);
    return rgb;
  }

  bool fail_start = false;
  bool streaming = false;
  UvcSettings settings;
  // Expires when the device destroys (closes) this camera: a test holds a weak_ptr to it.
  std::shared_ptr<int> lifetime = std::make_shared<int>(0);

 private:
  std::shared_ptr<FakeScreen> screen_;
};

}  // namespace body_scan_driver::hw::fakes
