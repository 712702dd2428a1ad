// backend:=usb: a real pair (docs/REAL_RIG.md): its device ids from the pair's
// `device:` map in ~rig_file, overridden by private parameters; its own poll timer (reconnects,
// hot-plug) and dynamic_reconfigure server (exposure, gain, settle frames).
#include <body_scan_driver/UsbPairSettingsConfig.h>
#include <body_scan_driver/hw/rig_device_ids.h>
#include <body_scan_driver/hw/usb_pair_device.h>
#include <body_scan_driver/ros/pair_backend.h>
#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>

#include <pluginlib/class_list_macros.hpp>

namespace body_scan_driver {
namespace {

// The private parameter `key` if set, else the rig file's id, else `fallback`.
template <typename T>
T deviceParam(ros::NodeHandle& pnh, const std::string& key, const std::optional<T>& from_rig,
              const T& fallback) {
  T value;
  if (pnh.getParam(key, value)) return value;
  return from_rig ? *from_rig : fallback;
}

// Parameters of backend:=usb. Throws naming a missing or malformed id.
hw::UsbPairSettings usbSettings(ros::NodeHandle& pnh, const std::string& pair_id) {
  const std::string rig_file = pnh.param<std::string>("rig_file", "");
  const hw::PairDeviceIds rig =
      rig_file.empty() ? hw::PairDeviceIds{} : hw::loadPairDeviceIds(rig_file, pair_id);
  hw::UsbPairSettings settings;
  settings.pair_id = pair_id;
  const std::string camera_id = deviceParam<std::string>(pnh, "camera_id", rig.camera_id, "");
  if (camera_id.empty())
    throw std::invalid_argument(
        "no camera configured for pair " + pair_id + ": set ~camera_id" +
        (rig_file.empty() ? std::string()
                          : " or `device: {camera_id: ...}` of the pair in " + rig_file) +
        " (vendor:product; rosrun body_scan_driver list_devices)");
  settings.camera = hw::UsbDeviceMatch::parse(
      camera_id, deviceParam<std::string>(pnh, "camera_serial", rig.camera_serial, ""));
  const std::string projector_id =
      deviceParam<std::string>(pnh, "projector_id", rig.projector_id, "");
  if (!projector_id.empty())
    settings.projector_usb = hw::UsbDeviceMatch::parse(
        projector_id, deviceParam<std::string>(pnh, "projector_serial", rig.projector_serial, ""));
  settings.projector_display =
      deviceParam<std::string>(pnh, "projector_display", rig.projector_display, ":0");
  settings.projector_screen = deviceParam<int>(pnh, "projector_screen", rig.projector_screen, -1);
  hw::UvcSettings& camera = settings.camera_settings;
  camera.format = pnh.param<std::string>("camera_format", camera.format);
  camera.width = pnh.param("camera_width", camera.width);
  camera.height = pnh.param("camera_height", camera.height);
  camera.fps = pnh.param("camera_fps", camera.fps);
  camera.exposure_ms = pnh.param("exposure_ms", camera.exposure_ms);
  camera.gain = pnh.param("gain", camera.gain);
  settings.sequencer.settle_frames = pnh.param("settle_frames", 2);
  settings.sequencer.frame_timeout_s = pnh.param("frame_timeout", 1.0);
  const std::string stripes = pnh.param<std::string>("stripes_along", "rows");
  if (stripes != "rows" && stripes != "columns")
    throw std::invalid_argument("stripes_along must be rows (vertical baseline) or columns");
  settings.sequencer.direction =
      stripes == "rows" ? hw::StripeDirection::kAlongRows : hw::StripeDirection::kAlongColumns;
  settings.bits = pnh.param("bits", 8);
  settings.inverse_frames = pnh.param("inverse_frames", true);
  settings.calibration_file = pnh.param<std::string>("calibration_file", "");
  settings.retry.initial_interval_s = pnh.param("retry_initial_interval", 0.5);
  settings.retry.max_interval_s = pnh.param("retry_max_interval", 10.0);
  return settings;
}

// A real pair with its ROS companions. They are members, so they stop (the timer waits for a
// running poll) before the device closes.
class RosUsbPair : public hw::UsbPairDevice {
 public:
  RosUsbPair(const hw::UsbPairSettings& settings, ros::NodeHandle& nh, ros::NodeHandle& pnh)
      : hw::UsbPairDevice(settings, hw::realHardware()),
        pair_id_(settings.pair_id),
        camera_settings_(settings.camera_settings),
        reconfigure_server_(pnh) {
    reconfigure_server_.setCallback(
        [this](const UsbPairSettingsConfig& config, uint32_t) { onReconfigure(config); });
    // Reconnects (DISCONNECTED/ERROR -> STREAMING) and hot-plug events happen here.
    poll_timer_ = nh.createWallTimer(ros::WallDuration(pnh.param("poll_period", 0.1)),
                                     [this](const ros::WallTimerEvent&) { pollAndLog(); });
  }

 private:
  // Logs each change of the connection state once (details on /diagnostics).
  void pollAndLog() {
    poll();
    const DeviceStatus now = status();
    if (now.state == last_logged_state_) return;
    last_logged_state_ = now.state;
    if (now.level == DeviceStatus::Level::kError)
      ROS_ERROR("[%s] %s: %s", pair_id_.c_str(), now.state.c_str(), now.message.c_str());
    else
      ROS_INFO("[%s] %s: %s", pair_id_.c_str(), now.state.c_str(), now.message.c_str());
  }

  void onReconfigure(const UsbPairSettingsConfig& config) {
    hw::UvcSettings camera = camera_settings_;
    camera.exposure_ms = config.exposure_ms;
    camera.gain = config.gain;
    try {
      applySettings(camera, config.settle_frames);
      camera_settings_ = camera;
    } catch (const std::exception& e) {
      ROS_ERROR("[%s] settings not applied: %s", pair_id_.c_str(), e.what());
    }
  }

  std::string pair_id_, last_logged_state_;
  hw::UvcSettings camera_settings_;
  dynamic_reconfigure::Server<UsbPairSettingsConfig> reconfigure_server_;
  ros::WallTimer poll_timer_;
};

}  // namespace

class UsbPairBackend : public PairBackend {
 public:
  std::unique_ptr<PairDevice> open(ros::NodeHandle& nh, ros::NodeHandle& pnh,
                                   const std::string& pair_id) override {
    return std::make_unique<RosUsbPair>(usbSettings(pnh, pair_id), nh, pnh);
  }
};

}  // namespace body_scan_driver

PLUGINLIB_EXPORT_CLASS(body_scan_driver::UsbPairBackend, body_scan_driver::PairBackend)
