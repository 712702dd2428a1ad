// UsbPairDevice with a fake bus, camera, projector and clock: a missing device gives an ERROR
// status naming it and the fix and is retried with growing intervals; plugging it in (hot-plug
// or polling) brings the pair to STREAMING and its captures decode exactly; unplugging it
// while streaming goes back to ERROR.
#include <body_scan_driver/hw/usb_pair_device.h>
#include <body_scan_driver/stripe_decoder.h>
#include <gtest/gtest.h>

#include "fake_hardware.h"

using namespace body_scan_driver;
using namespace body_scan_driver::hw;

namespace {

const UsbDeviceInfo kCamera{0x1234, 0x5678, "NOSUCHCAM", 1, 7, true};

struct Rig {
  std::shared_ptr<fakes::FakeScreen> screen = std::make_shared<fakes::FakeScreen>();
  fakes::FakeBus* bus = nullptr;
  fakes::FakeCamera* camera = nullptr;  // the last one opened (dangling once it is closed)
  std::weak_ptr<int> camera_lifetime;   // expired once the device closed it
  int cameras_opened = 0;
  double now = 100.0;
  std::unique_ptr<UsbPairDevice> device;

  explicit Rig(bool hotplug) {
    UsbPairSettings settings;
    settings.pair_id = "pole_b/pair_2";
    settings.camera = UsbDeviceMatch::parse("1234:5678", "NOSUCHCAM");
    settings.camera_settings.width = screen->size.width;
    settings.camera_settings.height = screen->size.height;
    settings.bits = 6;
    settings.sequencer.settle_frames = 1;
    settings.retry = {0.5, 2.0, 8.0};
    HardwareAccess access;
    auto fake_bus = std::make_unique<fakes::FakeBus>();
    fake_bus->hotplug = hotplug;
    bus = fake_bus.get();
    access.bus = std::move(fake_bus);
    access.open_camera = [this](const UsbDeviceMatch& match, const UvcSettings&) {
      EXPECT_EQ(match.describe(), "1234:5678/NOSUCHCAM");
      auto fake = std::make_unique<fakes::FakeCamera>(screen);
      camera = fake.get();
      camera_lifetime = fake->lifetime;
      ++cameras_opened;
      return std::unique_ptr<StreamingCamera>(std::move(fake));
    };
    access.open_projector = [this](const std::string&, int) {
      return std::unique_ptr<PatternProjector>(new fakes::FakeProjector(screen));
    };
    access.now_s = [this] { return now; };
    device = std::make_unique<UsbPairDevice>(settings, std::move(access));
  }
};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(UsbPairDevice, MissingCameraIsAnErrorNamingItAndHowToListDevices) {
  Rig rig(true);
  rig.device->poll();
  const DeviceStatus status = rig.device->status();
  EXPECT_EQ(status.level, DeviceStatus::Level::kError);
  EXPECT_EQ(status.state, "ERROR");
  EXPECT_TRUE(contains(status.message, "camera 1234:5678/NOSUCHCAM not found")) << status.message;
  EXPECT_TRUE(contains(status.message, "rosrun body_scan_driver list_devices")) << status.message;
  EXPECT_TRUE(contains(status.hardware_id, "1234:5678/NOSUCHCAM")) << status.hardware_id;
  EXPECT_EQ(rig.cameras_opened, 0);
  try {
    rig.device->capture(1);
    FAIL() << "capture without a camera must throw";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), "not streaming (ERROR)")) << e.what();
    EXPECT_TRUE(contains(e.what(), "1234:5678/NOSUCHCAM")) << e.what();
  }
}

TEST(UsbPairDevice, RetriesWithGrowingIntervals) {
  Rig rig(false);
  std::vector<std::string> intervals;
  int attempts_seen = 0;
  for (int step = 0; step < 40; ++step, rig.now += 0.25) {
    rig.device->poll();
    const DeviceStatus status = rig.device->status();
    const int attempts = std::stoi(status.values.at(0).second);
    if (attempts != attempts_seen) intervals.push_back(status.values.at(2).second);
    attempts_seen = attempts;
  }
  // 10 s of polling: attempts at 0, 0.5, 1.5, 3.5, 7.5 s.
  EXPECT_EQ(intervals, (std::vector<std::string>{"0.500", "1.000", "2.000", "4.000", "8.000"}));
}

TEST(UsbPairDevice, HotplugArrivalStreamsAndCapturesDecodeExactly) {
  Rig rig(true);
  rig.device->poll();
  rig.now += 0.1;  // long before the scheduled retry
  rig.bus->plug(kCamera);
  rig.device->poll();
  ASSERT_EQ(rig.device->state(), ConnectionState::kStreaming) << rig.device->status().message;
  const DeviceStatus status = rig.device->status();
  EXPECT_EQ(status.level, DeviceStatus::Level::kOk);
  EXPECT_DOUBLE_EQ(status.frame_rate_hz, 30);
  EXPECT_EQ(status.dropped_frames, 3u);

  const PatternCapture capture = rig.device->capture(1);
  DecoderParams params;
  params.subpixel = false;
  params.axis = DecoderParams::StripeAxis::kAlongRows;
  StripeImage decoded;
  StripeDecoder(rig.device->layout(), params).decode(capture.frames, decoded);
  int wrong = 0;
  for (int v = 0; v < decoded.stripe.rows; ++v)
    for (int u = 0; u < decoded.stripe.cols; ++u)
      wrong += decoded.stripe(v, u) != stripeOfProjectorPixel(v, decoded.stripe.rows, 64);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(rig.device->camera().width, rig.screen->size.width);
}

TEST(UsbPairDevice, UnplugWhileStreamingIsAnErrorAndReconnectsWhenBack) {
  Rig rig(true);
  rig.bus->plug(kCamera);
  rig.device->poll();
  ASSERT_EQ(rig.device->state(), ConnectionState::kStreaming);
  rig.bus->unplugAll();
  rig.device->poll();
  EXPECT_EQ(rig.device->state(), ConnectionState::kError);
  EXPECT_TRUE(contains(rig.device->status().message, "was unplugged"));
  EXPECT_TRUE(rig.camera_lifetime.expired());  // closed (rig.camera dangles: not read)
  rig.bus->plug(kCamera);
  rig.device->poll();
  EXPECT_EQ(rig.device->state(), ConnectionState::kStreaming);
  EXPECT_EQ(rig.cameras_opened, 2);
}

TEST(UsbPairDevice, CaptureFailureWithoutHotplugIsAnErrorAndIsRetriedByPolling) {
  Rig rig(false);
  rig.bus->attached.push_back(kCamera);
  rig.device->poll();
  ASSERT_EQ(rig.device->state(), ConnectionState::kStreaming);
  rig.screen->connected = false;
  EXPECT_THROW(rig.device->capture(1), std::runtime_error);
  EXPECT_EQ(rig.device->state(), ConnectionState::kError);
  rig.screen->connected = true;
  rig.now += 0.5;
  rig.device->poll();
  EXPECT_EQ(rig.device->state(), ConnectionState::kStreaming);
  EXPECT_EQ(rig.device->capture(2).frames.size(), 14u);
}

TEST(UsbPairDevice, AppliesRuntimeSettingsToTheOpenCamera) {
  Rig rig(true);
  rig.bus->plug(kCamera);
  rig.device->poll();
  UvcSettings settings;
  settings.exposure_ms = 33;
  settings.gain = 12;
  rig.device->applySettings(settings, 3);
  EXPECT_DOUBLE_EQ(rig.camera->settings.exposure_ms, 33);
  EXPECT_EQ(rig.camera->settings.gain, 12);
  EXPECT_EQ(rig.device->status().values.at(3).second, "3");
  EXPECT_THROW(rig.device->applySettings(settings, -1), std::invalid_argument);
}

TEST(UsbDeviceMatch, ParsesAndDescribes) {
  const UsbDeviceMatch match = UsbDeviceMatch::parse("046d:0825", "");
  EXPECT_EQ(match.vendor_id, 0x046d);
  EXPECT_EQ(match.product_id, 0x0825);
  EXPECT_EQ(match.describe(), "046d:0825");
  EXPECT_TRUE(match.matches({0x046d, 0x0825, "ANY", 1, 2, true}));
  EXPECT_FALSE(UsbDeviceMatch::parse("046d:0825", "A").matches({0x046d, 0x0825, "B", 1, 2, true}));
  EXPECT_THROW(UsbDeviceMatch::parse("046d-0825", ""), std::invalid_argument);
  EXPECT_THROW(UsbDeviceMatch::parse("46d:825", ""), std::invalid_argument);
}
