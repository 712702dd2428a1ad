#include <body_scan_driver/hw/uvc_camera.h>
#include <libuvc/libuvc.h>

#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <stdexcept>

namespace body_scan_driver::hw {
namespace {

constexpr size_t kMaxQueuedFrames = 8;     // older frames are dropped (and counted)
constexpr uint8_t kUvcManualExposure = 1;  // UVC CT_AE_MODE: 1 manual, 2 auto, 8 aperture prio.

std::string uvcError(const std::string& what, uvc_error_t error) {
  return what + ": " + uvc_strerror(error);
}

}  // namespace

struct UvcCamera::Impl {
  UsbDeviceMatch match;
  UvcSettings settings;
  uvc_context_t* context = nullptr;
  uvc_device_t* device = nullptr;
  uvc_device_handle_t* handle = nullptr;
  bool streaming = false;

  mutable std::mutex mutex;
  std::condition_variable frame_ready;
  std::deque<cv::Mat> queue;
  StreamStatistics stats;
  bool have_sequence = false;
  uint32_t last_sequence = 0;
  std::chrono::steady_clock::time_point last_arrival;

  void applyExposureAndGain() {
    if (uvc_error_t e = uvc_set_ae_mode(handle, kUvcManualExposure); e != UVC_SUCCESS)
      throw std::runtime_error(uvcError("camera " + match.describe() +
                                            " does not accept manual exposure (needed for "
                                            "patterns)",
                                        e));
    const auto exposure_100us = static_cast<uint32_t>(std::max(1.0, settings.exposure_ms * 10));
    if (uvc_error_t e = uvc_set_exposure_abs(handle, exposure_100us); e != UVC_SUCCESS)
      throw std::runtime_error(uvcError("camera " + match.describe() + ": exposure", e));
    // Gain is optional in UVC: cameras without it keep their fixed gain.
    uvc_set_gain(handle, static_cast<uint16_t>(std::max(0, settings.gain)));
  }

  // libuvc's streaming thread: convert to RGB and queue.
  static void onFrame(uvc_frame_t* frame, void* user) {
    auto* self = static_cast<Impl*>(user);
    uvc_frame_t* rgb = uvc_allocate_frame(static_cast<size_t>(frame->width) * frame->height * 3);
    if (!rgb) return;
    const bool converted = uvc_any2rgb(frame, rgb) == UVC_SUCCESS;
    cv::Mat image;
    if (converted)
      image = cv::Mat(static_cast<int>(rgb->height), static_cast<int>(rgb->width), CV_8UC3,
                      rgb->data, rgb->step)
                  .clone();
    uvc_free_frame(rgb);
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> lock(self->mutex);
    StreamStatistics& s = self->stats;
    if (self->have_sequence && frame->sequence > self->last_sequence + 1)
      s.dropped_frames += frame->sequence - self->last_sequence - 1;
    if (s.frames > 0) {
      const double dt = std::chrono::duration<double>(now - self->last_arrival).count();
      if (dt > 0)
        s.frame_rate_hz = s.frame_rate_hz == 0 ? 1 / dt : 0.9 * s.frame_rate_hz + 0.1 / dt;
    }
    self->have_sequence = true;
    self->last_sequence = frame->sequence;
    self->last_arrival = now;
    ++s.frames;
    if (!converted) {
      ++s.dropped_frames;
      return;
    }
    self->queue.push_back(std::move(image));
    if (self->queue.size() > kMaxQueuedFrames) {
      self->queue.pop_front();
      ++s.dropped_frames;
    }
    self->frame_ready.notify_one();
  }
};

UvcCamera::UvcCamera(const UsbDeviceMatch& match, const UvcSettings& settings) : impl_(new Impl) {
  impl_->match = match;
  impl_->settings = settings;
  if (uvc_error_t e = uvc_init(&impl_->context, nullptr); e != UVC_SUCCESS)
    throw std::runtime_error(uvcError("libuvc could not start", e));
  const char* serial = match.serial.empty() ? nullptr : match.serial.c_str();
  if (uvc_error_t e = uvc_find_device(impl_->context, &impl_->device, match.vendor_id,
                                      match.product_id, serial);
      e != UVC_SUCCESS) {
    uvc_exit(impl_->context);
    throw std::runtime_error(uvcError("no UVC camera " + match.describe() +
                                          " (rosrun body_scan_driver list_devices shows what is "
                                          "attached)",
                                      e));
  }
  if (uvc_error_t e = uvc_open(impl_->device, &impl_->handle); e != UVC_SUCCESS) {
    uvc_unref_device(impl_->device);
    uvc_exit(impl_->context);
    throw std::runtime_error(uvcError("cannot open camera " + match.describe() +
                                          " (permissions: install udev/99-body-scan.rules)",
                                      e));
  }
}

UvcCamera::~UvcCamera() {
  stopStreaming();
  if (impl_->handle) uvc_close(impl_->handle);
  if (impl_->device) uvc_unref_device(impl_->device);
  if (impl_->context) uvc_exit(impl_->context);
}

void UvcCamera::startStreaming() {
  if (impl_->streaming) return;
  const UvcSettings& s = impl_->settings;
  const uvc_frame_format format =
      s.format == "mjpeg" ? UVC_FRAME_FORMAT_MJPEG : UVC_FRAME_FORMAT_YUYV;
  if (s.format != "mjpeg" && s.format != "yuyv")
    throw std::invalid_argument("camera format '" + s.format + "': use yuyv or mjpeg");
  uvc_stream_ctrl_t control;
  if (uvc_error_t e = uvc_get_stream_ctrl_format_size(impl_->handle, &control, format, s.width,
                                                      s.height, s.fps);
      e != UVC_SUCCESS)
    throw std::runtime_error(uvcError(
        "camera " + impl_->match.describe() + " does not offer " + s.format + " " +
            std::to_string(s.width) + "x" + std::to_string(s.height) + " at " +
            std::to_string(s.fps) + " fps (list its modes with `v4l2-ctl --list-formats-ext`)",
        e));
  impl_->applyExposureAndGain();
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->queue.clear();
    impl_->stats = {};
    impl_->have_sequence = false;
  }
  if (uvc_error_t e = uvc_start_streaming(impl_->handle, &control, &Impl::onFrame, impl_.get(), 0);
      e != UVC_SUCCESS)
    throw std::runtime_error(
        uvcError("camera " + impl_->match.describe() + ": start streaming", e));
  impl_->streaming = true;
}

void UvcCamera::stopStreaming() {
  if (!impl_->streaming) return;
  uvc_stop_streaming(impl_->handle);
  impl_->streaming = false;
}

void UvcCamera::applySettings(const UvcSettings& settings) {
  impl_->settings = settings;
  if (impl_->streaming) impl_->applyExposureAndGain();
}

void UvcCamera::discardReceived() {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->queue.clear();
}

cv::Mat UvcCamera::nextFrame(double timeout_s) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  if (!impl_->frame_ready.wait_for(lock, std::chrono::duration<double>(timeout_s),
                                   [this] { return !impl_->queue.empty(); }))
    throw std::runtime_error("camera " + impl_->match.describe() + " delivered no frame within " +
                             std::to_string(timeout_s) + " s (unplugged?)");
  cv::Mat frame = std::move(impl_->queue.front());
  impl_->queue.pop_front();
  return frame;
}

StreamStatistics UvcCamera::statistics() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->stats;
}

}  // namespace body_scan_driver::hw
