// Camera calibration files: round trip, readable by camera_calibration_parsers, clear errors;
// and the calibrate_camera CLI end to end (success on OpenCV's samples, errors on bad input).
#include <body_scan_calib/camera_calibration_io.h>
#include <camera_calibration_parsers/parse.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "camera_test_fixtures.h"

namespace body_scan_calib {
namespace {

namespace fs = std::filesystem;

fs::path scratchFolder(const std::string& name) {
  const fs::path folder =
      fs::temp_directory_path() / ("body_scan_cam_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

CameraCalibrationReport simulatedReport() {
  const Checkerboard board{9, 6, 0.04};
  const auto views =
      test::projectCorners(test::simulatorCamera(), board, test::threeSpreadPoses(board), 0.2, 3);
  CameraCalibrationReport report;
  report.camera_name = "pole_a/pair_1";
  report.board = board;
  report.view_names = {"a.png", "b.png", "c.png"};
  report.result = calibrateCamera(views, board, 640, 480);
  return report;
}

TEST(CameraCalibrationIo, RoundTripAndReadableByCameraCalibrationParsers) {
  const fs::path folder = scratchFolder("io");
  const std::string path = (folder / "sub" / "camera.yaml").string();
  const CameraCalibrationReport report = simulatedReport();
  saveCameraCalibration(path, report);

  const body_scan_driver::PinholeCamera loaded = loadCameraCalibration(path);
  const body_scan_driver::PinholeCamera& c = report.result.camera;
  EXPECT_EQ(loaded.width, 640);
  EXPECT_EQ(loaded.height, 480);
  EXPECT_DOUBLE_EQ(loaded.alpha, c.alpha);
  EXPECT_DOUBLE_EQ(loaded.beta, c.beta);
  EXPECT_DOUBLE_EQ(loaded.gamma, c.gamma);
  EXPECT_DOUBLE_EQ(loaded.u0, c.u0);
  EXPECT_DOUBLE_EQ(loaded.v0, c.v0);
  EXPECT_DOUBLE_EQ(loaded.k1, c.k1);
  EXPECT_DOUBLE_EQ(loaded.k2, c.k2);

  std::string name;
  sensor_msgs::CameraInfo info;
  ASSERT_TRUE(camera_calibration_parsers::readCalibration(path, name, info));
  EXPECT_EQ(name, "pole_a/pair_1");
  EXPECT_EQ(info.width, 640u);
  EXPECT_DOUBLE_EQ(info.K[0], c.alpha);
  EXPECT_DOUBLE_EQ(info.K[2], c.u0);
  EXPECT_DOUBLE_EQ(info.K[4], c.beta);
  EXPECT_DOUBLE_EQ(info.K[5], c.v0);
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  ASSERT_EQ(info.D.size(), 5u);
  EXPECT_DOUBLE_EQ(info.D[0], c.k1);
  EXPECT_DOUBLE_EQ(info.D[1], c.k2);

  // The report carries the figures that say what the estimate is worth.
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  for (const char* key : {"calibration_report", "rms_px", "std_devs", "per_view", "b.png"})
    EXPECT_NE(text.str().find(key), std::string::npos) << key;
  fs::remove_all(folder);
}

TEST(CameraCalibrationIo, ErrorsNameTheFileAndTheFix) {
  const fs::path folder = scratchFolder("io_errors");
  try {
    loadCameraCalibration((folder / "missing.yaml").string());
    FAIL();
  } catch (const CameraCalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("calibrate_camera"), std::string::npos) << e.what();
  }
  const fs::path tangential = folder / "tangential.yaml";
  std::ofstream(tangential) << "image_width: 640\nimage_height: 480\n"
                               "camera_matrix: {rows: 3, cols: 3, data: [800, 0, 320, 0, 800, "
                               "240, 0, 0, 1]}\ndistortion_model: plumb_bob\n"
                               "distortion_coefficients: {rows: 1, cols: 5, data: [0.1, 0.01, "
                               "0.002, 0, 0]}\n";
  try {
    loadCameraCalibration(tangential.string());
    FAIL();
  } catch (const CameraCalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("tangential"), std::string::npos) << e.what();
  }
  fs::remove_all(folder);
}

struct CommandResult {
  int status;
  std::string output;
};

CommandResult run(const std::string& arguments) {
  const std::string command = std::string(CALIBRATE_CAMERA_EXECUTABLE) + " " + arguments + " 2>&1";
  CommandResult result{-1, ""};
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[512];
  while (std::fgets(buffer, sizeof(buffer), pipe)) result.output += buffer;
  result.status = ::pclose(pipe);
  return result;
}

TEST(CalibrateCameraTool, CalibratesOpenCvSamplesAndWritesAReadableFile) {
  const fs::path samples = "/usr/share/doc/opencv-doc/examples/data";
  if (!fs::exists(samples / "left01.jpg"))
    GTEST_SKIP() << "OpenCV sample images (plain .jpg) not in " << samples
                 << "; install opencv-doc";
  const fs::path folder = scratchFolder("tool");
  fs::create_directories(folder / "images");
  for (int i = 1; i <= 14; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "left%02d.jpg", i);
    if (fs::exists(samples / name))
      fs::copy_file(samples / name, folder / "images" / name, fs::copy_options::overwrite_existing);
  }
  const std::string output = (folder / "camera.yaml").string();
  const CommandResult result = run("--images " + (folder / "images").string() +
                                   " --cols 9 --rows 6 --square 0.025 --output " + output);
  std::printf("%s", result.output.c_str());
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("[1/"), std::string::npos);  // progress per image
  EXPECT_NE(result.output.find("board found"), std::string::npos);
  const body_scan_driver::PinholeCamera camera = loadCameraCalibration(output);
  EXPECT_EQ(camera.width, 640);
  EXPECT_GT(camera.alpha, 400);  // a plausible focal length; the figures are checked elsewhere
  fs::remove_all(folder);
}

TEST(CalibrateCameraTool, ReportsClearErrors) {
  const fs::path folder = scratchFolder("tool_errors");
  fs::create_directories(folder / "empty");
  CommandResult result = run("--images " + (folder / "empty").string() + " --output x.yaml");
  EXPECT_NE(result.status, 0);
  EXPECT_NE(result.output.find("no images"), std::string::npos) << result.output;

  // Two blank images: the board is found in none of them -> listed, and too few views.
  fs::create_directories(folder / "blank");
  const cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(128));
  cv::imwrite((folder / "blank" / "one.png").string(), blank);
  cv::imwrite((folder / "blank" / "two.png").string(), blank);
  result = run("--images " + (folder / "blank").string() + " --output " +
               (folder / "out.yaml").string());
  EXPECT_NE(result.status, 0);
  EXPECT_NE(result.output.find("not found in 2 of 2 images: one.png two.png"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("too few views"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(folder / "out.yaml"));

  result = run("--images " + (folder / "blank").string() + " --square 25 --output y.yaml");
  EXPECT_EQ(result.status >> 8, 2);
  EXPECT_NE(result.output.find("METRES"), std::string::npos) << result.output;
  fs::remove_all(folder);
}

}  // namespace
}  // namespace body_scan_calib
