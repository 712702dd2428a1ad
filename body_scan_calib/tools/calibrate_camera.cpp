// calibrate_camera: calibrates a camera from a folder of checkerboard images (thesis sec.
// 3.3.1) and writes a YAML whose camera part camera_calibration_parsers reads, with a report
// of the reprojection RMS (overall, per image) and the parameter standard deviations.
//
//   calibrate_camera --images DIR --board-cols 9 --board-rows 6 --square 0.025 --output FILE
//                    [--camera-name NAME] [--estimate-skew] [--layout opencv ...]
// With --layout, DIR is a capture folder and the lit frame of every board pose is used.
#include <body_scan_calib/camera_calibration.h>
#include <body_scan_calib/camera_calibration_io.h>
#include <body_scan_driver/tools/command_line.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "calibration_outputs.h"

namespace fs = std::filesystem;
using namespace body_scan_calib;

namespace {

struct Arguments {
  std::string images, output, camera_name = "camera";
  Checkerboard board;
  tools::CaptureOptions capture{""};  // "" = a plain folder of board images
  bool estimate_skew = false;
};

std::vector<fs::path> listImages(const std::string& folder) {
  std::vector<fs::path> images;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    std::string extension = entry.path().extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
    for (const char* known : {".png", ".jpg", ".jpeg", ".bmp", ".pgm", ".ppm", ".tif", ".tiff"})
      if (extension == known) images.push_back(entry.path());
  }
  std::sort(images.begin(), images.end());
  return images;
}

// The board's corners in every image where it is found (progress line per image).
struct DetectedViews {
  std::vector<std::vector<Eigen::Vector2d>> views;
  std::vector<std::string> view_names, not_found;
  int width = 0, height = 0;
};

// A board image by name, read when its turn comes.
struct BoardImage {
  std::string name;
  std::function<cv::Mat()> read;
};

// The images of a plain folder, or the lit frame of every pose of a capture folder (--layout).
std::vector<BoardImage> boardImages(const Arguments& arguments) {
  std::vector<BoardImage> images;
  if (arguments.capture.layout.empty()) {
    for (const fs::path& file : listImages(arguments.images))
      images.push_back({file.filename().string(),
                        [file] { return cv::imread(file.string(), cv::IMREAD_GRAYSCALE); }});
    return images;
  }
  for (const CapturedPatternSet& pose : loadCapturedPoses(
           arguments.images, arguments.capture.captureLayout(), arguments.capture.captureBits())) {
    const cv::Mat lit = pose.frames[body_scan_driver::PatternLayout::litFrame()];
    images.push_back({fs::path(pose.folder).filename().string(), [lit] { return lit; }});
  }
  return images;
}

DetectedViews detectBoards(const std::vector<BoardImage>& files, const Checkerboard& board) {
  DetectedViews detected;
  auto& [views, view_names, not_found, width, height] = detected;
  for (size_t i = 0; i < files.size(); ++i) {
    const std::string& name = files[i].name;
    std::printf("[%zu/%zu] %s: ", i + 1, files.size(), name.c_str());
    const cv::Mat image = files[i].read();
    if (image.empty()) {
      std::printf("cannot be read, skipped\n");
      not_found.push_back(name + " (unreadable)");
      continue;
    }
    if (width == 0) width = image.cols, height = image.rows;
    if (image.cols != width || image.rows != height) {
      std::printf("%dx%d differs from the first image's %dx%d, skipped\n", image.cols, image.rows,
                  width, height);
      not_found.push_back(name + " (different size)");
      continue;
    }
    std::vector<Eigen::Vector2d> corners;
    if (!detectCheckerboardCorners(image, board, corners)) {
      std::printf("board NOT found\n");
      not_found.push_back(name);
      continue;
    }
    std::printf("board found (%zu corners)\n", corners.size());
    views.push_back(corners);
    view_names.push_back(name);
  }
  return detected;
}

// The parameters with their standard deviations, and the reprojection RMS per view.
void printCalibration(const CameraCalibrationResult& r, const std::vector<std::string>& view_names,
                      bool estimate_skew, const std::string& output) {
  const body_scan_driver::PinholeCamera& c = r.camera;
  std::printf("alpha (fx) %10.3f +- %.3f px\n", c.alpha, r.std_devs[0]);
  std::printf("beta  (fy) %10.3f +- %.3f px\n", c.beta, r.std_devs[1]);
  std::printf("gamma      %10.4f +- %.4f px%s\n", c.gamma, r.std_devs[2],
              estimate_skew ? "" : " (held at 0)");
  std::printf("u0    (cx) %10.3f +- %.3f px\n", c.u0, r.std_devs[3]);
  std::printf("v0    (cy) %10.3f +- %.3f px\n", c.v0, r.std_devs[4]);
  std::printf("k1         %10.5f +- %.5f\n", c.k1, r.std_devs[5]);
  std::printf("k2         %10.5f +- %.5f\n", c.k2, r.std_devs[6]);
  std::printf("reprojection RMS %.4f px over %zu views (%d iterations)\n", r.rms_px,
              view_names.size(), r.iterations);
  for (size_t i = 0; i < view_names.size(); ++i)
    std::printf("  %-24s rms %.4f px\n", view_names[i].c_str(), r.per_view_rms_px[i]);
  std::printf("wrote %s\n", output.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Calibrates a camera from a folder of checkerboard images (thesis sec. 3.3.1) and writes a "
      "YAML whose camera part camera_calibration_parsers reads, with the reprojection RMS and "
      "the parameter standard deviations.",
      "calibrate_camera");
  Arguments arguments;
  app.add_option("--images", arguments.images,
                 "folder of board images, or with --layout a capture folder (the lit frame of "
                 "every pose)")
      ->required();
  tools::addBoardOptions(app, arguments.board);
  tools::addCaptureOptions(app, arguments.capture);
  app.add_option("--output", arguments.output,
                 "calibration YAML to write (atomically); its camera part is readable by "
                 "camera_calibration_parsers")
      ->required();
  app.add_option("--camera-name", arguments.camera_name, "camera name in the file")
      ->capture_default_str();
  app.add_flag("--estimate-skew", arguments.estimate_skew,
               "also estimate the skew gamma (default: held at 0)");
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  if (!fs::is_directory(arguments.images)) {
    std::cerr << "calibrate_camera: '" << arguments.images
              << "' is not a folder; pass --images with the folder of board images\n";
    return 1;
  }
  std::vector<BoardImage> files;
  try {
    files = boardImages(arguments);
  } catch (const std::exception& e) {
    std::cerr << "calibrate_camera: " << e.what() << "\n";
    return 1;
  }
  if (files.empty()) {
    std::cerr << "calibrate_camera: no images (.png, .jpg, .bmp, .pgm, .ppm, .tif) in '"
              << arguments.images << "'\n";
    return 1;
  }

  const Checkerboard& board = arguments.board;
  const DetectedViews detected = detectBoards(files, board);
  const auto& [views, view_names, not_found, width, height] = detected;
  std::fflush(stdout);
  if (!not_found.empty()) {
    std::cerr << "calibrate_camera: board of " << board.inner_cols << "x" << board.inner_rows
              << " inner corners not found in " << not_found.size() << " of " << files.size()
              << " images:";
    for (const std::string& name : not_found) std::cerr << " " << name;
    std::cerr << "\n";
  }
  if (views.size() < 3) {
    std::cerr
        << "calibrate_camera: too few views: the board was found in " << views.size()
        << " images, at least 3 with different tilts are needed. Check --board-cols/--board-rows "
           "(INNER corners, e.g. 9 and 6 for a 10x7-square board) and that the whole "
           "board with its white margin is in view.\n";
    return 1;
  }

  CameraCalibrationReport report;
  report.camera_name = arguments.camera_name;
  report.board = board;
  report.view_names = view_names;
  try {
    CameraCalibrationOptions options;
    options.estimate_skew = arguments.estimate_skew;
    std::printf("calibrating from %zu views (Zhang closed form, then Levenberg-Marquardt)...\n",
                views.size());
    report.result = calibrateCamera(views, board, width, height, options);
    saveCameraCalibration(arguments.output, report);
  } catch (const CameraCalibrationError& e) {
    std::cerr << "calibrate_camera: " << e.what() << "\n";
    return 1;
  }
  printCalibration(report.result, view_names, arguments.estimate_skew, arguments.output);
  return 0;
}
