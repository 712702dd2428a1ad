// Gait reconstruction (thesis 5.6, eqs 5.11-5.13) and symmetric poses (5.8.3): interpolation
// against its neighbours, stride and velocity against a hand-computed walk, the mirror image
// against the reflected joints.
#include <body_gait_model/gait_cycle.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180;

// Leg angles of a walking pose: forward swing of each thigh from the vertical and knee bend (rad).
struct Legs {
  double right_thigh, right_knee, left_thigh, left_knee;
};

// A pose on the standing model: q's thigh theta_x = -forward swing (a -Y cylinder swings forward
// under a negative theta_x), the knee's theta_x = +bend (the shank swings back).
BodyModel walkingPose(const Legs& legs, double heading, double stature = 1.75) {
  BodyModel pose = standingModel(stature);
  pose.p[4] = heading;
  pose.setJointAngles(kRightUpperLeg, -legs.right_thigh, 2 * kDegree);
  pose.setJointAngles(kRightLowerLeg, legs.right_knee, -1 * kDegree);
  pose.setJointAngles(kLeftUpperLeg, -legs.left_thigh, -3 * kDegree);
  pose.setJointAngles(kLeftLowerLeg, legs.left_knee, 1 * kDegree);
  // Arms swing against the legs.
  pose.setJointAngles(kRightUpperArm, legs.right_thigh * 0.8, -5 * kDegree);
  pose.setJointAngles(kLeftUpperArm, legs.left_thigh * 0.8, 5 * kDegree);
  pose.setJointAngles(kRightLowerArm, -10 * kDegree, 0);
  pose.setJointAngles(kLeftLowerArm, -12 * kDegree, 0);
  pose.setJointAngles(kUpperTorso, 4 * kDegree, 1 * kDegree);
  return pose;
}

// s1..s4 of thesis 5.3 for one heading: 1 right heel strike, 2 right mid-stance, 3 and 4 the
// left ones, with slightly different angles (a real walk is not exactly symmetric).
RepresentativePoses walk(double heading) {
  return {walkingPose({25 * kDegree, 5 * kDegree, -20 * kDegree, 15 * kDegree}, heading),
          walkingPose({0, 3 * kDegree, -15 * kDegree, 25 * kDegree}, heading),
          walkingPose({-18 * kDegree, 14 * kDegree, 24 * kDegree, 6 * kDegree}, heading),
          walkingPose({-14 * kDegree, 26 * kDegree, 1 * kDegree, 2 * kDegree}, heading)};
}

// One step by hand: both hips sit at the same forward position (offsets along X_m only), the
// sole is thigh * sin(thigh swing) + shank * sin(thigh swing - knee bend) ahead of it (the
// theta_z swings are coronal and do not move the sole forward).
double handStep(const BodyModel& pose, const Legs& legs) {
  const auto& r = pose.r;
  const double right = r[kRightUpperLeg] * std::sin(legs.right_thigh) +
                       r[kRightLowerLeg] * std::sin(legs.right_thigh - legs.right_knee);
  const double left = r[kLeftUpperLeg] * std::sin(legs.left_thigh) +
                      r[kLeftLowerLeg] * std::sin(legs.left_thigh - legs.left_knee);
  return right - left;
}

TEST(GaitCycle, RepresentativeFramesReproduceTheInputs) {
  const RepresentativePoses s = walk(0.3);
  const GaitCycle cycle = reconstructGaitCycle(s);
  ASSERT_EQ(static_cast<int>(cycle.frames.size()), kGaitCycleFrames);
  for (int i = 0; i < 4; ++i) {
    const int frame = kRepresentativeFrames[i];
    const BodyModel& model = cycle.frames[frame - 1];
    EXPECT_EQ(model.q, s[i].q) << "frame " << frame;
    EXPECT_EQ(model.p.tail<3>(), s[i].p.tail<3>()) << "frame " << frame;
    // Eq 5.11: the root has walked (f - 1) v from where the subject stood in the scanner.
    EXPECT_LT((model.p.head<3>() - (s[i].p.head<3>() + (frame - 1) * cycle.velocity)).norm(), 1e-12)
        << "frame " << frame;
  }
}

TEST(GaitCycle, InterpolatedFramesLieBetweenTheirNeighbours) {
  const RepresentativePoses s = walk(0.0);
  const GaitCycle cycle = reconstructGaitCycle(s);
  for (int frame = 1; frame <= kGaitCycleFrames; ++frame) {
    const int alpha = (frame - 1) / 5;
    const BodyModel& from = s[alpha];
    const BodyModel& to = s[(alpha + 1) % 4];  // frames 17-20: s4 -> next cycle's s1
    const double t = (frame - kRepresentativeFrames[alpha]) / 5.0;
    const JointAngles& q = cycle.frames[frame - 1].q;
    for (int i = 0; i < q.size(); ++i) {
      EXPECT_GE(q[i], std::min(from.q[i], to.q[i]) - 1e-15) << "frame " << frame << " q" << i;
      EXPECT_LE(q[i], std::max(from.q[i], to.q[i]) + 1e-15) << "frame " << frame << " q" << i;
    }
    // Eq 5.12 by hand.
    EXPECT_LT((q - (from.q + t * (to.q - from.q))).norm(), 1e-12) << "frame " << frame;
  }
  // Frame 18 is 2/5 of the way from s4 to s1: the right thigh between -14 and +25 deg forward.
  EXPECT_NEAR(-cycle.frames[17].thetaX(kRightUpperLeg), (-14 + 0.4 * (25 + 14)) * kDegree, 1e-12);
}

TEST(GaitCycle, LengthsAndShapeAreTheMeanOfTheFourPoses) {
  RepresentativePoses s = walk(0.0);
  // Four fits of one person never agree exactly on the lengths.
  const double statures[4] = {1.74, 1.76, 1.77, 1.73};
  for (int i = 0; i < 4; ++i) {
    const BodyModel shape = standingModel(statures[i]);
    s[i].r = shape.r;
    s[i].shape = shape.shape;
  }
  const GaitCycle cycle = reconstructGaitCycle(s);
  const SegmentLengths mean = (s[0].r + s[1].r + s[2].r + s[3].r) / 4;  // eq 5.13
  const double mean_shoulders = (s[0].shape.shoulder_half_width + s[1].shape.shoulder_half_width +
                                 s[2].shape.shoulder_half_width + s[3].shape.shoulder_half_width) /
                                4;
  for (const BodyModel& frame : cycle.frames) {
    EXPECT_LT((frame.r - mean).norm(), 1e-12);
    EXPECT_NEAR(frame.shape.shoulder_half_width, mean_shoulders, 1e-12);
    EXPECT_NEAR(frame.shape.proximal_radius[kHead],
                standingModel(1.75).shape.proximal_radius[kHead], 1e-12);  // 1.75 = the mean
  }
}

TEST(GaitCycle, StrideAndVelocityMatchAHandComputedWalk) {
  const double heading = 0.3;
  const Legs heel_strike_right{25 * kDegree, 5 * kDegree, -20 * kDegree, 15 * kDegree};
  const Legs heel_strike_left{-18 * kDegree, 14 * kDegree, 24 * kDegree, 6 * kDegree};
  const RepresentativePoses s = walk(heading);
  const GaitCycle cycle = reconstructGaitCycle(s);
  const BodyModel& s3 = s[2];
  const double right_step = handStep(s[0], heel_strike_right);
  const Legs s3_swapped{heel_strike_left.left_thigh, heel_strike_left.left_knee,
                        heel_strike_left.right_thigh, heel_strike_left.right_knee};
  const double left_step = handStep(s3, s3_swapped);
  // The coronal (theta_z) swings of 1-3 deg shorten the legs' sagittal reach by < 0.1 %.
  EXPECT_NEAR(cycle.stride_length, right_step + left_step, 1e-3);
  EXPECT_GT(cycle.stride_length, 1.0);  // ~1.3 m: a brisk stride for 1.75 m
  const Eigen::Vector3d front(std::cos(heading), std::sin(heading), 0);
  EXPECT_LT((cycle.velocity - cycle.stride_length / 20 * front).norm(), 1e-12);
  // Over the cycle the root advances 19 v; the next cycle's frame 1 would be one more.
  const Eigen::Vector3d walked = cycle.frames.back().p.head<3>() - cycle.frames.front().p.head<3>();
  EXPECT_LT((walked - 19 * cycle.velocity).norm(), 1e-12);
}

TEST(GaitCycle, BadPosesAreRefusedWithTheReason) {
  RepresentativePoses backwards = walk(0.0);
  std::swap(backwards[0], backwards[2]);  // s1 leads with the left foot: not thesis 5.3's s1
  try {
    reconstructGaitCycle(backwards);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("s1 must lead with the right foot"), std::string::npos)
        << error.what();
  }
  // One misfitted step backwards (a left-leading pose where s1 should be, s3 right): the other
  // step, s3's, stands in for it.
  RepresentativePoses one_back = walk(0.0);
  one_back[0] = one_back[2];
  const double left_step =
      -handStep(one_back[2], {-18 * kDegree, 14 * kDegree, 24 * kDegree, 6 * kDegree});
  ASSERT_GT(left_step, 0.2);
  EXPECT_NEAR(reconstructGaitCycle(one_back).stride_length, 2 * left_step, 1e-3);
  RepresentativePoses opposite = walk(0.0);
  opposite[2].p[4] = opposite[3].p[4] = kPi;  // two fits face the other way: no mean heading
  EXPECT_THROW(reconstructGaitCycle(opposite), std::invalid_argument);
}

// Reflection across the vertical plane through the root along the heading.
Eigen::Vector3d reflect(const BodyModel& pose, const Eigen::Vector3d& point) {
  PoseVector heading_only = PoseVector::Zero();
  heading_only[4] = pose.p[4];
  const Eigen::Matrix3d heading = wholeBodyRotation(heading_only);
  const Eigen::Vector3d root = pose.p.head<3>();
  return root +
         heading * Eigen::Vector3d(-1, 1, 1).asDiagonal() * heading.transpose() * (point - root);
}

TEST(SymmetricPoses, MirroredPoseIsTheReflectionWithSidesSwapped) {
  BodyModel pose = walk(0.7)[0];
  pose.p.head<3>() = Eigen::Vector3d(0.4, -0.3, 1.0);
  pose.p[3] = 5 * kDegree;   // leaning forward ...
  pose.p[5] = -4 * kDegree;  // ... and to one side
  pose.setJointAngles(kHead, -6 * kDegree, 7 * kDegree);
  pose.setJointAngles(kLowerTorso, 3 * kDegree, -2 * kDegree);
  pose.r[kLeftUpperArm] *= 1.05;  // an asymmetric body: lengths must follow their side
  pose.shape.distal_radius[kRightLowerLeg] *= 1.2;
  const BodyModel mirrored = mirroredPose(pose);
  const PosedModel original = forwardKinematics(pose), image = forwardKinematics(mirrored);
  for (const char* name : {"waist", "neck_base", "head_base", "head_top"})
    EXPECT_LT((image.joint(name) - reflect(pose, original.joint(name))).norm(), 1e-9) << name;
  for (const std::string joint : {"shoulder", "elbow", "hand_tip", "hip", "knee", "sole"}) {
    EXPECT_LT(
        (image.joint("left_" + joint) - reflect(pose, original.joint("right_" + joint))).norm(),
        1e-9)
        << "left_" << joint;
    EXPECT_LT(
        (image.joint("right_" + joint) - reflect(pose, original.joint("left_" + joint))).norm(),
        1e-9)
        << "right_" << joint;
  }
  EXPECT_EQ(mirrored.shape.distal_radius[kLeftLowerLeg], pose.shape.distal_radius[kRightLowerLeg]);
  // Mirroring twice gives the pose back.
  const BodyModel twice = mirroredPose(mirrored);
  EXPECT_EQ(twice.q, pose.q);
  EXPECT_EQ(twice.p, pose.p);
  EXPECT_EQ(twice.r, pose.r);
  EXPECT_TRUE(withinJointLimits(mirrored));
}

TEST(SymmetricPoses, EachSymmetricPoseIsTheMirrorOfTheOppositePhase) {
  const RepresentativePoses s = walk(0.2);
  const RepresentativePoses symmetric = symmetricPoses(s);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(symmetric[i].q, mirroredPose(s[(i + 2) % 4]).q) << i;
  // sbar1 (from s3) is again a right heel strike: right thigh forward, left back.
  EXPECT_LT(symmetric[0].thetaX(kRightUpperLeg), 0);
  EXPECT_GT(symmetric[0].thetaX(kLeftUpperLeg), 0);
  // A perfectly symmetric walk is its own symmetric set.
  RepresentativePoses even = s;
  even[2] = mirroredPose(s[0]);
  even[3] = mirroredPose(s[1]);
  const RepresentativePoses even_symmetric = symmetricPoses(even);
  for (int i = 0; i < 4; ++i) EXPECT_LT((even_symmetric[i].q - even[i].q).norm(), 1e-15) << i;
}

TEST(SymmetricPoses, GaitSetsCombineTheThesisPoses) {
  const RepresentativePoses s = walk(0.0);
  const RepresentativePoses sb = symmetricPoses(s);
  const std::map<GaitSet, std::array<const BodyModel*, 4>> expected = {
      {GaitSet::kEta1, {&s[0], &sb[1], &s[2], &sb[3]}},
      {GaitSet::kEta2, {&sb[0], &s[1], &sb[2], &s[3]}},
      {GaitSet::kEta3, {&s[0], &s[1], &s[2], &s[3]}},
  };
  for (const auto& [which, poses] : expected) {
    const RepresentativePoses set = gaitSet(s, which);
    for (int i = 0; i < 4; ++i)
      EXPECT_EQ(set[i].q, poses[i]->q) << "set " << int(which) << " pose " << i + 1;
  }
  // s and sbar differ (the walk is not symmetric), so the sets do too.
  EXPECT_GT((gaitSet(s, GaitSet::kEta1)[1].q - s[1].q).norm(), 1e-3);
  // Each training set reconstructs to a forward walk.
  EXPECT_GT(reconstructGaitCycle(gaitSet(s, GaitSet::kEta1)).stride_length, 1.0);
  EXPECT_GT(reconstructGaitCycle(gaitSet(s, GaitSet::kEta2)).stride_length, 1.0);
}

}  // namespace
}  // namespace body_gait_model
