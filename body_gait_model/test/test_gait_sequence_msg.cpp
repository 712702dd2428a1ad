// GaitSequence message without a master: a round trip gives the same cycle (every frame poses
// the same joints), and malformed sequences are clear errors.
#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/ros/gait_sequence_msg.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <string>

namespace body_gait_model {
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

TEST(GaitSequenceMsg, FilmstripShowsEveryFrameSpacedAlongTheWalk) {
  const GaitCycle cycle = walkCycle();
  std_msgs::Header header;
  header.frame_id = "world";
  const double spacing = 0.5;
  const auto strip = gaitSequenceMarkers(cycle, header, spacing, Eigen::Vector3d(0, -1, 0));
  const size_t per_frame = modelMarkers(cycle.frames[0], false, header).markers.size();
  ASSERT_EQ(strip.markers.size(), 20 * per_frame);
  std::set<std::pair<std::string, int>> keys;
  int blue = 0;
  for (const auto& marker : strip.markers) {
    keys.insert({marker.ns, marker.id});
    blue += marker.color.b > 0.5f && marker.ns.find("segments") != std::string::npos;
  }
  EXPECT_EQ(keys.size(), strip.markers.size()) << "every marker needs its own (ns, id)";
  EXPECT_EQ(blue, 4 * 12) << "the 12 segments of frames 1, 6, 11 and 16";
  // Frame 11's waist (the joints marker's 4th point) lies 10 spacings along the walk from frame
  // 1's, where the cycle's own frames are 10 v apart.
  auto waist = [&](int frame) {
    for (const auto& marker : strip.markers) {
      char ns[32];
      std::snprintf(ns, sizeof(ns), "frame_%02d/joints", frame);
      if (marker.ns == ns)
        return Eigen::Vector3d(marker.points[3].x, marker.points[3].y, marker.points[3].z);
    }
    return Eigen::Vector3d(Eigen::Vector3d::Constant(NAN));
  };
  const Eigen::Vector3d expected = cycle.frames[10].p.head<3>() - cycle.frames[0].p.head<3>() +
                                   10 * (spacing * cycle.velocity.normalized() - cycle.velocity);
  EXPECT_LT((waist(11) - waist(1) - expected).norm(), 1e-9);
  EXPECT_NEAR((waist(11) - waist(1)).dot(cycle.velocity.normalized()), 10 * spacing, 0.05);
}

}  // namespace
}  // namespace body_gait_model
