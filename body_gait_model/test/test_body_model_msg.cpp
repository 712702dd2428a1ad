// ROS side of the body model without a master: the TF chain of modelTransforms composes to
// forwardKinematics' segment frames, a message round trip poses the same model, clouds in
// float32/float64 layouts are read with NaNs skipped, and bad clouds are clear errors.
#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/urdf.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>

namespace body_gait_model {
namespace {

BodyModel posedModel() {
  BodyModel model = standingModel(1.8);
  model.p << 0.3, -0.2, 0.95, 0.05, 0.7, -0.04;
  model.setJointAngles(kRightUpperLeg, 0.4, 0.05);
  model.setJointAngles(kRightLowerLeg, -0.3, 0.0);
  model.setJointAngles(kLeftUpperArm, -0.35, 0.2);
  model.setJointAngles(kHead, 0.1, -0.05);
  return model;
}

Eigen::Isometry3d isometry(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() << t.translation.x, t.translation.y, t.translation.z;
  pose.linear() =
      Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).toRotationMatrix();
  return pose;
}

TEST(BodyModelMsg, TransformsComposeToTheForwardKinematics) {
  const BodyModel model = posedModel();
  std_msgs::Header header;
  header.frame_id = "world";
  std::map<std::string, Eigen::Isometry3d> world;  // frame -> world pose
  world["world"] = Eigen::Isometry3d::Identity();
  const auto transforms = modelTransforms(model, header, "bg/");
  for (const auto& t : transforms) {  // parents are published before their children
    ASSERT_TRUE(world.count(t.header.frame_id)) << t.child_frame_id;
    world[t.child_frame_id] = world[t.header.frame_id] * isometry(t.transform);
  }
  EXPECT_EQ(transforms.size(), 1u + 11 * 2 + 1);  // body, 11 two-joint segments, the neck
  const PosedModel posed = forwardKinematics(model);
  EXPECT_TRUE(world.at("bg/body").isApprox(posed.whole_body, 1e-9));
  for (int s = 0; s < kSegmentCount; ++s)
    EXPECT_TRUE(
        world.at(std::string("bg/") + segmentInfo(s).name).isApprox(posed.segments[s].frame, 1e-9))
        << segmentInfo(s).name;
  // Every link of the URDF has a frame.
  const std::string urdf = modelUrdf(model, "body", "bg/");
  for (const auto& entry : world) {
    if (entry.first == "world") continue;
    EXPECT_NE(urdf.find("<link name=\"" + entry.first + "\""), std::string::npos) << entry.first;
  }
}

TEST(BodyModelMsg, RoundTripPosesTheSameModel) {
  BodyFit fit;
  fit.model = posedModel();
  fit.model.shape.hip_rise = 0.07;
  fit.model.shape.hip_back = 0.034;
  fit.quality.low_quality = true;
  fit.quality.reason = "test";
  const auto msg = toMsg(fit, std_msgs::Header(), 0.25);
  EXPECT_EQ(msg.q.size(), 22u);
  EXPECT_TRUE(msg.low_quality);
  const PosedModel a = forwardKinematics(fit.model), b = forwardKinematics(fromMsg(msg));
  for (const char* joint : {"head_top", "left_hand_tip", "right_sole", "left_hip"})
    EXPECT_LT((a.joint(joint) - b.joint(joint)).norm(), 1e-12) << joint;
  auto short_msg = msg;
  short_msg.r.pop_back();
  EXPECT_THROW(fromMsg(short_msg), std::invalid_argument);
  auto nan_msg = msg;
  nan_msg.q[7] = std::numeric_limits<double>::quiet_NaN();
  try {
    fromMsg(nan_msg);
    ADD_FAILURE() << "a NaN joint angle was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "BodyModel.q[7] is not finite");
  }
  const auto states = jointStates(fit.model, std_msgs::Header());
  EXPECT_EQ(states.name, urdfJointNames());
  EXPECT_DOUBLE_EQ(states.position[jointAngleIndex(kRightUpperLeg)], 0.4);
}

TEST(BodyModelMsg, ReadsCloudLayoutsAndRejectsBadOnes) {
  const Cloud points = {{1, 2, 3}, {-1, 0.5, 2}};
  EXPECT_EQ(cloudFromMsg(cloudToMsg(points, std_msgs::Header())), points);
  // float64 x, y, z after a padding field, with one NaN point (skipped).
  sensor_msgs::PointCloud2 msg;
  msg.width = 3;
  msg.height = 1;
  msg.point_step = 32;
  msg.row_step = 96;
  const char* names[3] = {"x", "y", "z"};
  for (uint32_t i = 0; i < 3; ++i) {
    sensor_msgs::PointField field;
    field.name = names[i];
    field.offset = 8 + 8 * i;
    field.datatype = sensor_msgs::PointField::FLOAT64;
    field.count = 1;
    msg.fields.push_back(field);
  }
  msg.data.resize(96);
  const double values[3][3] = {
      {1, 2, 3}, {std::numeric_limits<double>::quiet_NaN(), 0, 0}, {4, 5, 6}};
  for (int p = 0; p < 3; ++p) std::memcpy(msg.data.data() + 32 * p + 8, values[p], 24);
  const Cloud read = cloudFromMsg(msg);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[1], Eigen::Vector3d(4, 5, 6));
  auto no_z = msg;
  no_z.fields.pop_back();
  EXPECT_THROW(cloudFromMsg(no_z), std::invalid_argument);
  auto short_data = msg;
  short_data.data.resize(50);
  EXPECT_THROW(cloudFromMsg(short_data), std::invalid_argument);
  // An offset near 2^31 must not wrap around into the point.
  auto far_field = msg;
  far_field.fields[0].offset = 0x7FFFFFFCu;
  EXPECT_THROW(cloudFromMsg(far_field), std::invalid_argument);
}

}  // namespace
}  // namespace body_gait_model
