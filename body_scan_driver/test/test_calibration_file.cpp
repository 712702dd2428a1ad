#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>
#include <camera_calibration_parsers/parse.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "sim_fixtures.h"

using namespace body_scan_driver;

namespace {

std::string temporaryFolder() {
  const auto folder = std::filesystem::temp_directory_path() /
                      ("body_scan_calibration_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  return folder.string();
}

std::string expectError(const std::string& path) {
  try {
    loadCalibration(path);
  } catch (const CalibrationFileError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for " << path;
  return "";
}

}  // namespace

TEST(CalibrationFile, RoundTripIsExactAndAtomic) {
  const sim::VirtualPair pair(test::pairLookingAlongX(), test::planeScene(1.0));
  const PairCalibration written = pair.factoryCalibration();
  const std::string folder = temporaryFolder();
  const std::string path = folder + "/nested/pair.yaml";
  saveCalibration(path, written);
  const PairCalibration read = loadCalibration(path);
  EXPECT_EQ(read.pair_id, written.pair_id);
  EXPECT_EQ(read.camera.width, 640);
  EXPECT_DOUBLE_EQ(read.camera.alpha, written.camera.alpha);
  EXPECT_DOUBLE_EQ(read.camera.k1, written.camera.k1);
  EXPECT_DOUBLE_EQ(read.camera.k2, written.camera.k2);
  ASSERT_EQ(read.projector.stripeCount(), 256);
  for (int i = 0; i < 256; ++i)
    EXPECT_EQ((read.projector.planes[i] - written.projector.planes[i]).norm(), 0.0) << i;
  // Only the final file remains: the temporary one was renamed over it.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder + "/nested"),
                          std::filesystem::directory_iterator()),
            1);
  std::filesystem::remove_all(folder);
}

TEST(CalibrationFile, BadFilesGiveErrorsNamingTheProblemAndTheFix) {
  const std::string folder = temporaryFolder();
  std::string message = expectError(folder + "/missing.yaml");
  EXPECT_NE(message.find("missing.yaml"), std::string::npos);
  EXPECT_NE(message.find("calibrate the pair"), std::string::npos);

  std::ofstream(folder + "/no_planes.yaml")
      << "image_width: 640\nimage_height: 480\ncamera_matrix: {rows: 3, cols: 3, data: "
         "[810, 0, 320, 0, 810, 240, 0, 0, 1]}\ndistortion_coefficients: {data: [0, 0, 0, 0, "
         "0]}\n";
  EXPECT_NE(expectError(folder + "/no_planes.yaml").find("projector: planes:"), std::string::npos);

  std::ofstream(folder + "/short_matrix.yaml")
      << "image_width: 640\nimage_height: 480\ncamera_matrix: {data: [810, 0]}\n";
  EXPECT_NE(expectError(folder + "/short_matrix.yaml").find("9 numbers"), std::string::npos);

  std::ofstream(folder + "/broken.yaml") << "camera_matrix: [unclosed\n";
  EXPECT_NE(expectError(folder + "/broken.yaml").find("not valid YAML"), std::string::npos);
  std::filesystem::remove_all(folder);
}

TEST(CalibrationFile, CameraPartIsReadByCameraCalibrationParsers) {
  // The standard ROS reader must accept our files and see the same camera.
  const sim::VirtualPair pair(test::pairLookingAlongX(), test::planeScene(1.0));
  const PairCalibration written = pair.factoryCalibration();
  const std::string folder = temporaryFolder();
  const std::string path = folder + "/pair.yaml";
  saveCalibration(path, written);
  std::string camera_name;
  sensor_msgs::CameraInfo info;
  ASSERT_TRUE(camera_calibration_parsers::readCalibration(path, camera_name, info));
  EXPECT_EQ(camera_name, written.pair_id);
  EXPECT_EQ(info.width, 640u);
  EXPECT_EQ(info.height, 480u);
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  EXPECT_DOUBLE_EQ(info.K[0], written.camera.alpha);
  EXPECT_DOUBLE_EQ(info.K[2], written.camera.u0);
  EXPECT_DOUBLE_EQ(info.K[4], written.camera.beta);
  EXPECT_DOUBLE_EQ(info.K[5], written.camera.v0);
  ASSERT_EQ(info.D.size(), 5u);
  EXPECT_DOUBLE_EQ(info.D[0], written.camera.k1);
  EXPECT_DOUBLE_EQ(info.D[1], written.camera.k2);
  std::filesystem::remove_all(folder);
}

// A stripe the calibration never observed is stored as NaN, read back as missing, and
// triangulates to nothing instead of an invented surface.
TEST(CalibrationFile, MissingStripesRoundTripAndTriangulateToNothing) {
  const sim::VirtualPair pair(test::pairLookingAlongX(), test::planeScene(1.0));
  PairCalibration written = pair.factoryCalibration();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int i = 100; i < 110; ++i) written.projector.planes[i].setConstant(nan);
  const std::string folder = temporaryFolder();
  saveCalibration(folder + "/pair.yaml", written);
  const PairCalibration read = loadCalibration(folder + "/pair.yaml");
  for (int i = 0; i < read.projector.stripeCount(); ++i)
    EXPECT_EQ(read.projector.planes[i].array().isNaN().all(), i >= 100 && i < 110) << i;

  // On a decoded plane, pixels whose coordinate needs a missing plane (interpolation between
  // planes i and i + 1 for s in [i + 0.5, i + 1.5)) give NaN; every other pixel is unchanged.
  StripeImage image;
  StripeDecoder(pair.layout(), DecoderParams()).decode(pair.render(3).frames, image);
  const size_t n = image.coordinate.total();
  std::vector<float> expected(4 * n), points(4 * n);
  Triangulator(pair.factoryCalibration()).triangulate(image.coordinate, expected.data(), 4);
  Triangulator(read).triangulate(image.coordinate, points.data(), 4);
  size_t in_missing = 0, other = 0;
  for (size_t i = 0; i < n; ++i) {
    const float s = image.coordinate(static_cast<int>(i));
    if (!std::isfinite(expected[4 * i + 2])) continue;
    if (s >= 99.5f && s < 110.5f) {
      EXPECT_TRUE(std::isnan(points[4 * i + 2])) << "pixel " << i << " stripe " << s;
      ++in_missing;
    } else {
      EXPECT_EQ(points[4 * i + 2], expected[4 * i + 2]) << "pixel " << i << " stripe " << s;
      ++other;
    }
  }
  EXPECT_GT(in_missing, 1000u);
  EXPECT_GT(other, 100000u);

  std::ofstream(folder + "/half_nan.yaml")
      << "image_width: 640\nimage_height: 480\ncamera_matrix: {rows: 3, cols: 3, data: "
         "[810, 0, 320, 0, 810, 240, 0, 0, 1]}\ndistortion_coefficients: {data: [0, 0, 0, 0, "
         "0]}\nprojector: {stripe_count: 2, planes: [[0, 1, 0, -0.1], [0, .nan, 0, -0.1]]}\n";
  EXPECT_NE(expectError(folder + "/half_nan.yaml").find("never observed"), std::string::npos);
  std::filesystem::remove_all(folder);
}
