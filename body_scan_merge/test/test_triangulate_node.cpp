#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/ros/conversions.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <body_scan_driver/test_time_scale.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>

using body_scan_driver::scaledSeconds;

using namespace body_scan_driver;

namespace {

// Publishers of `topic` registered with the master.
size_t registeredPublishers(const std::string& topic) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  if (!ros::master::execute("getSystemState", args, result, payload, true)) return 0;
  for (int i = 0; i < payload[0].size(); ++i)
    if (static_cast<std::string>(payload[0][i][0]) == topic)
      return static_cast<size_t>(payload[0][i][1].size());
  return 0;
}

class TriangulateNode : public testing::Test {
 protected:
  void SetUp() override {
    calibration_file_ = ros::NodeHandle("~").param<std::string>("calibration_file", "");
    std::remove(calibration_file_.c_str());
    auto scene = std::make_shared<body_scan_driver::sim::Scene>();
    scene->add(std::make_unique<body_scan_driver::sim::Plane>(
        Eigen::Vector3d(1.0, 0, 0), Eigen::Vector3d(-1, 0, 0),
        body_scan_driver::sim::Material{0.8, {0.8, 0.8, 0.8}}));
    body_scan_driver::sim::VirtualPairConfig config;
    config.world_from_camera = body_scan_driver::sim::cameraPose({0, 0, 0}, 0, 0);
    pair_ = std::make_unique<body_scan_driver::sim::VirtualPair>(config, scene);
    const body_scan_driver::sim::RenderedPatternSet rendered = pair_->render(1);
    std_msgs::Header header;
    header.frame_id = "test_camera_optical_frame";
    good_ = toPatternSet({rendered.frames, rendered.texture}, pair_->layout(),
                         pair_->config().camera, header, "test/pair", 1);
    publisher_ = nh_.advertise<body_scan_msgs::PatternSet>("pattern_set", 4);
    subscriber_ = nh_.subscribe("points", 4, &TriangulateNode::onCloud, this);
    for (int i = 0;
         i < 50 && (publisher_.getNumSubscribers() == 0 || subscriber_.getNumPublishers() == 0);
         ++i)
      ros::WallDuration(0.1).sleep();
    ASSERT_GT(publisher_.getNumSubscribers(), 0u) << "Triangulate did not subscribe";
  }

  // Publishes a set and waits up to `wait` seconds for a cloud; returns how many arrived.
  int publishAndCount(const body_scan_msgs::PatternSet& set, double wait) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      clouds_ = 0;
    }
    publisher_.publish(set);
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(scaledSeconds(wait));
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (clouds_ > 0) break;
      }
      ros::WallDuration(0.05).sleep();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    return clouds_;
  }

  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& cloud) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++clouds_;
    last_ = cloud;
  }

  ros::NodeHandle nh_;
  ros::Publisher publisher_;
  ros::Subscriber subscriber_;
  std::string calibration_file_;
  std::unique_ptr<body_scan_driver::sim::VirtualPair> pair_;
  body_scan_msgs::PatternSetPtr good_;
  std::mutex mutex_;
  int clouds_ = 0;
  sensor_msgs::PointCloud2::ConstPtr last_;
};

TEST_F(TriangulateNode, RejectsBadInputAndKeepsRunning) {
  // No calibration file yet: nothing published.
  EXPECT_EQ(publishAndCount(*good_, 1.5), 0);
  saveCalibration(calibration_file_, pair_->factoryCalibration());

  body_scan_msgs::PatternSet missing_frame = *good_;
  missing_frame.frames.pop_back();
  EXPECT_EQ(publishAndCount(missing_frame, 1.5), 0) << "17 frames triangulated";

  body_scan_msgs::PatternSet wrong_encoding = *good_;
  wrong_encoding.frames[4].encoding = "rgb8";
  EXPECT_EQ(publishAndCount(wrong_encoding, 1.5), 0) << "rgb8 frame accepted";

  body_scan_msgs::PatternSet wrong_scheme = *good_;
  wrong_scheme.scheme = "phase_shift";
  EXPECT_EQ(publishAndCount(wrong_scheme, 1.5), 0) << "unknown scheme accepted";

  // Still alive: the good set gives the plane at z = 1 m.
  ASSERT_EQ(publishAndCount(*good_, 10.0), 1);
  std::lock_guard<std::mutex> lock(mutex_);
  EXPECT_EQ(last_->header.frame_id, "test_camera_optical_frame");
  EXPECT_EQ(last_->width, 640u);
  EXPECT_EQ(last_->height, 480u);
  long valid = 0;
  double error = 0;
  for (sensor_msgs::PointCloud2ConstIterator<float> it(*last_, "x"); it != it.end(); ++it)
    if (std::isfinite(it[2])) {
      ++valid;
      error += std::abs(it[2] - 1.0);
    }
  EXPECT_GT(valid, 300000);
  EXPECT_LT(1000 * error / valid, 1.0) << "mean |z - 1 m| in mm";
}

// A set whose frames declare a row step smaller than their width used to throw from the
// cv::Mat constructor outside any try block and terminate the whole nodelet manager. Now: one
// error naming the field on /rosout, nothing published, and the next good set triangulates.
TEST_F(TriangulateNode, MalformedRowStepKeepsTheManagerAlive) {
  saveCalibration(calibration_file_, pair_->factoryCalibration());
  std::vector<std::string> errors;
  ros::Subscriber rosout = nh_.subscribe<rosgraph_msgs::Log>(
      "/rosout", 100, [&](const rosgraph_msgs::Log::ConstPtr& log) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (log->level >= rosgraph_msgs::Log::ERROR && log->name == "/manager")
          errors.push_back(log->msg);
      });
  // Connected to every node's /rosout (the manager's among them) before the error is logged.
  for (int i = 0; i < 100 && rosout.getNumPublishers() < registeredPublishers("/rosout"); ++i)
    ros::WallDuration(0.05).sleep();
  ASSERT_GE(rosout.getNumPublishers(), registeredPublishers("/rosout"));

  body_scan_msgs::PatternSet malformed = *good_;
  malformed.frames[0].step = malformed.frames[0].width - 1;
  EXPECT_EQ(publishAndCount(malformed, 1.5), 0) << "the malformed set was triangulated";
  ASSERT_EQ(publishAndCount(*good_, 10.0), 1) << "the manager did not survive";
  std::lock_guard<std::mutex> lock(mutex_);
  const auto named = std::count_if(errors.begin(), errors.end(), [](const std::string& e) {
    return e.find("frames[0].step 639 is less than width") != std::string::npos;
  });
  EXPECT_EQ(named, 1) << "errors from /manager: " << errors.size();
}

// World alignment (eq 4.1): a calibration whose planes scale every range by 2% carries an
// alignment whose residual linear part L = I / 1.02 undoes it; Triangulate must apply L, so the
// plane 1 m in front of the camera comes out at 1 m, not 1.02 m.
TEST_F(TriangulateNode, AppliesTheResidualLinearPartOfTheWorldAlignment) {
  constexpr double kScale = 1.02;
  body_scan_driver::PairCalibration calibration = pair_->factoryCalibration();
  for (Eigen::Vector4d& plane : calibration.projector.planes) plane[3] *= kScale;
  Eigen::Matrix<double, 3, 4> affine;
  affine << pair_->config().world_from_camera.linear() / kScale,
      pair_->config().world_from_camera.translation();
  calibration.alignment = body_scan_driver::WorldAlignment::fromAffine(affine);
  saveCalibration(calibration_file_ + ".aligned.yaml", calibration);

  ros::Publisher publisher = nh_.advertise<body_scan_msgs::PatternSet>("aligned/pattern_set", 1);
  ros::Subscriber subscriber = nh_.subscribe<sensor_msgs::PointCloud2>(
      "aligned/points", 1,
      [this](const sensor_msgs::PointCloud2::ConstPtr& cloud) { onCloud(cloud); });
  // Both links: Triangulate publishes its points only to a connected subscriber.
  for (int i = 0;
       i < 50 && (publisher.getNumSubscribers() == 0 || subscriber.getNumPublishers() == 0); ++i)
    ros::WallDuration(0.1).sleep();
  ASSERT_GT(publisher.getNumSubscribers(), 0u) << "the aligned Triangulate did not subscribe";
  ASSERT_GT(subscriber.getNumPublishers(), 0u) << "aligned/points is not connected";
  publisher_ = publisher;
  ASSERT_EQ(publishAndCount(*good_, 10.0), 1);
  std::lock_guard<std::mutex> lock(mutex_);
  long valid = 0;
  double error = 0;
  for (sensor_msgs::PointCloud2ConstIterator<float> it(*last_, "x"); it != it.end(); ++it)
    if (std::isfinite(it[2])) {
      ++valid;
      error += std::abs(it[2] - 1.0);
    }
  ASSERT_GT(valid, 300000);
  EXPECT_LT(1000 * error / valid, 1.0) << "mean |z - 1 m| in mm with L applied (20 mm without)";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_triangulate_node");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
