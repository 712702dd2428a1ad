// Real captures of a projector-camera pair (test/data/kamino_procam, README there): the OpenCV
// capture layout, the user's board on the calibration tools, and the camera against
// cv::calibrateCamera on the same corners.
#include <body_scan_calib/capture_layout.h>
#include <body_scan_calib/pair_calibration_pipeline.h>
#include <body_scan_calib/pair_calibration_run.h>
#include <body_scan_calib/pair_validation.h>
#include <body_scan_driver/calibration_file.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <string>

namespace body_scan_calib {
namespace {

namespace fs = std::filesystem;

const std::string kFixture = REAL_CAPTURES_DIR;
// The fixture keeps the column bits (10 for 1024 projector columns) and no row bits.
const CaptureBits kFixtureBits{10, 0};
// The data's board: 9 x 7 inner corners; its squares are 75 units, taken as millimetres.
const Checkerboard kRealBoard{9, 7, 0.075};

std::vector<cv::Mat> litFrames(const std::vector<CapturedPatternSet>& poses) {
  std::vector<cv::Mat> lit;
  for (const CapturedPatternSet& pose : poses)
    lit.push_back(pose.frames[body_scan_driver::PatternLayout::litFrame()]);
  return lit;
}

TEST(RealCaptures, OpenCvLayoutImportsTheGrayCodeOrder) {
  const auto poses = loadCapturedPoses(kFixture, captureLayout("opencv"), kFixtureBits);
  ASSERT_EQ(poses.size(), 4u);
  for (const CapturedPatternSet& pose : poses) {
    ASSERT_EQ(pose.frames.size(), 22u);  // lit, dark, 10 pattern/inverse pairs
    EXPECT_TRUE(pose.cross_frames.empty());
    // The white frame (last but one on disk) comes first, the black one second.
    const cv::Mat lit = pose.frames[0], dark = pose.frames[1];
    const cv::Mat on_band = pose.frames[2] > 0;
    EXPECT_GT(cv::mean(lit, on_band)[0], cv::mean(dark, on_band)[0] + 40) << pose.folder;
    // The most significant pattern and its inverse light complementary halves.
    cv::Mat difference;
    cv::absdiff(pose.frames[2], pose.frames[3], difference);
    EXPECT_GT(cv::mean(difference, on_band)[0], 20) << pose.folder;
  }
}

TEST(RealCaptures, WrongBitCountNamesTheImageCounts) {
  try {
    loadCapturedPoses(kFixture, captureLayout("opencv"), CaptureBits{8, 0});
    FAIL() << "8 column bits accepted for a set of 10";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("holds 22 images"), std::string::npos) << message;
    EXPECT_NE(message.find("needs 18"), std::string::npos) << message;
    EXPECT_NE(message.find("--projector-width"), std::string::npos) << message;
  }
  EXPECT_THROW(captureLayout("matlab"), std::invalid_argument);
  EXPECT_THROW(loadCapturedPoses(kFixture, captureLayout("project"), kFixtureBits),
               std::runtime_error);  // no pose_NN folders
}

TEST(RealCaptures, BitsForProjectorPixelsAsOpenCv) {
  EXPECT_EQ(bitsForPixels(1024), 10);
  EXPECT_EQ(bitsForPixels(768), 10);
  EXPECT_EQ(bitsForPixels(1280), 11);
  EXPECT_EQ(bitsForPixels(2), 1);
}

TEST(RealCaptures, ReferenceBoardIsRefusedTheUsersBoardIsFound) {
  const auto poses = loadCapturedPoses(kFixture, captureLayout("opencv"), kFixtureBits);
  const std::vector<cv::Mat> lit = litFrames(poses);
  EXPECT_THROW(estimateCameraAndBoardPoses(lit, referenceBoard()), PairCalibrationError);
  const CameraAndBoardPoses camera = estimateCameraAndBoardPoses(lit, kRealBoard);
  EXPECT_LT(camera.rms_px, 0.5);
  ASSERT_EQ(camera.board_to_camera.size(), 4u);
  // The board stands a few metres away at the data's scale.
  for (const Eigen::Isometry3d& pose : camera.board_to_camera) {
    EXPECT_GT(pose.translation().z(), 1.0);
    EXPECT_LT(pose.translation().z(), 6.0);
  }
}

TEST(RealCaptures, CameraMatchesOpenCvCalibrateCameraOnTheSameCorners) {
  const auto poses = loadCapturedPoses(kFixture, captureLayout("opencv"), kFixtureBits);
  const CameraAndBoardPoses ours = estimateCameraAndBoardPoses(litFrames(poses), kRealBoard);
  std::vector<std::vector<cv::Point3f>> object(ours.corners.size());
  std::vector<std::vector<cv::Point2f>> image(ours.corners.size());
  for (size_t view = 0; view < ours.corners.size(); ++view) {
    for (const Eigen::Vector3d& p : kRealBoard.objectPoints())
      object[view].emplace_back(p.x(), p.y(), 0);
    for (const Eigen::Vector2d& p : ours.corners[view]) image[view].emplace_back(p.x(), p.y());
  }
  // The same model as ours: k1, k2, no tangential terms, no k3.
  cv::Mat matrix, distortion;
  std::vector<cv::Mat> rotations, translations;
  const double opencv_rms = cv::calibrateCamera(
      object, image, cv::Size(ours.camera.width, ours.camera.height), matrix, distortion, rotations,
      translations, cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST);
  const double fx = matrix.at<double>(0, 0), fy = matrix.at<double>(1, 1);
  const double cx = matrix.at<double>(0, 2), cy = matrix.at<double>(1, 2);
  std::printf(
      "ours fx %.1f fy %.1f cx %.1f cy %.1f rms %.4f; OpenCV fx %.1f fy %.1f cx %.1f cy "
      "%.1f rms %.4f\n",
      ours.camera.alpha, ours.camera.beta, ours.camera.u0, ours.camera.v0, ours.rms_px, fx, fy, cx,
      cy, opencv_rms);
  EXPECT_NEAR(ours.camera.alpha / fx, 1.0, 0.005);
  EXPECT_NEAR(ours.camera.beta / fy, 1.0, 0.005);
  // The principal point within 0.5 % of the image size.
  EXPECT_NEAR(ours.camera.u0, cx, 0.005 * ours.camera.width);
  EXPECT_NEAR(ours.camera.v0, cy, 0.005 * ours.camera.height);
  EXPECT_LE(ours.rms_px, opencv_rms * 1.001);
}

struct CommandResult {
  int status;
  std::string output;
};

CommandResult run(const std::string& command) {
  CommandResult result{-1, ""};
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  char buffer[512];
  while (std::fgets(buffer, sizeof(buffer), pipe)) result.output += buffer;
  result.status = ::pclose(pipe);
  return result;
}

// The board flags and the layout on the command line; scan_folder on a calibration of the set.
TEST(RealCaptures, ToolsTakeTheBoardAndTheLayout) {
  const fs::path folder =
      fs::temp_directory_path() / ("real_captures_" + std::to_string(::getpid()));
  fs::create_directories(folder);
  const std::string layout = " --layout opencv --projector-width 1024 --projector-height 0";
  const std::string images = " --images " + kFixture + layout;
  CommandResult camera = run(std::string(CALIBRATE_CAMERA_EXECUTABLE) + images + " --output " +
                             (folder / "camera.yaml").string());
  EXPECT_NE(camera.status, 0) << camera.output;  // the reference 9x6 board is not this one
  EXPECT_NE(camera.output.find("not found in 4 of 4"), std::string::npos) << camera.output;
  camera = run(std::string(CALIBRATE_CAMERA_EXECUTABLE) + images +
               " --board-cols 9 --board-rows 7 --square 0.075 --output " +
               (folder / "camera.yaml").string());
  EXPECT_EQ(camera.status, 0) << camera.output;
  EXPECT_NE(camera.output.find("capture_3"), std::string::npos) << camera.output;

  // A calibration of the set (library), then the offline scan of one pose through the CLI.
  PairCalibrationOptions options;
  options.board = kRealBoard;
  options.projector.model = StripePlaneModel::kSmooth;
  options.decoding.enabled = true;
  options.joint_refinement = false;
  const PairViews views = loadPairViews(kFixture, captureLayout("opencv"), kFixtureBits, 1);
  const PairCalibrationOutcome outcome = calibratePair(views.pose_frames, views.layout, options);
  body_scan_driver::saveCalibration((folder / "pair.yaml").string(), outcome.calibration);
  const CommandResult scan =
      run(std::string(SCAN_FOLDER_EXECUTABLE) + " --calibration " +
          (folder / "pair.yaml").string() + " --images " + kFixture + "/capture_0" + layout +
          " --output " + (folder / "cloud.ply").string());
  ASSERT_EQ(scan.status, 0) << scan.output;
  const size_t points = std::stoul(scan.output);
  std::printf("[ figure ] scan_folder capture_0 of the fixture: %zu points\n", points);
  EXPECT_GT(points, 15000u);  // two 16-row bands across the board
  EXPECT_GT(fs::file_size(folder / "cloud.ply"), points * 12);
  const CommandResult wrong_bits = run(
      std::string(SCAN_FOLDER_EXECUTABLE) + " --calibration " + (folder / "pair.yaml").string() +
      " --images " + kFixture + "/capture_0 --layout opencv --projector-width 256 --output " +
      (folder / "x.ply").string());
  EXPECT_NE(wrong_bits.status, 0);
  EXPECT_NE(wrong_bits.output.find("1024 stripe planes"), std::string::npos) << wrong_bits.output;
  fs::remove_all(folder);
}

PairCalibrationOptions realOptions(bool robust_decoding) {
  PairCalibrationOptions options;
  options.board = kRealBoard;
  options.projector.model = StripePlaneModel::kSmooth;
  options.decoding.enabled = robust_decoding;
  return options;
}

// Leave-one-pose-out on the fixture (about 5 calibrations), once for the tests below.
const PairValidation& robustValidation() {
  static const PairValidation validation = validateLeaveOnePoseOut(
      loadPairViews(kFixture, captureLayout("opencv"), kFixtureBits, 1), realOptions(true));
  return validation;
}

void printFigure(const char* name, const PlaneErrorStatistics& s) {
  std::printf(
      "[ figure ] %s: %zu points, median %.2f mm, rms %.2f mm, p95 %.2f mm, gross %.2f %%\n", name,
      s.points, s.median_mm, s.rms_mm, s.p95_mm, 100 * s.gross_share);
}

TEST(RealCaptures, EveryStripeOnABoardGetsAPlane) {
  const PairValidation& validation = robustValidation();
  std::printf("[ figure ] stripes calibrated %d of %d on a board\n", validation.stripes_calibrated,
              validation.stripes_on_board);
  EXPECT_GT(validation.stripes_on_board, 400);
  EXPECT_GE(validation.stripes_calibrated, 0.9 * validation.stripes_on_board);

  // The plane per stripe alone covers a fraction: most stripes are on fewer than 3 boards.
  const PairViews views = loadPairViews(kFixture, captureLayout("opencv"), kFixtureBits, 1);
  PairCalibrationOptions per_stripe = realOptions(true);
  per_stripe.projector.model = StripePlaneModel::kPerStripe;
  per_stripe.joint_refinement = false;
  const PairCalibrationOutcome outcome = calibratePair(views.pose_frames, views.layout, per_stripe);
  int fitted = 0;
  for (const Eigen::Vector4d& plane : outcome.planes.projector.planes) fitted += plane.allFinite();
  std::printf("[ figure ] plane per stripe alone: %d planes\n", fitted);
  EXPECT_LT(fitted, 0.7 * validation.stripes_on_board);

  // Stripes far beyond every board stay NaN; those just beyond are flagged as extrapolated.
  PairCalibrationOptions smooth = realOptions(true);
  smooth.joint_refinement = false;
  const PairCalibrationOutcome all = calibratePair(views.pose_frames, views.layout, smooth);
  const ProjectorCalibrationResult& planes = all.planes;
  EXPECT_FALSE(planes.missing_stripes.empty());
  for (int stripe : planes.missing_stripes) {
    EXPECT_EQ(planes.poses_per_stripe[stripe], 0) << stripe;
    EXPECT_FALSE(planes.projector.planes[stripe].allFinite()) << stripe;
  }
  for (int stripe : planes.extrapolated_stripes) {
    EXPECT_EQ(planes.points_per_stripe[stripe], 0) << stripe;
    EXPECT_TRUE(planes.projector.planes[stripe].allFinite()) << stripe;
  }
}

// Bounds between the robust decoding's figures and the standard decoder's on this fixture
// (robust: 62300 points, median 6.3 mm, p95 12.0 mm, gross 0.68 %; standard: 54800, p95 34.0 mm,
// gross 9.6 %; the robust decoding without its local plane fit: gross 7.3 %).
TEST(RealCaptures, LeaveOnePoseOutBoundsFailIfDecodingRegresses) {
  const PairValidation& validation = robustValidation();
  printFigure("leave-one-pose-out, ours", validation.ours.pooled);
  ASSERT_EQ(validation.ours.per_pose.size(), 4u);
  EXPECT_GT(validation.ours.pooled.points, 56000u);
  EXPECT_LT(validation.ours.pooled.median_mm, 7.0);
  EXPECT_LT(validation.ours.pooled.p95_mm, 15.0);
  EXPECT_LT(validation.ours.pooled.gross_share, 0.012);
}

}  // namespace
}  // namespace body_scan_calib
