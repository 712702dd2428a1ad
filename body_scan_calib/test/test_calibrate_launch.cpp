// rostest of calibrate.launch against the simulator: the launch must write a calibration file
// that loadCalibration reads and whose stripe planes match the simulated pair's true (factory)
// planes, plus the accuracy report and the Fig 3.6 plot; and the driver's ~set_scene must
// refuse bad scenes with a clear message while the driver keeps serving.
#include <body_scan_calib/calibration_bag.h>
#include <body_scan_calib/calibration_capture.h>
#include <body_scan_calib/calibration_rig.h>
#include <body_scan_calib/capture_folder.h>
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <body_scan_driver/test_time_scale.h>
#include <body_scan_msgs/SetScene.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

using body_scan_driver::scaledSeconds;

using namespace body_scan_driver;
namespace fs = std::filesystem;

namespace {

// Files older than the test process are from an earlier run.
fs::file_time_type test_start;

std::string param(const std::string& name) {
  std::string value;
  if (!ros::param::get("~" + name, value)) ADD_FAILURE() << "missing test parameter ~" << name;
  return value;
}

// Waits until every file exists and was written after `start` (earlier runs leave old ones).
bool waitForFiles(const std::vector<std::string>& files, fs::file_time_type start, double timeout) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(scaledSeconds(timeout));
  while (ros::WallTime::now() < end && ros::ok()) {
    bool all = true;
    for (const std::string& file : files) {
      std::error_code error;
      all = all && fs::exists(file) && fs::last_write_time(file, error) >= start;
    }
    if (all) return true;
    ros::WallDuration(0.2).sleep();
  }
  return false;
}

double angleDeg(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  return std::acos(std::min(1.0, a.head<3>().normalized().dot(b.head<3>().normalized()))) * 180 /
         M_PI;
}

}  // namespace

TEST(SetScene, RefusesBadScenesAndTheDriverKeepsServing) {
  ros::NodeHandle nh;
  ros::ServiceClient client = nh.serviceClient<body_scan_msgs::SetScene>(param("set_scene"));
  ASSERT_TRUE(client.waitForExistence(ros::Duration(scaledSeconds(20))));
  body_scan_msgs::SetScene bad_yaml;
  bad_yaml.request.scene_yaml = "objects: [ {type: sphere";
  ASSERT_TRUE(client.call(bad_yaml));
  EXPECT_FALSE(bad_yaml.response.success);
  EXPECT_NE(bad_yaml.response.message.find("YAML"), std::string::npos) << bad_yaml.response.message;
  body_scan_msgs::SetScene bad_object;
  bad_object.request.scene_yaml = "objects:\n  - type: sphere\n    center: [0, 0]\n    radius: 1\n";
  ASSERT_TRUE(client.call(bad_object));
  EXPECT_FALSE(bad_object.response.success);
  EXPECT_NE(bad_object.response.message.find("'center' must be a list of 3 numbers"),
            std::string::npos)
      << bad_object.response.message;
  // A real pair says its scene cannot be set (the test's usb pair has no camera attached).
  ros::ServiceClient usb = nh.serviceClient<body_scan_msgs::SetScene>(param("usb_set_scene"));
  ASSERT_TRUE(usb.waitForExistence(ros::Duration(scaledSeconds(20))));
  body_scan_msgs::SetScene on_usb;
  on_usb.request.scene_yaml = "objects: []\n";
  ASSERT_TRUE(usb.call(on_usb));
  EXPECT_FALSE(on_usb.response.success);
  EXPECT_NE(on_usb.response.message.find("place the target by hand"), std::string::npos)
      << on_usb.response.message;
  // Still serving: the calibration test below needs every capture of the launch to succeed.
  EXPECT_TRUE(client.exists());
}

TEST(CalibrateLaunch, WritesACalibrationWhosePlanesMatchTheTruePlanes) {
  const auto start = test_start;
  const std::string calibration_file = param("calibration_file");
  const std::vector<std::string> files = {calibration_file, param("report_file"),
                                          param("plot_file")};
  double timeout = 240;
  ros::param::get("~timeout", timeout);
  ASSERT_TRUE(waitForFiles(files, start, timeout))
      << "calibrate.launch wrote no fresh " << calibration_file << " + report + plot within "
      << timeout << " s";
  const body_scan_driver::PairCalibration estimated = loadCalibration(calibration_file);
  const body_scan_driver::PairCalibration truth =
      body_scan_driver::sim::VirtualPair(
          body_scan_driver::sim::loadVirtualPairConfig(param("pair_file")),
          std::make_shared<body_scan_driver::sim::Scene>())
          .factoryCalibration();
  ASSERT_EQ(estimated.projector.stripeCount(), truth.projector.stripeCount());
  double worst_angle = 0, mean_angle = 0, worst_offset = 0;
  int fitted = 0;
  for (int i = 0; i < truth.projector.stripeCount(); ++i) {
    const Eigen::Vector4d& e = estimated.projector.planes[i];
    const Eigen::Vector4d& t = truth.projector.planes[i];
    if (!e.allFinite()) continue;  // seen on < 3 poses: reported, not invented
    ++fitted;
    const Eigen::Vector4d tn = t / t.head<3>().norm();
    Eigen::Vector4d en = e / e.head<3>().norm();
    if (en.head<3>().dot(tn.head<3>()) < 0) en = -en;  // one plane, either orientation
    worst_angle = std::max(worst_angle, angleDeg(en, tn));
    mean_angle += angleDeg(en, tn);
    worst_offset = std::max(worst_offset, std::abs(en[3] - tn[3]));
  }
  mean_angle /= std::max(1, fitted);
  std::printf(
      "[ figure ] calibrate.launch: %d planes; normal angle mean %.4f worst %.4f deg, "
      "worst offset %.3f mm; alpha %.2f (true %.2f)\n",
      fitted, mean_angle, worst_angle, worst_offset * 1e3, estimated.camera.alpha,
      truth.camera.alpha);
  EXPECT_GE(fitted, 150);
  EXPECT_LT(mean_angle, 0.1);
  EXPECT_LT(worst_angle, 0.2);
  EXPECT_LT(worst_offset, 0.001);
  EXPECT_NEAR(estimated.camera.alpha / truth.camera.alpha, 1.0, 0.01);
  // Named after the launch's pair, not the offline default "pair".
  EXPECT_EQ(estimated.pair_id, "pole_a/pair_1");
}

// The launch also recorded the raw pattern sets: converted offline, they give the very folder
// the live capture wrote (one exposure per pose: no averaging, frame for frame).
TEST(CalibrateLaunch, RecordedBagConvertsToTheCapturedFolder) {
  const std::string bag = param("bag"), images = param("images");
  const auto start = test_start;
  ASSERT_TRUE(waitForFiles({bag, param("plot_file")}, start, 240));
  const fs::path converted = fs::path(bag).parent_path() / "converted_from_bag";
  fs::remove_all(converted);
  const body_scan_calib::BagConversionResult result =
      body_scan_calib::bagToCalibrationFolder(bag, converted.string(), {});
  const size_t poses = body_scan_calib::rig::defaultBoardPoses().size();
  ASSERT_EQ(result.folders.size(), poses);  // the rig's poses, no spheres in this test
  int compared = 0, differing = 0;
  const body_scan_driver::PatternLayout layout(8, true);
  for (int pose = 0; pose < static_cast<int>(result.folders.size()); ++pose) {
    const std::string name = body_scan_calib::poseFolderName(pose);
    const std::vector<cv::Mat> live =
        body_scan_calib::loadPatternFrames(images + "/" + name, layout);
    const std::vector<cv::Mat> offline =
        body_scan_calib::loadPatternFrames((converted / name).string(), layout);
    ASSERT_EQ(live.size(), offline.size()) << name;
    for (size_t f = 0; f < live.size(); ++f, ++compared) {
      ASSERT_EQ(live[f].size(), offline[f].size()) << name << " frame " << f;
      differing += cv::countNonZero(live[f] != offline[f]);
    }
  }
  EXPECT_EQ(compared, static_cast<int>(poses) * 18);
  EXPECT_EQ(differing, 0);
}

int main(int argc, char** argv) {
  test_start = fs::file_time_type::clock::now() - std::chrono::seconds(1);
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_calibrate_launch");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
