// play_gait_cycle node: the latched GaitSequence holds a whole forward cycle facing the given
// heading, and /body_gait/model plays its frames in order (the same p, q as the sequence's
// frames, walked on by 20 v per cycle), with markers for rviz.
#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/ros/gait_sequence_msg.h>
#include <body_scan_driver/test_time_scale.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <cmath>
#include <optional>

using body_scan_driver::scaledSeconds;

namespace body_gait_model {
namespace {

TEST(PlayGaitCycle, PublishesTheSequenceAndPlaysItsFrames) {
  ros::NodeHandle nh;
  std::optional<body_scan_msgs::GaitSequence> sequence;
  std::vector<body_scan_msgs::BodyModel> models;
  int marker_arrays = 0;
  std::optional<visualization_msgs::MarkerArray> filmstrip;
  ros::Subscriber filmstrip_sub = nh.subscribe<visualization_msgs::MarkerArray>(
      "/body_gait/gait_sequence_markers", 1,
      [&](const visualization_msgs::MarkerArray::ConstPtr& msg) { filmstrip = *msg; });
  ros::Subscriber sequence_sub = nh.subscribe<body_scan_msgs::GaitSequence>(
      "/body_gait/gait_sequence", 1,
      [&](const body_scan_msgs::GaitSequence::ConstPtr& msg) { sequence = *msg; });
  ros::Subscriber model_sub = nh.subscribe<body_scan_msgs::BodyModel>(
      "/body_gait/model", 100,
      [&](const body_scan_msgs::BodyModel::ConstPtr& msg) { models.push_back(*msg); });
  ros::Subscriber marker_sub = nh.subscribe<visualization_msgs::MarkerArray>(
      "/body_gait/markers", 100,
      [&](const visualization_msgs::MarkerArray::ConstPtr&) { ++marker_arrays; });
  const ros::Time deadline = ros::Time::now() + ros::Duration(scaledSeconds(30));
  while (ros::ok() && ros::Time::now() < deadline &&
         (!sequence || !filmstrip || models.size() < 50)) {
    ros::spinOnce();
    ros::Duration(0.01).sleep();
  }
  ASSERT_TRUE(sequence) << "no latched GaitSequence on /body_gait/gait_sequence";
  ASSERT_GE(models.size(), 50u) << "the node did not play frames on /body_gait/model";
  EXPECT_GT(marker_arrays, 0);
  ASSERT_TRUE(filmstrip) << "no latched filmstrip on /body_gait/gait_sequence_markers";
  EXPECT_EQ(filmstrip->markers.size() % 20, 0u);
  EXPECT_GT(filmstrip->markers.size(), 20u);
  EXPECT_EQ(sequence->subject, "person_003");
  const GaitCycle cycle = fromMsg(*sequence);
  // A forward walk along the heading (0.5 rad) with a plausible adult stride.
  EXPECT_GT(cycle.stride_length, 0.9);
  EXPECT_LT(cycle.stride_length, 1.9);
  EXPECT_NEAR(std::atan2(cycle.velocity.y(), cycle.velocity.x()), 0.5, 1e-6);
  EXPECT_NEAR(cycle.velocity.norm(), cycle.stride_length / 20, 1e-12);

  // Every played model is a frame of the cycle (q), walked on by a whole number of cycles (p);
  // consecutive models are consecutive frames (none skipped at 50 Hz with a queue of 100).
  int previous = -1, in_order = 0;
  for (const auto& msg : models) {
    const BodyModel model = fromMsg(msg);
    int frame = -1;
    for (int f = 0; f < kGaitCycleFrames; ++f)
      if ((model.q - cycle.frames[f].q).norm() < 1e-12) frame = f;
    ASSERT_GE(frame, 0) << "a played model is no frame of the sequence";
    const Eigen::Vector3d walked = model.p.head<3>() - cycle.frames[frame].p.head<3>();
    const double cycles_walked = walked.norm() / (kGaitCycleFrames * cycle.velocity.norm());
    EXPECT_NEAR(cycles_walked, std::round(cycles_walked), 1e-9);
    EXPECT_LE(std::round(cycles_walked), 1.0) << "~cycles = 2: at most one cycle walked on";
    if (previous >= 0 && frame == (previous + 1) % kGaitCycleFrames) ++in_order;
    previous = frame;
  }
  EXPECT_GE(in_order, static_cast<int>(models.size()) - 2);
}

}  // namespace
}  // namespace body_gait_model

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_play_gait_cycle");
  ros::NodeHandle nh;  // starts the node
  return RUN_ALL_TESTS();
}
