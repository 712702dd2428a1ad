// Measures a pair's projector latency in camera frames, the value for settle_frames:
//   rosrun body_scan_driver measure_projector_latency VID:PID [SERIAL] [--display :0]
//       [--screen 0] [--width 640 --height 480 --fps 30 --format yuyv --exposure-ms 10]
//       [--max-frames 15] [--repeat 5]
// Shows black, then a full-screen white flash, and counts the camera frames that still show
// black. Point the camera at the projected area. Use the largest count over the repeats
// (+1 for margin) as settle_frames.
#include <body_scan_driver/hw/pattern_sequencer.h>
#include <body_scan_driver/hw/projector_window.h>
#include <body_scan_driver/hw/uvc_camera.h>
#include <body_scan_driver/tools/command_line.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

using namespace body_scan_driver::hw;

int main(int argc, char** argv) {
  CLI::App app(
      "Measures a pair's projector latency in camera frames, the value for settle_frames: shows "
      "black, then a full-screen white flash, and counts the camera frames that still show black.",
      "measure_projector_latency");
  std::string camera_id, serial, display;
  int screen = -1, max_frames = 15, repeat = 5;
  UvcSettings settings;
  app.add_option("VID:PID", camera_id,
                 "the camera's vendor:product in hex (rosrun body_scan_driver list_devices --uvc)")
      ->required();
  app.add_option("SERIAL", serial, "the camera's serial, when several are attached");
  app.add_option("--display", display, "X display of the projector, e.g. :0 (default: $DISPLAY)");
  app.add_option("--screen", screen, "screen of the projector (default: the display's)");
  app.add_option("--width", settings.width, "camera image width")
      ->capture_default_str()
      ->check(body_scan_driver::tools::positive());
  app.add_option("--height", settings.height, "camera image height")
      ->capture_default_str()
      ->check(body_scan_driver::tools::positive());
  app.add_option("--fps", settings.fps, "camera frame rate")
      ->capture_default_str()
      ->check(body_scan_driver::tools::positive());
  app.add_option("--format", settings.format, "camera pixel format")
      ->capture_default_str()
      ->check(CLI::IsMember({"yuyv", "mjpeg"}));
  app.add_option("--exposure-ms", settings.exposure_ms, "camera exposure time (ms)")
      ->capture_default_str();
  app.add_option("--max-frames", max_frames, "frames to wait for the flash")
      ->capture_default_str()
      ->check(body_scan_driver::tools::positive());
  app.add_option("--repeat", repeat, "flashes; use the largest count (+1) as settle_frames")
      ->capture_default_str()
      ->check(body_scan_driver::tools::positive());
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  try {
    UvcCamera camera(UsbDeviceMatch::parse(camera_id, serial), settings);
    ProjectorWindow projector(display, screen);
    camera.startStreaming();
    int worst = 0;
    for (int r = 0; r < repeat; ++r) {
      const int latency = measureDisplayLatency(projector, camera, max_frames, 1.0);
      std::printf("flash %d: seen after %d camera frame(s)\n", r + 1, latency);
      worst = std::max(worst, latency);
    }
    const StreamStatistics stats = camera.statistics();
    std::printf("camera %.1f fps, %llu dropped frame(s)\nset settle_frames to %d (worst %d + 1)\n",
                stats.frame_rate_hz, static_cast<unsigned long long>(stats.dropped_frames),
                worst + 1, worst);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "measure_projector_latency: %s\n", e.what());
    return 1;
  }
}
