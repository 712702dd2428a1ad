// Kinematic model (thesis 5.4): forward kinematics of known poses against hand-computed joint
// centres, Table 5.2 bounds, and the tapered-cylinder distance against analytic cases.
#include <body_gait_model/kinematic_model.h>
#include <gtest/gtest.h>

#include <cmath>

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;

void expectNear(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected, double tolerance,
                const char* what) {
  EXPECT_LT((actual - expected).norm(), tolerance)
      << what << ": got " << actual.transpose() << ", expected " << expected.transpose();
}

TEST(KinematicModel, VectorSizesMatchTheThesis) {
  BodyModel model;
  EXPECT_EQ(model.p.size(), 6);   // eq 5.1
  EXPECT_EQ(model.q.size(), 22);  // eq 5.2
  EXPECT_EQ(model.r.size(), 12);  // eq 5.3
  // q covers every segment but the neck, two angles each, in part-ID order.
  int expected_index = 0;
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    if (segment == kNeck) {
      EXPECT_EQ(jointAngleIndex(segment), -1);
      continue;
    }
    EXPECT_EQ(jointAngleIndex(segment), expected_index) << segmentInfo(segment).name;
    expected_index += 2;
  }
  EXPECT_EQ(expected_index, 22);
}

TEST(KinematicModel, UprightModelStandsAlongWorldZFacingX) {
  BodyModel model = standingModel(1.75);
  model.p.head<3>() = Eigen::Vector3d(0.5, -0.2, 1.0);
  const PosedModel posed = forwardKinematics(model);
  const Eigen::Vector3d waist(0.5, -0.2, 1.0);
  const auto& r = model.r;
  const BodyShape& shape = model.shape;
  expectNear(posed.joint("waist"), waist, 1e-12, "waist");
  expectNear(posed.joint("neck_base"), waist + Eigen::Vector3d(0, 0, r[kUpperTorso]), 1e-12,
             "neck base");
  expectNear(posed.joint("head_top"),
             waist + Eigen::Vector3d(0, 0, r[kUpperTorso] + r[kNeck] + r[kHead]), 1e-12,
             "head top");
  // X_m = world +y is the subject's left.
  const Eigen::Vector3d left_shoulder =
      waist + Eigen::Vector3d(0, shape.shoulder_half_width, r[kUpperTorso] - shape.shoulder_drop);
  expectNear(posed.joint("left_shoulder"), left_shoulder, 1e-12, "left shoulder");
  expectNear(posed.joint("left_hand_tip"),
             left_shoulder - Eigen::Vector3d(0, 0, r[kLeftUpperArm] + r[kLeftLowerArm]), 1e-12,
             "left hand tip");
  // World +x is the front (Z_m): the hips sit hip_back behind the lower torso's axis.
  ASSERT_GT(shape.hip_back, 0.01);
  const Eigen::Vector3d right_hip = waist + Eigen::Vector3d(-shape.hip_back, -shape.hip_half_width,
                                                            -(r[kLowerTorso] - shape.hip_rise));
  expectNear(posed.joint("right_hip"), right_hip, 1e-12, "right hip");
  expectNear(posed.joint("right_sole"),
             right_hip - Eigen::Vector3d(0, 0, r[kRightUpperLeg] + r[kRightLowerLeg]), 1e-12,
             "right sole");
  // The standing model of 1.75 m reaches the floor and about its stature.
  EXPECT_NEAR(posed.joint("right_sole").z() - waist.z() + 0.58 * 1.75, 0.0, 0.02);
  EXPECT_NEAR(posed.joint("head_top").z() - waist.z() + 0.58 * 1.75, 1.75, 0.02);
}

TEST(KinematicModel, JointAnglesSwingLimbsAboutTheirJoints) {
  BodyModel model = standingModel(1.75);
  // Knee bent by 30 degrees about X_m: the lower leg swings in the sagittal plane about the
  // knee, its length kept; then the whole body turned by 90 degrees about the vertical.
  const double angle = kPi / 6;
  model.setJointAngles(kLeftLowerLeg, angle, 0);
  model.setJointAngles(kRightUpperArm, 0, kPi / 18);
  model.p[4] = kPi / 2;  // heading: facing world +y
  const PosedModel posed = forwardKinematics(model);
  const Eigen::Vector3d knee = posed.joint("left_knee");
  const Eigen::Vector3d sole = posed.joint("left_sole");
  EXPECT_NEAR((sole - knee).norm(), model.r[kLeftLowerLeg], 1e-12);
  // Rx(+a) turns -Y toward -Z_m: the foot goes backward, i.e. world -y after the turn.
  const double l = model.r[kLeftLowerLeg];
  expectNear(sole - knee, Eigen::Vector3d(0, -l * std::sin(angle), -l * std::cos(angle)), 1e-12,
             "lower leg");
  // Facing +y, the subject's left (X_m) is world -x: the left knee has x < right knee's.
  EXPECT_LT(knee.x(), posed.joint("right_knee").x());
  // Rz(+a) turns the right upper arm's -Y toward +X_m (the midline): hand moves inward.
  const Eigen::Vector3d arm = posed.joint("right_elbow") - posed.joint("right_shoulder");
  const Eigen::Vector3d left = wholeBodyRotation(model.p).col(0);
  EXPECT_NEAR(arm.normalized().dot(left), std::sin(kPi / 18), 1e-12);
}

TEST(KinematicModel, WholeBodyRotationIsRightHandedAndMatchesHeading) {
  PoseVector p = PoseVector::Zero();
  for (double heading : {0.0, 0.7, -2.5}) {
    p[4] = heading;
    const Eigen::Matrix3d rotation = wholeBodyRotation(p);
    EXPECT_NEAR(rotation.determinant(), 1.0, 1e-12);
    // Front (Z_m) = (cos, sin, 0) of the heading in the world; up stays world z.
    expectNear(rotation.col(2), Eigen::Vector3d(std::cos(heading), std::sin(heading), 0), 1e-12,
               "front");
    expectNear(rotation.col(1), Eigen::Vector3d::UnitZ(), 1e-12, "up");
    expectNear(rotation.col(0), rotation.col(1).cross(rotation.col(2)), 1e-12, "left = up x front");
  }
}

TEST(KinematicModel, DirectionsAndFramesInvertForwardKinematics) {
  BodyModel model = standingModel(1.7);
  model.p << 0.3, -0.1, 1.0, 0.05, 2.8, -0.04;
  model.setJointAngles(kHead, 0.3, -0.2);
  model.setJointAngles(kLeftUpperLeg, -0.5, 0.1);
  const PosedModel posed = forwardKinematics(model);
  const PoseVector p =
      poseVectorFromFrame(posed.whole_body.translation(), posed.whole_body.linear());
  EXPECT_LT((p - model.p).norm(), 1e-12) << p.transpose();
  for (int segment : {kHead, kLeftUpperLeg}) {
    const PosedSegment& child = posed.segments[segment];
    const int parent = segmentInfo(segment).parent;
    const Eigen::Vector3d direction = posed.segments[parent].frame.linear().transpose() *
                                      (child.distal - child.proximal).normalized();
    const Eigen::Vector2d angles =
        jointAnglesForDirection(direction, segmentInfo(segment).points_up);
    EXPECT_NEAR(angles[0], model.thetaX(segment), 1e-12) << segmentInfo(segment).name;
    EXPECT_NEAR(angles[1], model.thetaZ(segment), 1e-12) << segmentInfo(segment).name;
  }
}

// A real swing knee flexes 60-70 deg: the walking set holds it, Table 5.2's (30 deg) does not,
// and the bound a clamped angle lands on is named.
TEST(KinematicModel, WalkingLimitsHoldASwingKneeAndNameTheBoundsReached) {
  BodyModel model = standingModel(1.7);
  const double knee = 65 * kPi / 180, elbow = -40 * kPi / 180, hip = -32 * kPi / 180;
  model.setJointAngles(kRightLowerLeg, knee, 0);
  model.setJointAngles(kRightLowerArm, elbow, 0);
  model.setJointAngles(kLeftUpperLeg, hip, 0);
  EXPECT_TRUE(withinJointLimits(model, walkingJointLimits()));
  EXPECT_FALSE(withinJointLimits(model, thesisJointLimits()));
  EXPECT_TRUE(jointLimitsReached(model, walkingJointLimits()).empty());
  EXPECT_GE(walkingJointLimits()[kLeftLowerLeg].x_max, 75 * kPi / 180);  // the knee
  // Flexion is +theta_x of the lower leg: the shank's far end swings backward (-Z_m).
  const PosedModel posed = forwardKinematics(model);
  const Eigen::Vector3d shank = posed.segments[kRightLowerLeg].distal - posed.joint("right_knee");
  EXPECT_LT(shank.dot(posed.whole_body.linear().col(2)), -0.1);
  model.setJointAngles(kRightLowerLeg, 2.0, 0);  // 115 deg
  const BodyModel clamped = clampToJointLimits(model, walkingJointLimits());
  EXPECT_DOUBLE_EQ(clamped.thetaX(kRightLowerLeg), walkingJointLimits()[kRightLowerLeg].x_max);
  const std::vector<std::string> reached = jointLimitsReached(clamped, walkingJointLimits());
  ASSERT_EQ(reached.size(), 1u);
  EXPECT_EQ(reached[0], "right_lower_leg theta_x at its max 80 deg");
  EXPECT_EQ(jointLimitsReached(clampToJointLimits(model), thesisJointLimits()),
            std::vector<std::string>{"right_lower_leg theta_x at its max 30 deg"});
}

TEST(KinematicModel, JointLimitsOfTable52AreEnforced) {
  const JointLimits arm = jointLimits(kRightUpperArm);
  EXPECT_DOUBLE_EQ(arm.x_max, kPi / 6);
  EXPECT_DOUBLE_EQ(arm.z_min, -kPi / 18);
  EXPECT_DOUBLE_EQ(jointLimits(kLeftUpperLeg).x_max, kPi / 4);
  EXPECT_DOUBLE_EQ(jointLimits(kLeftLowerLeg).x_max, kPi / 6);
  EXPECT_DOUBLE_EQ(jointLimits(kHead).z_max, kPi / 2);
  EXPECT_DOUBLE_EQ(jointLimits(kNeck).x_max, 0.0);

  BodyModel model = standingModel(1.8);
  EXPECT_TRUE(withinJointLimits(model));
  model.setJointAngles(kRightUpperArm, 0.9, -0.5);  // beyond pi/6 and -pi/18
  model.setJointAngles(kLeftLowerLeg, -1.0, 0.05);
  EXPECT_FALSE(withinJointLimits(model));
  const BodyModel clamped = clampToJointLimits(model);
  EXPECT_TRUE(withinJointLimits(clamped));
  EXPECT_DOUBLE_EQ(clamped.thetaX(kRightUpperArm), kPi / 6);
  EXPECT_DOUBLE_EQ(clamped.thetaZ(kRightUpperArm), -kPi / 18);
  EXPECT_DOUBLE_EQ(clamped.thetaX(kLeftLowerLeg), -kPi / 6);
  EXPECT_DOUBLE_EQ(clamped.thetaZ(kLeftLowerLeg), 0.05);  // inside: untouched
  EXPECT_THROW(model.setJointAngles(kNeck, 0.1, 0), std::invalid_argument);
  EXPECT_EQ(thesisJointLimits()[kLeftLowerLeg].x_max, jointLimits(kLeftLowerLeg).x_max);
  EXPECT_THROW(segmentInfo(12), std::out_of_range);
  EXPECT_THROW(forwardKinematics(model).joint("left_ear"), std::invalid_argument);
}

TEST(KinematicModel, TaperedCylinderDistanceMatchesAnalyticCases) {
  const Eigen::Vector3d a(1, 2, 3), b(1, 2, 4);  // axis along +z, length 1
  const double r0 = 0.2, r1 = 0.1;
  // On the axis at mid-length: inside by the mid radius (0.15), measured perpendicular to the
  // slanted profile: 0.15 * cos(atan(0.1)).
  const double slant = std::atan(0.1);
  EXPECT_NEAR(taperedCylinderDistance({1, 2, 3.5}, a, b, r0, r1), -0.15 * std::cos(slant), 1e-12);
  // Radially outside at mid-length by 0.35 from the axis: (0.35 - 0.15) cos(slant).
  EXPECT_NEAR(taperedCylinderDistance({1.35, 2, 3.5}, a, b, r0, r1), 0.20 * std::cos(slant), 1e-12);
  // Beyond the distal end on the axis: to the rim (axial 0.3, radial 0.1).
  EXPECT_NEAR(taperedCylinderDistance({1, 2, 4.3}, a, b, r0, r1), std::hypot(0.3, 0.1), 1e-12);
  // Straight cylinder (r0 = r1): plain radial distance, sign by side.
  EXPECT_NEAR(taperedCylinderDistance({1, 2.5, 3.2}, a, b, 0.2, 0.2), 0.3, 1e-12);
  EXPECT_NEAR(taperedCylinderDistance({1, 2.05, 3.2}, a, b, 0.2, 0.2), -0.15, 1e-12);
  // A point on the surface is at distance 0.
  EXPECT_NEAR(taperedCylinderDistance({1 + 0.15, 2, 3.5}, a, b, r0, r1), 0.0, 1e-12);
}

}  // namespace
}  // namespace body_gait_model
