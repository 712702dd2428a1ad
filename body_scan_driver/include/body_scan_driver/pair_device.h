// One projector-camera pair as the driver sees it, whatever is behind it: a real pair (usb
// backend) or the virtual pair (sim backend, which also implements simulator_control.h); the
// velodyne driver's Input/InputSocket/InputPCAP split.
#pragma once

#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/pair_model.h>

#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <string>
#include <utility>
#include <vector>

namespace body_scan_driver {

struct PatternCapture {
  std::vector<cv::Mat> frames;  // CV_8UC1 in PatternLayout order
  cv::Mat texture;              // CV_8UC3 RGB
};

// Health of a device for /diagnostics: what it is, its connection state, and why.
struct DeviceStatus {
  enum class Level { kOk, kWarn, kError };
  Level level = Level::kOk;
  std::string hardware_id;  // e.g. "simulator" or "uvc 046d:0825/SERIAL + display :0.0"
  std::string state;        // e.g. STREAMING, ERROR
  std::string message;      // one line: what is wrong and how to fix it, or "streaming"
  double frame_rate_hz = 0;
  uint64_t dropped_frames = 0;
  std::vector<std::pair<std::string, std::string>> values;  // further key/values
};

class PairDevice {
 public:
  virtual ~PairDevice() = default;
  // Projects the pattern sequence and captures it. Throws std::runtime_error on device failure.
  virtual PatternCapture capture(uint32_t scan_id) = 0;
  virtual const PatternLayout& layout() const = 0;
  // The camera model to announce in camera_info (from the factory or a calibration).
  virtual PinholeCamera camera() const = 0;
  // Called periodically by whoever runs the device (the usb backend's poll timer, a test):
  // hardware reconnects here. Must not throw.
  virtual void poll() {}
  // Thread-safe: may be called while capture() runs. Not pure, so that devices written before
  // diagnostics existed (test doubles, replay) still compile; they report no health.
  virtual DeviceStatus status() const {
    DeviceStatus status;
    status.hardware_id = "none";
    status.state = "UNKNOWN";
    status.message = "this device reports no health";
    return status;
  }
};

}  // namespace body_scan_driver
