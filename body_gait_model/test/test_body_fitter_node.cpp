// BodyFitter node: a simulated body cloud on /body_scan/cloud gives a BodyModel whose joints are
// within the core fitter's figures of the simulator's true skeleton, with markers and the URDF;
// the calibration cylinder gives low_quality; an empty or non-world cloud gives no model and
// the node keeps running; a walk's 4 clouds (ids from their scan reports) give 4 models with the
// walk id and pose index and the walk's gait cycle.
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <body_gait_model/ros/body_model_msg.h>
#include <body_scan_driver/test_time_scale.h>
#include <body_scan_msgs/GaitSequence.h>
#include <body_scan_msgs/ScanReport.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <algorithm>
#include <cmath>
#include <optional>

using body_scan_driver::scaledSeconds;

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;

class BodyFitterNode : public ::testing::Test {
 protected:
  void SetUp() override {
    cloud_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("/body_scan/cloud", 1);
    model_sub_ = nh_.subscribe("/body_gait/model", 4, &BodyFitterNode::onModel, this);
    marker_sub_ = nh_.subscribe("/body_gait/markers", 4, &BodyFitterNode::onMarkers, this);
    const ros::Time deadline = ros::Time::now() + ros::Duration(scaledSeconds(20));
    while (ros::ok() && cloud_pub_.getNumSubscribers() == 0 && ros::Time::now() < deadline)
      ros::Duration(0.05).sleep();
    ASSERT_GT(cloud_pub_.getNumSubscribers(), 0u) << "the body fitter did not subscribe";
  }

  void onModel(const body_scan_msgs::BodyModel::ConstPtr& msg) { models_.push_back(*msg); }
  void onMarkers(const visualization_msgs::MarkerArray::ConstPtr& msg) { markers_.push_back(*msg); }

  // Publishes cloud with a fresh stamp; returns the model of that stamp, if one arrives. The
  // cloud is published again every 3 s: the node's queue holds one cloud, and a cloud sent while
  // a previous test's connection is still being torn down can be lost (1 run in 5 under load).
  std::optional<body_scan_msgs::BodyModel> fit(const Cloud& cloud, const std::string& frame,
                                               double timeout = 15) {
    std_msgs::Header header;
    header.frame_id = frame;
    header.stamp = ros::Time::now();
    const sensor_msgs::PointCloud2 message = cloudToMsg(cloud, header);
    const ros::Time deadline = ros::Time::now() + ros::Duration(scaledSeconds(timeout));
    for (ros::Time next_publish; ros::ok() && ros::Time::now() < deadline;) {
      if (ros::Time::now() >= next_publish) {
        cloud_pub_.publish(message);
        next_publish = ros::Time::now() + ros::Duration(3.0);
      }
      ros::spinOnce();
      for (const auto& model : models_)
        if (model.header.stamp == header.stamp) return model;
      ros::Duration(0.02).sleep();
    }
    return std::nullopt;
  }

  ros::NodeHandle nh_;
  ros::Publisher cloud_pub_;
  ros::Subscriber model_sub_, marker_sub_;
  std::vector<body_scan_msgs::BodyModel> models_;
  std::vector<visualization_msgs::MarkerArray> markers_;
};

TEST_F(BodyFitterNode, FitsASimulatedBodyCloud) {
  auto spec = eval::simulatedSubjects(2)[1];
  spec.pose = eval::gaitPose(2, 0.8);
  eval::ScanRig rig;
  rig.columns = 200;
  rig.rows = 162;
  rig.noise_sigma = 0.002;
  const auto body = eval::sampleBody(spec, rig);
  const auto msg = fit(body.points, "world");
  ASSERT_TRUE(msg) << "no model for the body cloud";
  EXPECT_EQ(msg->header.frame_id, "world");
  ASSERT_EQ(msg->segment_names.size(), 12u);
  EXPECT_EQ(msg->segment_names[0], "upper_torso");
  EXPECT_FALSE(msg->low_quality) << msg->reason;
  EXPECT_GT(msg->fit_seconds, 0.0);
  const BodyModel model = fromMsg(*msg);
  const eval::FitErrors errors = eval::compareWithTruth(model, body);
  // The core fitter's figures (test_body_fitter: mean joint error <= 35 mm, swing <= 4 deg).
  EXPECT_LE(errors.mean_joint_error, 0.035);
  EXPECT_LE(errors.mean_swing_error, 4 * kPi / 180);
  EXPECT_TRUE(errors.front_right && errors.left_right);
  std::printf("[ figure ] node fit: mean joint error %.1f mm, %.1f ms, RMS %.1f mm\n",
              1000 * errors.mean_joint_error, 1000 * msg->fit_seconds, 1000 * msg->rms_distance);

  // Markers of the same fit: 12 segments + the joints, green.
  const ros::Time deadline = ros::Time::now() + ros::Duration(scaledSeconds(5));
  while (ros::ok() && ros::Time::now() < deadline &&
         (markers_.empty() || markers_.back().markers.at(0).header.stamp != msg->header.stamp)) {
    ros::spinOnce();
    ros::Duration(0.02).sleep();
  }
  ASSERT_FALSE(markers_.empty());
  ASSERT_EQ(markers_.back().markers.size(), 13u);
  EXPECT_GT(markers_.back().markers[0].color.g, markers_.back().markers[0].color.r);
  // The URDF of this fit.
  std::string urdf;
  ASSERT_TRUE(nh_.getParam("/robot_description", urdf));
  EXPECT_NE(urdf.find("body_gait/left_lower_leg"), std::string::npos);
}

TEST_F(BodyFitterNode, FlagsTheCalibrationCylinderLowQuality) {
  Cloud cylinder;  // 0.15 m radius, 1.8 m tall, standing on the floor
  for (int i = 0; i < 60000; ++i) {
    const double angle = 2 * kPi * (i % 300) / 300.0, height = 1.8 * (i / 300) / 200.0;
    cylinder.emplace_back(0.15 * std::cos(angle), 0.15 * std::sin(angle), height);
  }
  const auto msg = fit(cylinder, "world");
  ASSERT_TRUE(msg) << "no model for the cylinder";
  EXPECT_TRUE(msg->low_quality);
  EXPECT_FALSE(msg->reason.empty());
  ros::Duration(0.3).sleep();
  ros::spinOnce();
  ASSERT_FALSE(markers_.empty());
  EXPECT_GT(markers_.back().markers[0].color.r, markers_.back().markers[0].color.g);  // red
}

TEST_F(BodyFitterNode, RejectsEmptyAndNonWorldCloudsAndKeepsRunning) {
  EXPECT_FALSE(fit({}, "world", 1.5)) << "an empty cloud gave a model";
  Cloud few(10, Eigen::Vector3d(0, 0, 1));
  EXPECT_FALSE(fit(few, "world", 1.5)) << "10 points gave a model";
  auto spec = eval::simulatedSubjects(1)[0];
  eval::ScanRig rig;
  rig.columns = 120;
  rig.rows = 100;
  const auto body = eval::sampleBody(spec, rig);
  EXPECT_FALSE(fit(body.points, "pole_a/pair_1_camera_optical_frame", 1.5))
      << "a cloud outside the world frame was fitted";
  EXPECT_TRUE(fit(body.points, "world")) << "the node stopped fitting after bad clouds";
}

TEST_F(BodyFitterNode, FitsAWalksFourCloudsAndPublishesItsGaitCycle) {
  ros::Publisher report_pub =
      nh_.advertise<body_scan_msgs::ScanReport>("/body_scan/scan_report", 8);
  std::vector<body_scan_msgs::GaitSequence> sequences;
  ros::Subscriber sequence_sub = nh_.subscribe<body_scan_msgs::GaitSequence>(
      "/body_gait/gait_sequence", 2,
      [&](const body_scan_msgs::GaitSequenceConstPtr& msg) { sequences.push_back(*msg); });
  for (const ros::Time end = ros::Time::now() + ros::Duration(scaledSeconds(10));
       ros::ok() && ros::Time::now() < end && report_pub.getNumSubscribers() == 0;)
    ros::Duration(0.02).sleep();
  ASSERT_GT(report_pub.getNumSubscribers(), 0u) << "the fitter does not read scan reports";
  const eval::SimulatedPerson person = eval::simulatedPeople(1)[0];
  eval::ScanRig rig;
  rig.columns = 160;
  rig.rows = 130;
  std::vector<ros::Time> stamps;
  for (int pose = 1; pose <= 4; ++pose) {
    const auto body = eval::sampleBody(eval::walkingSubject(person, pose, 0, 0.0), rig);
    std_msgs::Header header;
    header.frame_id = "world";
    header.stamp = ros::Time::now();
    stamps.push_back(header.stamp);
    body_scan_msgs::ScanReport report;
    report.header = header;
    report.scan_id = 100 + pose;
    report.walk_id = 9;
    report.pose_index = pose;
    // The report before its cloud (as Merge sends them) and after it: both pair up by stamp.
    if (pose % 2) report_pub.publish(report);
    cloud_pub_.publish(cloudToMsg(body.points, header));
    if (pose % 2 == 0) {
      ros::Duration(0.2).sleep();
      report_pub.publish(report);
    }
  }
  const ros::Time deadline = ros::Time::now() + ros::Duration(scaledSeconds(30));
  while (ros::ok() && ros::Time::now() < deadline && sequences.empty()) {
    ros::spinOnce();
    ros::Duration(0.02).sleep();
  }
  ASSERT_EQ(sequences.size(), 1u) << "no gait cycle for the walk";
  EXPECT_EQ(sequences[0].walk_id, 9u);
  EXPECT_EQ(sequences[0].frames.size(), 20u);
  ros::spinOnce();
  for (int pose = 1; pose <= 4; ++pose) {
    const auto model = std::find_if(models_.begin(), models_.end(), [&](const auto& m) {
      return m.header.stamp == stamps[pose - 1];
    });
    ASSERT_NE(model, models_.end()) << "no model of pose " << pose;
    EXPECT_EQ(model->walk_id, 9u);
    EXPECT_EQ(model->pose_index, pose);
    EXPECT_EQ(model->scan_id, 100u + pose);
    EXPECT_FALSE(model->low_quality) << "pose " << pose << ": " << model->reason;
  }
  std::printf("[ figure ] walk of 4 clouds: 4 models, gait cycle of %zu frames, stride %.2f m\n",
              sequences[0].frames.size(), sequences[0].stride_length);
}

}  // namespace
}  // namespace body_gait_model

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_body_fitter_node");
  ros::NodeHandle nh;  // starts the node
  return RUN_ALL_TESTS();
}
