// The projector output path under a headless X server: Xvfb is started by
// the test on a free display number, ProjectorWindow shows every Gray code
// pattern frame full-screen, the test grabs the X screen (XGetImage) after each and decodes
// the grabs with the project's decoder: every pixel must decode to the stripe the projector
// pixel belongs to. The last test runs the driver's own path (UsbPairDevice -> sequencer ->
// ProjectorWindow) with a camera that grabs the screen. Skipped, with a message, when Xvfb is
// not installed.
#include <body_scan_driver/hw/projector_window.h>
#include <body_scan_driver/hw/usb_pair_device.h>
#include <body_scan_driver/stripe_decoder.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "fake_hardware.h"

using namespace body_scan_driver;
using namespace body_scan_driver::hw;

namespace {

const char* const kXvfb = "/usr/bin/Xvfb";

// An Xvfb server for the lifetime of the object, on the first free display number from one
// derived from our pid (other test processes may run their own servers at the same time).
class Xvfb {
 public:
  Xvfb(int width, int height) {
    const std::string screen = std::to_string(width) + "x" + std::to_string(height) + "x24";
    for (int number = 100 + getpid() % 800, tries = 0; tries < 20; ++number, ++tries) {
      const std::string name = ":" + std::to_string(number);
      if (access(("/tmp/.X11-unix/X" + std::to_string(number)).c_str(), F_OK) == 0 ||
          access(("/tmp/.X" + std::to_string(number) + "-lock").c_str(), F_OK) == 0)
        continue;
      pid_ = fork();
      if (pid_ == 0) {
        execl(kXvfb, "Xvfb", name.c_str(), "-screen", "0", screen.c_str(), "-nolisten", "tcp",
              "-noreset", static_cast<char*>(nullptr));
        _exit(127);
      }
      // Ready when a client can connect; a server that exits lost the race for the number.
      for (int wait = 0; wait < 100; ++wait) {
        if (waitpid(pid_, nullptr, WNOHANG) == pid_) {
          pid_ = -1;
          break;
        }
        try {
          grabScreen(name, 0);
          display_ = name;
          return;
        } catch (const std::runtime_error&) {
          std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
      }
      stop();
    }
  }
  ~Xvfb() { stop(); }
  const std::string& display() const { return display_; }

 private:
  void stop() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
  pid_t pid_ = -1;
  std::string display_;
};

cv::Mat grabGrey(const std::string& display) {
  cv::Mat grey;
  cv::cvtColor(grabScreen(display, 0), grey, cv::COLOR_RGB2GRAY);
  return grey;
}

// Shows every frame of `layout`, grabs the screen after each, decodes, and counts the pixels
// whose stripe id differs from the projector stripe of that pixel.
int wrongStripesThroughTheScreen(const std::string& display, const PatternLayout& layout,
                                 StripeDirection direction, int& pixels) {
  ProjectorWindow window(display, 0);
  const cv::Size size = window.resolution();
  std::vector<cv::Mat> grabs;
  for (int frame = 0; frame < layout.frameCount(); ++frame) {
    window.show(renderPatternFrame(layout, frame, size, direction));
    grabs.push_back(grabGrey(display));
  }
  DecoderParams params;
  params.subpixel = false;
  params.axis = direction == StripeDirection::kAlongRows ? DecoderParams::StripeAxis::kAlongRows
                                                         : DecoderParams::StripeAxis::kAlongColumns;
  StripeImage decoded;
  StripeDecoder(layout, params).decode(grabs, decoded);
  int wrong = 0;
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) {
      const int expected = direction == StripeDirection::kAlongRows
                               ? stripeOfProjectorPixel(v, size.height, layout.stripeCount())
                               : stripeOfProjectorPixel(u, size.width, layout.stripeCount());
      wrong += decoded.stripe(v, u) != expected;
    }
  pixels = size.area();
  return wrong;
}

}  // namespace

class ProjectorWindowOnXvfb : public ::testing::Test {
 protected:
  void SetUp() override {
    if (access(kXvfb, X_OK) != 0)
      GTEST_SKIP() << kXvfb << " is missing: apt-get install xvfb (make deps) to run this test";
    xvfb_ = std::make_unique<Xvfb>(640, 480);
    ASSERT_FALSE(xvfb_->display().empty()) << "Xvfb did not start";
  }
  std::unique_ptr<Xvfb> xvfb_;
};

TEST_F(ProjectorWindowOnXvfb, CoversTheWholeScreen) {
  ProjectorWindow window(xvfb_->display(), 0);
  EXPECT_EQ(window.resolution(), cv::Size(640, 480));
  for (int level : {255, 0, 128}) {
    window.show(cv::Mat(window.resolution(), CV_8UC1, cv::Scalar(level)));
    const cv::Mat grey = grabGrey(xvfb_->display());
    double low, high;
    cv::minMaxLoc(grey, &low, &high);
    EXPECT_EQ(low, level);
    EXPECT_EQ(high, level);
  }
}

TEST_F(ProjectorWindowOnXvfb, GrabbedGrayCodeDecodesToTheExactStripeEverywhere) {
  int pixels = 0;
  // The pole's layout: 256 horizontal stripes with inverse frames.
  const int wrong_rows = wrongStripesThroughTheScreen(xvfb_->display(), PatternLayout(8, true),
                                                      StripeDirection::kAlongRows, pixels);
  std::cout << "[ figure ] 8 bits + inverses, stripes along rows: " << wrong_rows
            << " wrong stripe ids of " << pixels << " pixels\n";
  EXPECT_EQ(wrong_rows, 0);
  // A horizontal baseline without inverse frames: 512 vertical stripes.
  const int wrong_columns = wrongStripesThroughTheScreen(xvfb_->display(), PatternLayout(9, false),
                                                         StripeDirection::kAlongColumns, pixels);
  std::cout << "[ figure ] 9 bits, no inverses, stripes along columns: " << wrong_columns
            << " wrong stripe ids of " << pixels << " pixels\n";
  EXPECT_EQ(wrong_columns, 0);
}

TEST_F(ProjectorWindowOnXvfb, MissingDisplayOrScreenIsAClearError) {
  try {
    ProjectorWindow window(xvfb_->display(), 3);
    FAIL() << "screen 3 does not exist";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("projector_screen"), std::string::npos) << e.what();
  }
  try {
    ProjectorWindow window(":98765", 0);
    FAIL() << "display :98765 does not exist";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("projector_display"), std::string::npos) << e.what();
  }
}

// A "camera" that sees exactly what the X screen shows: the driver's whole output path (the
// UsbPairDevice's sequencer driving the real ProjectorWindow) observed through XGetImage.
class ScreenGrabCamera : public StreamingCamera {
 public:
  explicit ScreenGrabCamera(std::string display) : display_(std::move(display)) {}
  void startStreaming() override {}
  void stopStreaming() override {}
  void applySettings(const UvcSettings&) override {}
  StreamStatistics statistics() const override { return {}; }
  void discardReceived() override {}
  cv::Mat nextFrame(double) override { return grabScreen(display_, 0); }

 private:
  std::string display_;
};

TEST_F(ProjectorWindowOnXvfb, UsbPairDeviceCapturesDecodableSetsThroughTheScreen) {
  UsbPairSettings settings;
  settings.camera = UsbDeviceMatch::parse("1234:5678", "SCREEN");
  settings.projector_display = xvfb_->display();
  settings.projector_screen = 0;
  settings.sequencer.settle_frames = 0;  // XSync: the grab always sees the pattern just shown
  HardwareAccess access;
  auto bus = std::make_unique<fakes::FakeBus>();
  bus->attached.push_back({0x1234, 0x5678, "SCREEN", 1, 2, true});
  access.bus = std::move(bus);
  const std::string display = xvfb_->display();
  access.open_camera = [display](const UsbDeviceMatch&, const UvcSettings&) {
    return std::unique_ptr<StreamingCamera>(new ScreenGrabCamera(display));
  };
  access.open_projector = [](const std::string& name, int screen) {
    return std::unique_ptr<PatternProjector>(new ProjectorWindow(name, screen));
  };
  access.now_s = [] { return 0.0; };
  UsbPairDevice device(settings, std::move(access));
  device.poll();
  ASSERT_EQ(device.state(), ConnectionState::kStreaming) << device.status().message;

  const PatternCapture capture = device.capture(1);
  DecoderParams params;
  params.subpixel = false;
  params.axis = DecoderParams::StripeAxis::kAlongRows;
  StripeImage decoded;
  StripeDecoder(device.layout(), params).decode(capture.frames, decoded);
  int wrong = 0;
  for (int v = 0; v < decoded.stripe.rows; ++v)
    for (int u = 0; u < decoded.stripe.cols; ++u)
      wrong += decoded.stripe(v, u) != stripeOfProjectorPixel(v, decoded.stripe.rows, 256);
  std::cout << "[ figure ] UsbPairDevice on Xvfb (8 bits + inverses): " << wrong
            << " wrong stripe ids of " << decoded.stripe.total() << " pixels\n";
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(cv::countNonZero(grabGrey(display)), 0) << "the projector is left dark";
}
