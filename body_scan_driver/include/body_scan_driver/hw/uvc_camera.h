// A UVC camera through libuvc: opens the configured vendor:product/serial,
// streams at a chosen format and resolution, and keeps exposure and gain fixed (auto-exposure
// off), since an exposure that adapts between pattern frames would corrupt every bit decision.
// libuvc headers stay in the .cpp.
#pragma once

#include <body_scan_driver/hw/pattern_sequencer.h>
#include <body_scan_driver/hw/usb_bus.h>

#include <cstdint>
#include <memory>
#include <string>

namespace body_scan_driver::hw {

struct UvcSettings {
  std::string format = "yuyv";  // "yuyv" or "mjpeg"
  int width = 640, height = 480, fps = 30;
  double exposure_ms = 10.0;  // fixed exposure time; UVC counts it in 100 us steps
  int gain = 0;               // device units
};

struct StreamStatistics {
  double frame_rate_hz = 0;     // measured from frame arrivals
  uint64_t frames = 0;          // received since streaming started
  uint64_t dropped_frames = 0;  // gaps in the device's frame numbers + frames never consumed
};

// A camera the pair device can start, stop and tune: UvcCamera, or a fake in tests.
class StreamingCamera : public FrameCamera {
 public:
  virtual void startStreaming() = 0;  // throws std::runtime_error naming the problem
  virtual void stopStreaming() = 0;
  // Exposure and gain apply at once; format and resolution at the next startStreaming().
  virtual void applySettings(const UvcSettings& settings) = 0;
  virtual StreamStatistics statistics() const = 0;
};

class UvcCamera : public StreamingCamera {
 public:
  // Opens the device; throws std::runtime_error naming match.describe() and the fix.
  UvcCamera(const UsbDeviceMatch& match, const UvcSettings& settings);
  ~UvcCamera() override;
  UvcCamera(const UvcCamera&) = delete;
  UvcCamera& operator=(const UvcCamera&) = delete;

  void startStreaming() override;  // throws if the format/resolution/rate is not offered
  void stopStreaming() override;
  void applySettings(const UvcSettings& settings) override;
  void discardReceived() override;
  cv::Mat nextFrame(double timeout_s) override;
  StreamStatistics statistics() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace body_scan_driver::hw
