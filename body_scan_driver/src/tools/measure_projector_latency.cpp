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

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

using namespace body_scan_driver::hw;

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0) {
    std::fprintf(stderr,
                 "usage: measure_projector_latency VID:PID [SERIAL] [--display :0] [--screen N]\n"
                 "       [--width W] [--height H] [--fps F] [--format yuyv|mjpeg]\n"
                 "       [--exposure-ms E] [--max-frames N] [--repeat N]\n"
                 "VID:PID and SERIAL of the camera: rosrun body_scan_driver list_devices --uvc\n");
    return 2;
  }
  try {
    std::string serial, display;
    int screen = -1, max_frames = 15, repeat = 5;
    UvcSettings settings;
    int i = 2;
    if (i < argc && argv[i][0] != '-') serial = argv[i++];
    for (; i < argc; ++i) {
      const std::string flag = argv[i];
      if (i + 1 >= argc) throw std::invalid_argument("option " + flag + " needs a value");
      const std::string value = argv[++i];
      if (flag == "--display")
        display = value;
      else if (flag == "--screen")
        screen = std::stoi(value);
      else if (flag == "--width")
        settings.width = std::stoi(value);
      else if (flag == "--height")
        settings.height = std::stoi(value);
      else if (flag == "--fps")
        settings.fps = std::stoi(value);
      else if (flag == "--format")
        settings.format = value;
      else if (flag == "--exposure-ms")
        settings.exposure_ms = std::stod(value);
      else if (flag == "--max-frames")
        max_frames = std::stoi(value);
      else if (flag == "--repeat")
        repeat = std::stoi(value);
      else
        throw std::invalid_argument("unknown option " + flag + " (see --help)");
    }
    UvcCamera camera(UsbDeviceMatch::parse(argv[1], serial), settings);
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
