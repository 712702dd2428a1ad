// A real projector-camera pair behind the PairDevice interface: a UVC camera found
// on USB by vendor:product/serial, a projector attached as an X display (optionally also
// required on USB, for vendor projectors), the pattern sequencer between them, and the
// connection state machine that keeps reconnecting. Construction never fails for a missing
// device: status() reports ERROR with the missing device and the fix, poll() retries.
#pragma once

#include <body_scan_driver/hw/pair_connection.h>
#include <body_scan_driver/hw/pattern_sequencer.h>
#include <body_scan_driver/hw/usb_bus.h>
#include <body_scan_driver/hw/uvc_camera.h>
#include <body_scan_driver/pair_device.h>

#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace body_scan_driver::hw {

struct UsbPairSettings {
  std::string pair_id = "pole_a/pair_1";
  UsbDeviceMatch camera;                        // the UVC camera
  std::optional<UsbDeviceMatch> projector_usb;  // a vendor projector's USB id; none: DIY
  std::string projector_display;                // X display ("" = $DISPLAY)
  int projector_screen = -1;                    // -1: the display's default screen
  UvcSettings camera_settings;
  SequencerSettings sequencer;
  int bits = 8;
  bool inverse_frames = true;
  // Camera model announced in camera_info until the pair is calibrated: a calibration file,
  // or (empty) a nominal pinhole of the camera resolution with focal length nominal_focal_px.
  std::string calibration_file;
  double nominal_focal_px = 810;
  RetryPolicy retry;
};

// How the device reaches its hardware: libusb + libuvc + X11 (realHardware), or fakes.
struct HardwareAccess {
  std::unique_ptr<UsbBus> bus;
  std::function<std::unique_ptr<StreamingCamera>(const UsbDeviceMatch&, const UvcSettings&)>
      open_camera;
  std::function<std::unique_ptr<PatternProjector>(const std::string& display, int screen)>
      open_projector;
  std::function<double()> now_s;  // a monotonic clock in seconds
};
HardwareAccess realHardware();

class UsbPairDevice : public PairDevice {
 public:
  // Throws std::invalid_argument only for bad settings (and a bad calibration file).
  UsbPairDevice(const UsbPairSettings& settings, HardwareAccess hardware);
  ~UsbPairDevice() override;

  PatternCapture capture(uint32_t scan_id) override;  // throws unless STREAMING
  const PatternLayout& layout() const override { return layout_; }
  PinholeCamera camera() const override { return camera_model_; }
  void poll() override;
  DeviceStatus status() const override;

  // Run-time settings (dynamic_reconfigure): exposure and gain at once, settle frames from
  // the next capture.
  void applySettings(const UvcSettings& camera_settings, int settle_frames);
  ConnectionState state() const;

 private:
  void open();
  void startStreaming();
  void close();
  void updateStatus();
  std::string hardwareId() const;

  UsbPairSettings settings_;
  HardwareAccess hardware_;
  PatternLayout layout_;
  PinholeCamera camera_model_;
  std::unique_ptr<StreamingCamera> camera_;
  std::unique_ptr<PatternProjector> projector_;
  std::unique_ptr<PatternSequencer> sequencer_;
  PairConnection connection_;
  bool bus_changed_ = false;
  std::mutex device_mutex_;  // poll() and capture(): one at a time

  mutable std::mutex status_mutex_;
  DeviceStatus status_;
};

}  // namespace body_scan_driver::hw
