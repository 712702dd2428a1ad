// Enrolment poses (thesis 5.8.3): eta1 = {s1, sb2, s3, sb4} and eta2 = {sb1, s2, sb3, s4},
// each a 20-frame cycle; the representative frames (1, 6, 11, 16) carry those poses.
#include <body_gait_id/enrollment.h>
#include <gtest/gtest.h>

namespace body_gait_id {
namespace {

body_gait_model::RepresentativePoses walkingPoses() {
  body_gait_model::RepresentativePoses s;
  const double swing[4] = {0.35, 0.1, -0.3, -0.05};
  for (int i = 0; i < 4; ++i) {
    s[i] = body_gait_model::standingModel(1.72);
    s[i].p << 0.05 * i, 0, 0.95, 0, 0.1, 0;
    s[i].setJointAngles(body_gait_model::kRightUpperLeg, -swing[i], 0.02);
    s[i].setJointAngles(body_gait_model::kLeftUpperLeg, swing[i], -0.03);
    s[i].setJointAngles(body_gait_model::kRightUpperArm, swing[i], -0.1);
    s[i].setJointAngles(body_gait_model::kRightLowerLeg, 0.2 + 0.1 * i, 0);
  }
  return s;
}

TEST(Enrollment, TwoSequencesOfTwentyWithTheRepresentativePoses) {
  const body_gait_model::RepresentativePoses s = walkingPoses();
  const std::vector<PoseRecord> poses = trainingPoses(s);
  ASSERT_EQ(poses.size(), 40u);
  for (int i = 0; i < 40; ++i) {
    EXPECT_EQ(poses[i].sequence, i / 20);
    EXPECT_EQ(poses[i].frame, i % 20 + 1);
  }
  const auto at = [&](int sequence, int frame) { return poses[sequence * 20 + frame - 1].model; };
  // The symmetric pose sb_i is s_{i+2} mirrored: half a cycle later the other leg is where
  // this one was (5.8.3).
  const auto mirrored = [&](int i) { return body_gait_model::mirroredPose(s[(i + 2) % 4]); };
  for (int i = 0; i < 4; ++i) {
    const int frame = body_gait_model::kRepresentativeFrames[i];
    // eta1 takes s1 and s3 as they are, s2 and s4 mirrored; eta2 the other way round.
    const body_gait_model::BodyModel eta1 = i % 2 == 0 ? s[i] : mirrored(i);
    const body_gait_model::BodyModel eta2 = i % 2 == 0 ? mirrored(i) : s[i];
    EXPECT_LT((at(0, frame).q - eta1.q).norm(), 1e-12) << "eta1, s" << i + 1;
    EXPECT_LT((at(1, frame).q - eta2.q).norm(), 1e-12) << "eta2, s" << i + 1;
  }
  // The two sequences differ (mirrored swings), and eq 5.13 keeps r constant.
  EXPECT_GT((at(0, 1).q - at(1, 1).q).norm(), 0.1);
  EXPECT_LT((at(0, 3).r - at(1, 17).r).norm(), 1e-12);
}

TEST(Enrollment, NeedsExactlyFourPoses) {
  const body_gait_model::RepresentativePoses s = walkingPoses();
  EXPECT_NO_THROW(representativePoses({s[0], s[1], s[2], s[3]}));
  try {
    representativePoses({s[0], s[1], s[2]});
    FAIL() << "3 poses must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exactly 4"), std::string::npos) << e.what();
  }
}

// The median of the four fits: one bad fit of a segment does not move it, the angles stay.
TEST(Enrollment, MedianBodyIgnoresOneBadFit) {
  body_gait_model::RepresentativePoses s;
  const double thigh[4] = {0.42, 0.44, 0.60, 0.43};  // pose 3's thigh badly fitted
  for (int i = 0; i < 4; ++i) {
    s[i] = body_gait_model::standingModel(1.75);
    s[i].r[body_gait_model::kRightUpperLeg] = thigh[i];
    s[i].shape.hip_half_width = 0.08 + 0.01 * i;
    s[i].q[3] = 0.1 * i;
  }
  const body_gait_model::RepresentativePoses m = withMedianBody(s);
  for (int i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(m[i].r[body_gait_model::kRightUpperLeg], 0.435);  // (0.43 + 0.44) / 2
    EXPECT_DOUBLE_EQ(m[i].shape.hip_half_width, 0.095);
    EXPECT_EQ(m[i].q, s[i].q);
    EXPECT_EQ(m[i].p, s[i].p);
  }
}

}  // namespace
}  // namespace body_gait_id
