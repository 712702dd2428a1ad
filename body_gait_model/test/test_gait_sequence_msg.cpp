// GaitSequence message without a master: a round trip gives the same cycle (every frame poses
// the same joints), and malformed sequences are clear errors.
#include <body_gait_model/ros/gait_sequence_msg.h>
#include <gtest/gtest.h>

#include <string>

namespace body_gait {
namespace {

GaitCycle walkCycle() {
  RepresentativePoses poses;
  const double thighs[4][2] = {{-0.4, 0.3}, {0.0, 0.25}, {0.3, -0.4}, {0.25, 0.0}};
  for (int i = 0; i < 4; ++i) {
    poses[i] = standingModel(1.7 + 0.01 * i);
    poses[i].p << 0.1, 0.2, 0.98, 0.02, 0.6, -0.01;
    poses[i].setJointAngles(kRightUpperLeg, thighs[i][0], 0.03);
    poses[i].setJointAngles(kLeftUpperLeg, thighs[i][1], -0.02);
    poses[i].setJointAngles(kLeftUpperArm, -0.5 * thighs[i][1], 0.1);
  }
  return reconstructGaitCycle(poses);
}

TEST(GaitSequenceMsg, RoundTripKeepsEveryFrame) {
  const GaitCycle cycle = walkCycle();
  std_msgs::Header header;
  header.frame_id = "world";
  header.stamp = ros::Time(12.5);
  const body_scan_msgs::GaitSequence msg = toMsg(cycle, header, "person_007");
  EXPECT_EQ(msg.subject, "person_007");
  ASSERT_EQ(msg.frames.size(), 20u);
  EXPECT_EQ(msg.representative_frames, (std::vector<int32_t>{1, 6, 11, 16}));
  EXPECT_EQ(msg.frames[7].header.frame_id, "world");
  EXPECT_EQ(msg.frames[7].segment_names.size(), 12u);
  const GaitCycle back = fromMsg(msg);
  ASSERT_EQ(back.frames.size(), cycle.frames.size());
  EXPECT_EQ(back.velocity, cycle.velocity);
  EXPECT_EQ(back.stride_length, cycle.stride_length);
  EXPECT_GT(back.stride_length, 0.5);
  for (size_t f = 0; f < cycle.frames.size(); ++f) {
    EXPECT_EQ(back.frames[f].p, cycle.frames[f].p) << "frame " << f + 1;
    EXPECT_EQ(back.frames[f].q, cycle.frames[f].q) << "frame " << f + 1;
    EXPECT_EQ(back.frames[f].r, cycle.frames[f].r) << "frame " << f + 1;
    const PosedModel a = forwardKinematics(back.frames[f]), b = forwardKinematics(cycle.frames[f]);
    EXPECT_LT((a.joint("left_hand_tip") - b.joint("left_hand_tip")).norm(), 1e-15);
    EXPECT_LT((a.joint("right_sole") - b.joint("right_sole")).norm(), 1e-15);
  }
}

TEST(GaitSequenceMsg, MalformedSequencesAreNamedErrors) {
  const body_scan_msgs::GaitSequence good = toMsg(walkCycle(), std_msgs::Header());
  auto expectError = [](const body_scan_msgs::GaitSequence& msg, const std::string& words) {
    try {
      fromMsg(msg);
      ADD_FAILURE() << "expected std::invalid_argument mentioning '" << words << "'";
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
    }
  };
  body_scan_msgs::GaitSequence short_cycle = good;
  short_cycle.frames.pop_back();
  expectError(short_cycle, "19 frames, not 20");
  body_scan_msgs::GaitSequence wrong_frames = good;
  wrong_frames.representative_frames[1] = 5;
  expectError(wrong_frames, "1, 6, 11, 16");
  body_scan_msgs::GaitSequence bad_q = good;
  bad_q.frames[3].q.resize(21);
  expectError(bad_q, "frame 4: BodyModel.q has 21 elements");
}

}  // namespace
}  // namespace body_gait
