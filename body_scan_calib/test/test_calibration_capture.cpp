// The capture side of the calibration workflow: the rig's targets as scene files render
// exactly like the intended simulator objects, averaging matches rig::captureAveraged, and a bag
// of pattern sets converts to the image folder frame for frame.
#include <body_scan_calib/calibration_bag.h>
#include <body_scan_calib/calibration_capture.h>
#include <body_scan_calib/calibration_rig.h>
#include <body_scan_calib/capture_folder.h>
#include <body_scan_calib/pattern_set_waiter.h>
#include <body_scan_calib/sim/calibration_scenes.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>

#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>

using namespace body_scan_driver;
namespace fs = std::filesystem;

namespace {

body_scan_driver::sim::VirtualPairConfig smallPair() {
  body_scan_driver::sim::VirtualPairConfig
      config;  // a posed pair, so the scene's world transform matters
  config.world_from_camera = body_scan_driver::sim::cameraPose({1.0, 0.2, 1.25}, M_PI, 0.1);
  return config;
}

int differingPixels(const std::vector<cv::Mat>& a, const std::vector<cv::Mat>& b) {
  EXPECT_EQ(a.size(), b.size());
  int differing = 0;
  for (size_t f = 0; f < std::min(a.size(), b.size()); ++f)
    differing += cv::countNonZero(a[f] != b[f]);
  return differing;
}

fs::path freshFolder(const std::string& name) {
  const fs::path folder = fs::temp_directory_path() / (name + "_" + std::to_string(getpid()));
  fs::remove_all(folder);
  return folder;
}

}  // namespace

// The rig's targets are defined once, as scene-file text (what ~set_scene receives); these
// scenes, built here from simulator objects as the rig intends them, must render identically.
TEST(CalibrationCapture, BoardSceneFileRendersTheBoardOnItsPanel) {
  const body_scan_driver::sim::VirtualPairConfig config = smallPair();
  const body_scan_calib::Checkerboard board = body_scan_calib::referenceBoard();
  const Eigen::Isometry3d pose = body_scan_calib::rig::defaultBoardPoses()[2];
  const Eigen::Isometry3d world_from_board = config.world_from_camera * pose;
  const Eigen::Vector3d facing_camera = -world_from_board.linear().col(2);
  auto intended = std::make_shared<body_scan_driver::sim::Scene>();
  intended->add(std::make_unique<body_scan_driver::sim::CheckerboardPlane>(
      world_from_board.translation(), facing_camera, world_from_board.linear().col(0),
      board.inner_cols + 1, board.inner_rows + 1, board.square_size,
      body_scan_calib::rig::kBoardLightAlbedo, body_scan_calib::rig::kBoardDarkAlbedo));
  intended->add(
      std::make_unique<body_scan_driver::sim::Plane>(  // white panel 3 mm behind the board
          world_from_board * Eigen::Vector3d(0, 0, 0.003), facing_camera,
          body_scan_driver::sim::Material{body_scan_calib::rig::kBoardLightAlbedo, {0.9, 0.9, 0.9}},
          0.5 * (board.inner_cols + 1) * board.square_size + 0.1));
  const body_scan_driver::sim::VirtualPair from_objects(config, intended);
  const body_scan_driver::sim::VirtualPair from_yaml(
      config, std::make_shared<body_scan_driver::sim::Scene>(body_scan_driver::sim::parseScene(
                  body_scan_calib::boardSceneYaml(board, pose, config.world_from_camera))));
  const body_scan_driver::sim::RenderedPatternSet expected = from_objects.render(7);
  const body_scan_driver::sim::RenderedPatternSet actual = from_yaml.render(7);
  // The board is in view: a good share of the pixels sees it (else the comparison is empty).
  EXPECT_GT(cv::countNonZero(expected.truth.surface == 0), 20000);
  EXPECT_EQ(differingPixels(expected.frames, actual.frames), 0);
  // rig::boardScene is that same text.
  EXPECT_EQ(differingPixels(expected.frames, body_scan_driver::sim::VirtualPair(
                                                 config, body_scan_calib::rig::boardScene(
                                                             board, pose, config.world_from_camera))
                                                 .render(7)
                                                 .frames),
            0);
}

TEST(CalibrationCapture, SphereSceneFileRendersTheFiveSpheres) {
  const body_scan_driver::sim::VirtualPairConfig config = smallPair();
  const auto centers = body_scan_calib::rig::defaultSphereCenters();
  auto intended = std::make_shared<body_scan_driver::sim::Scene>();
  for (const Eigen::Vector3d& center : centers)
    intended->add(std::make_unique<body_scan_driver::sim::Sphere>(
        config.world_from_camera * center, 0.025,
        body_scan_driver::sim::Material{0.7, {0.8, 0.8, 0.8}}));
  const body_scan_driver::sim::VirtualPair from_objects(config, intended);
  const body_scan_driver::sim::VirtualPair from_yaml(
      config, std::make_shared<body_scan_driver::sim::Scene>(body_scan_driver::sim::parseScene(
                  body_scan_calib::sphereSceneYaml(centers, 0.025, config.world_from_camera))));
  const body_scan_driver::sim::RenderedPatternSet expected = from_objects.render(3);
  for (int sphere = 0; sphere < 5; ++sphere)
    EXPECT_GT(cv::countNonZero(expected.truth.surface == sphere), 500) << "sphere " << sphere;
  EXPECT_EQ(differingPixels(expected.frames, from_yaml.render(3).frames), 0);
}

TEST(CalibrationCapture, AveragingMatchesTheRigProtocol) {
  const body_scan_driver::sim::VirtualPairConfig config = smallPair();
  const body_scan_driver::sim::VirtualPair pair(
      config, body_scan_calib::rig::boardScene(body_scan_calib::referenceBoard(),
                                               body_scan_calib::rig::defaultBoardPoses()[0],
                                               config.world_from_camera));
  std::vector<std::vector<cv::Mat>> captures;
  for (uint32_t id = 500; id < 503; ++id) captures.push_back(pair.render(id).frames);
  const std::vector<cv::Mat> averaged = body_scan_calib::averageCaptures(captures);
  EXPECT_GT(differingPixels(averaged, captures[0]), 10000);  // the noise did average out
  EXPECT_EQ(differingPixels(averaged, body_scan_calib::rig::captureAveraged(pair, 3, 500)), 0);
  captures[1].pop_back();
  EXPECT_THROW(body_scan_calib::averageCaptures(captures), std::invalid_argument);
}

TEST(CalibrationCapture, GroupsRunsOfConsecutiveScanIds) {
  const auto groups = body_scan_calib::groupConsecutiveScanIds({1000, 1001, 1002, 2000, 7, 8, 8});
  ASSERT_EQ(groups.size(), 4u);
  EXPECT_EQ(groups[0], (std::vector<size_t>{0, 1, 2}));
  EXPECT_EQ(groups[1], (std::vector<size_t>{3}));
  EXPECT_EQ(groups[2], (std::vector<size_t>{4, 5}));
  EXPECT_EQ(groups[3], (std::vector<size_t>{6}));  // a repeated id is a new placement
}

namespace {

constexpr int kBits = 2;  // 2 + 2 * 2 = 6 frames per set

body_scan_msgs::PatternSet randomSet(uint32_t scan_id, const std::string& pair_id,
                                     std::mt19937& random, std::vector<cv::Mat>& frames,
                                     int row_padding = 0) {
  body_scan_msgs::PatternSet set;
  set.header.frame_id = "pair_camera";
  set.pair_id = pair_id;
  set.scan_id = scan_id;
  set.scheme = "gray";
  set.bits = kBits;
  set.inverse_frames = true;
  frames.clear();
  std::uniform_int_distribution<int> grey(0, 255);
  for (int f = 0; f < 2 + 2 * kBits; ++f) {
    cv::Mat frame(24, 32, CV_8UC1);
    for (auto it = frame.begin<uchar>(); it != frame.end<uchar>(); ++it) *it = grey(random);
    frames.push_back(frame);
    sensor_msgs::Image image;
    image.encoding = "mono8";
    image.width = frame.cols;
    image.height = frame.rows;
    image.step = frame.cols + row_padding;  // padded rows must be read row by row
    image.data.assign(image.step * image.height, 0xAB);
    for (int r = 0; r < frame.rows; ++r)
      std::copy(frame.ptr<uchar>(r), frame.ptr<uchar>(r) + frame.cols,
                image.data.begin() + r * image.step);
    set.frames.push_back(image);
  }
  return set;
}

std::vector<cv::Mat> readFolder(const fs::path& folder) {
  return body_scan_calib::loadPatternFrames(folder.string(),
                                            body_scan_driver::PatternLayout(kBits, true));
}

}  // namespace

TEST(CalibrationBag, ConvertsRunsOfScanIdsToPoseFoldersFrameForFrame) {
  const fs::path folder = freshFolder("bag_to_calibration_folder");
  fs::create_directories(folder);
  const std::string bag_path = (folder / "calibration.bag").string();
  std::mt19937 random(42);
  std::vector<std::vector<cv::Mat>> pose0, pose1, spheres;
  {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    std::vector<cv::Mat> frames;
    const ros::Time stamp(100);
    for (uint32_t id : {1000u, 1001u}) {
      bag.write("/pole_a/pair_1/pattern_set", stamp,
                randomSet(id, "pole_a/pair_1", random, frames));
      pose0.push_back(frames);
    }
    bag.write("/pole_a/pair_1/pattern_set", stamp,
              randomSet(2000, "pole_a/pair_1", random, frames, 3));
    pose1.push_back(frames);
    for (uint32_t id : {3000u, 3001u, 3002u}) {
      bag.write("/pole_a/pair_1/pattern_set", stamp,
                randomSet(id, "pole_a/pair_1", random, frames));
      spheres.push_back(frames);
    }
  }
  body_scan_calib::BagConversionOptions options;
  options.spheres_last = true;
  const fs::path out = folder / "images";
  // An earlier, longer run left pose_07: it must not be read with this run's poses.
  fs::create_directories(out / "pose_07");
  fs::create_directories(out / "notes");
  const body_scan_calib::BagConversionResult result =
      body_scan_calib::bagToCalibrationFolder(bag_path, out.string(), options);
  EXPECT_EQ(result.pattern_sets, 6u);
  EXPECT_EQ(result.bits, kBits);
  ASSERT_EQ(result.folders.size(), 3u);
  EXPECT_TRUE(fs::is_directory(out / "pose_00"));
  EXPECT_TRUE(fs::is_directory(out / "pose_01"));
  EXPECT_TRUE(fs::is_directory(out / "spheres"));
  EXPECT_FALSE(fs::exists(out / "pose_02"));
  EXPECT_FALSE(fs::exists(out / "pose_07"));
  EXPECT_TRUE(fs::exists(out / "notes"));  // not the capture layout's: left alone
  // A single set is written unchanged; repeated exposures are their per-pattern mean.
  EXPECT_EQ(differingPixels(readFolder(out / "pose_01"), pose1[0]), 0);
  EXPECT_EQ(differingPixels(readFolder(out / "pose_00"), body_scan_calib::averageCaptures(pose0)),
            0);
  EXPECT_EQ(differingPixels(readFolder(out / "spheres"), body_scan_calib::averageCaptures(spheres)),
            0);
  EXPECT_GT(differingPixels(readFolder(out / "pose_00"), pose0[0]), 0);
  fs::remove_all(folder);
}

TEST(CalibrationBag, RejectsBagsWithoutOrWithSeveralPairs) {
  const fs::path folder = freshFolder("bag_to_calibration_folder_errors");
  fs::create_directories(folder);
  const std::string bag_path = (folder / "two_pairs.bag").string();
  std::mt19937 random(1);
  std::vector<cv::Mat> frames;
  {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    bag.write("/a/pattern_set", ros::Time(1), randomSet(1000, "pole_a/pair_1", random, frames));
    bag.write("/b/pattern_set", ros::Time(1), randomSet(1000, "pole_b/pair_1", random, frames));
  }
  const std::string out = (folder / "images").string();
  try {
    body_scan_calib::bagToCalibrationFolder(bag_path, out, {});
    ADD_FAILURE() << "two pairs accepted";
  } catch (const body_scan_calib::CalibrationBagError& e) {
    EXPECT_NE(std::string(e.what()).find("--pair-id"), std::string::npos) << e.what();
  }
  body_scan_calib::BagConversionOptions one_pair;
  one_pair.pair_id = "pole_b/pair_1";
  EXPECT_EQ(body_scan_calib::bagToCalibrationFolder(bag_path, out, one_pair).pattern_sets, 1u);
  one_pair.topic = "/nothing";
  EXPECT_THROW(body_scan_calib::bagToCalibrationFolder(bag_path, out, one_pair),
               body_scan_calib::CalibrationBagError);
  EXPECT_THROW(body_scan_calib::bagToCalibrationFolder((folder / "missing.bag").string(), out, {}),
               body_scan_calib::CalibrationBagError);
  fs::remove_all(folder);
}

// A set whose frames declare a row step smaller than their width (any node may publish one):
// capture_calibration_views keeps waiting for a whole set and, if none comes, its error names
// the field; the bag converter refuses it naming the field. Nothing reads past the data.
TEST(PatternSetWaiter, RejectsAMalformedSetNamingTheFieldAndKeepsTheGoodOne) {
  std::mt19937 random(7);
  std::vector<cv::Mat> frames;
  const body_scan_msgs::PatternSet good = randomSet(1000, "pole_a/pair_1", random, frames);
  body_scan_msgs::PatternSet::Ptr bad(new body_scan_msgs::PatternSet(good));
  bad->frames[0].step = bad->frames[0].width / 2;

  body_scan_calib::PatternSetWaiter waiter;
  EXPECT_NO_THROW(waiter.onPatternSet(bad));
  EXPECT_EQ(waiter.waitFor(1000, 0.0), nullptr);
  const auto rejection = waiter.rejection(1000);
  ASSERT_TRUE(rejection.has_value());
  EXPECT_NE(rejection->find("frames[0].step 16 is less than width"), std::string::npos)
      << *rejection;
  EXPECT_FALSE(waiter.rejection(1001).has_value());

  waiter.onPatternSet(body_scan_msgs::PatternSet::ConstPtr(new body_scan_msgs::PatternSet(good)));
  const auto received = waiter.waitFor(1000, 0.0);
  ASSERT_NE(received, nullptr);
  EXPECT_EQ(differingPixels(body_scan_calib::patternFrames(*received), frames), 0);

  try {
    body_scan_calib::patternFrames(*bad);
    ADD_FAILURE() << "a set with step < width was read";
  } catch (const body_scan_calib::CalibrationBagError& e) {
    EXPECT_NE(std::string(e.what()).find("scan 1000 (pole_a/pair_1): frames[0].step"),
              std::string::npos)
        << e.what();
  }
}
