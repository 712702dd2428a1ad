#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/hw/projector_window.h>
#include <body_scan_driver/hw/usb_pair_device.h>

#include <chrono>
#include <cstdio>
#include <stdexcept>

namespace body_scan_driver::hw {
namespace {

const char* const kListDevicesHint =
    "`rosrun body_scan_driver list_devices` lists what is attached";

std::string fixed(double value, int decimals) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

PinholeCamera cameraModel(const UsbPairSettings& settings) {
  if (!settings.calibration_file.empty()) {
    PinholeCamera camera = loadCalibration(settings.calibration_file).camera;
    if (camera.width != settings.camera_settings.width ||
        camera.height != settings.camera_settings.height)
      throw std::invalid_argument(
          "calibration file " + settings.calibration_file + " is for " +
          std::to_string(camera.width) + "x" + std::to_string(camera.height) +
          " but the camera is set to stream " + std::to_string(settings.camera_settings.width) +
          "x" + std::to_string(settings.camera_settings.height));
    return camera;
  }
  PinholeCamera camera;
  camera.width = settings.camera_settings.width;
  camera.height = settings.camera_settings.height;
  camera.alpha = camera.beta = settings.nominal_focal_px;
  camera.u0 = (camera.width - 1) / 2.0;
  camera.v0 = (camera.height - 1) / 2.0;
  camera.k1 = camera.k2 = 0;
  return camera;
}

}  // namespace

HardwareAccess realHardware() {
  HardwareAccess access;
  access.bus = makeLibusbBus();
  access.open_camera = [](const UsbDeviceMatch& match, const UvcSettings& settings) {
    return std::unique_ptr<StreamingCamera>(new UvcCamera(match, settings));
  };
  access.open_projector = [](const std::string& display, int screen) {
    return std::unique_ptr<PatternProjector>(new ProjectorWindow(display, screen));
  };
  access.now_s = [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  };
  return access;
}

UsbPairDevice::UsbPairDevice(const UsbPairSettings& settings, HardwareAccess hardware)
    : settings_(settings),
      hardware_(std::move(hardware)),
      layout_(settings.bits, settings.inverse_frames),
      camera_model_(cameraModel(settings)),
      connection_({[this] { open(); }, [this] { startStreaming(); }, [this] { close(); }},
                  settings.retry) {
  if (!hardware_.bus || !hardware_.open_camera || !hardware_.open_projector || !hardware_.now_s)
    throw std::invalid_argument("UsbPairDevice needs a bus, camera and projector openers, a clock");
  if (settings_.sequencer.settle_frames < 0)
    throw std::invalid_argument("settle_frames must be >= 0 (camera frames to skip)");
  hardware_.bus->setChangeCallback([this] { bus_changed_ = true; });
  updateStatus();
}

UsbPairDevice::~UsbPairDevice() {
  std::lock_guard<std::mutex> lock(device_mutex_);
  connection_.disconnect();
}

std::string UsbPairDevice::hardwareId() const {
  std::string id = "uvc " + settings_.camera.describe();
  if (settings_.projector_usb) id += " + projector " + settings_.projector_usb->describe();
  return id + " + display '" + settings_.projector_display + "'";
}

void UsbPairDevice::open() {
  const std::string pair = "pair " + settings_.pair_id + ": ";
  std::vector<UsbDeviceInfo> devices;
  try {
    devices = hardware_.bus->devices();
  } catch (const std::exception& e) {
    throw std::runtime_error(pair + "cannot look for camera " + settings_.camera.describe() + ": " +
                             e.what() + "; " + kListDevicesHint);
  }
  const auto missing = [&](const std::string& what, const UsbDeviceMatch& match) {
    return std::runtime_error(pair + what + " " + match.describe() + " not found on USB (" +
                              std::to_string(devices.size()) +
                              " devices attached): check cable and power, and the configured "
                              "vendor:product/serial; " +
                              kListDevicesHint);
  };
  if (!findDevice(devices, settings_.camera)) throw missing("camera", settings_.camera);
  if (settings_.projector_usb && !findDevice(devices, *settings_.projector_usb))
    throw missing("projector", *settings_.projector_usb);
  camera_ = hardware_.open_camera(settings_.camera, settings_.camera_settings);
  projector_ = hardware_.open_projector(settings_.projector_display, settings_.projector_screen);
  sequencer_ =
      std::make_unique<PatternSequencer>(layout_, projector_->resolution(), settings_.sequencer);
}

void UsbPairDevice::startStreaming() { camera_->startStreaming(); }

void UsbPairDevice::close() {
  if (camera_) camera_->stopStreaming();
  sequencer_.reset();
  projector_.reset();
  camera_.reset();
}

void UsbPairDevice::poll() {
  std::lock_guard<std::mutex> lock(device_mutex_);
  hardware_.bus->handleEvents();  // may set bus_changed_
  const double now = hardware_.now_s();
  if (bus_changed_) {
    bus_changed_ = false;
    if (connection_.state() == ConnectionState::kStreaming) {
      std::vector<UsbDeviceInfo> devices;
      try {
        devices = hardware_.bus->devices();
      } catch (const std::exception&) {
      }
      if (!findDevice(devices, settings_.camera))
        connection_.reportFailure("pair " + settings_.pair_id + ": camera " +
                                      settings_.camera.describe() + " was unplugged; " +
                                      kListDevicesHint,
                                  now);
    } else {
      connection_.deviceArrived();
    }
  }
  connection_.poll(now);
  updateStatus();
}

PatternCapture UsbPairDevice::capture(uint32_t /*scan_id*/) {
  std::lock_guard<std::mutex> lock(device_mutex_);
  if (connection_.state() != ConnectionState::kStreaming)
    throw std::runtime_error(
        std::string("not streaming (") + toString(connection_.state()) + ")" +
        (connection_.lastError().empty() ? "" : ": " + connection_.lastError()));
  try {
    PatternCapture capture = sequencer_->capture(*projector_, *camera_);
    updateStatus();
    return capture;
  } catch (const std::exception& e) {
    connection_.reportFailure(e.what(), hardware_.now_s());
    updateStatus();
    throw;
  }
}

void UsbPairDevice::applySettings(const UvcSettings& camera_settings, int settle_frames) {
  if (settle_frames < 0)
    throw std::invalid_argument("settle_frames must be >= 0 (camera frames to skip)");
  std::lock_guard<std::mutex> lock(device_mutex_);
  settings_.camera_settings = camera_settings;
  settings_.sequencer.settle_frames = settle_frames;
  if (sequencer_) sequencer_->setSettleFrames(settle_frames);
  if (camera_) camera_->applySettings(camera_settings);
  updateStatus();
}

ConnectionState UsbPairDevice::state() const {
  std::lock_guard<std::mutex> lock(status_mutex_);
  return status_.state == "STREAMING"   ? ConnectionState::kStreaming
         : status_.state == "CONNECTED" ? ConnectionState::kConnected
         : status_.state == "ERROR"     ? ConnectionState::kError
                                        : ConnectionState::kDisconnected;
}

void UsbPairDevice::updateStatus() {
  DeviceStatus status;
  status.hardware_id = hardwareId();
  const ConnectionState state = connection_.state();
  status.state = toString(state);
  switch (state) {
    case ConnectionState::kStreaming:
      status.level = DeviceStatus::Level::kOk;
      status.message = "streaming";
      break;
    case ConnectionState::kError:
      status.level = DeviceStatus::Level::kError;
      status.message = connection_.lastError() + " (retry " +
                       std::to_string(connection_.failedAttempts()) + " in " +
                       fixed(connection_.retryInterval(), 2) + " s)";
      break;
    default:
      status.level = DeviceStatus::Level::kWarn;
      status.message = std::string("not streaming yet (") + toString(state) + ")";
  }
  if (camera_) {
    const StreamStatistics stats = camera_->statistics();
    status.frame_rate_hz = stats.frame_rate_hz;
    status.dropped_frames = stats.dropped_frames;
  }
  status.values = {
      {"connection attempts", std::to_string(connection_.totalAttempts())},
      {"failed attempts since last success", std::to_string(connection_.failedAttempts())},
      {"retry interval (s)", fixed(connection_.retryInterval(), 3)},
      {"settle frames", std::to_string(settings_.sequencer.settle_frames)},
      {"pattern bits", std::to_string(layout_.bits())},
  };
  std::lock_guard<std::mutex> lock(status_mutex_);
  status_ = std::move(status);
}

DeviceStatus UsbPairDevice::status() const {
  std::lock_guard<std::mutex> lock(status_mutex_);
  return status_;
}

}  // namespace body_scan_driver::hw
