// modelFromSkeleton: the body model read off the simulator's true skeleton puts its joints on the
// true joints (checked directly and through compareWithTruth, the fit evaluation's yardstick).
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <body_gait_model/eval/skeleton_model.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace body_gait_model::eval {
namespace {

namespace sim = body_scan_driver::sim;
constexpr double kDegree = 3.14159265358979323846 / 180;

SampledBody unsampled(const sim::HumanBodySpec& spec) {
  SampledBody body;  // the skeleton is all compareWithTruth needs
  body.spec = spec;
  body.skeleton = sim::humanSkeleton(spec);
  return body;
}

void expectJointsOnTheSkeleton(const sim::HumanBodySpec& spec, const std::string& what) {
  const SampledBody body = unsampled(spec);
  const BodyModel model = modelFromSkeleton(body);
  const PosedModel posed = forwardKinematics(model);
  const FitErrors errors = compareWithTruth(model, body);
  // Hands, elbows, shoulders, hips, knees, soles and the head top.
  for (const auto& [joint, error] : errors.joint_error) EXPECT_LT(error, 1e-9) << what << joint;
  for (const auto& [segment, error] : errors.segment_length_error)
    EXPECT_LT(error, 1e-9) << what << segment;
  for (const auto& [segment, error] : errors.swing_error) EXPECT_LT(error, 1e-9) << what << segment;
  EXPECT_TRUE(errors.front_right) << what;
  EXPECT_TRUE(errors.left_right) << what;
  EXPECT_LT((posed.joint("waist") - trueJoint(body, "pelvis")).norm(), 1e-9) << what;
  EXPECT_LT((posed.joint("neck_base") - trueJoint(body, "neck")).norm(), 1e-9) << what;
}

TEST(SkeletonModel, ForwardKinematicsPutsTheJointsOnTheTrueSkeleton) {
  const auto subjects = simulatedSubjects(4);
  for (const auto& subject : subjects) {
    for (int index = 1; index <= 4; ++index) {
      sim::HumanBodySpec spec = subject;
      spec.pose = gaitPose(index, 0.4 * index - 1.0);
      expectJointsOnTheSkeleton(spec, subject.name + " pose " + std::to_string(index) + ": ");
      EXPECT_TRUE(withinJointLimits(modelFromSkeleton(spec)))
          << subject.name << " pose " << index << ": gaitPose keeps to Table 5.2";
    }
  }
}

TEST(SkeletonModel, LeaningAndAbductedPosesToo) {
  sim::HumanBodySpec spec = simulatedSubjects(1)[0];
  spec.pose = gaitPose(3, 2.5);
  spec.pose.torso_lean = 8 * kDegree;
  spec.pose.left_shoulder_abduction = 9 * kDegree;
  spec.pose.right_hip_abduction = -4 * kDegree;
  spec.pose.left_elbow_flexion = 40 * kDegree;
  spec.position = Eigen::Vector3d(0.3, -0.2, 0);
  expectJointsOnTheSkeleton(spec, "leaning: ");
  const BodyModel model = modelFromSkeleton(spec);
  // The lean is the upper torso's theta_x: Rx turns its +Y axis toward the front (+Z_m).
  EXPECT_NEAR(model.thetaX(kUpperTorso), 8 * kDegree, 1e-9);
  EXPECT_NEAR(model.thetaZ(kUpperTorso), 0, 1e-9);
}

TEST(SkeletonModel, LengthsAreTheSimulatorsSegments) {
  const sim::Anthropometry body = sim::Anthropometry::fromStature(1.80);
  sim::HumanBodySpec spec;
  spec.body = body;
  spec.pose = gaitPose(1);
  const BodyModel model = modelFromSkeleton(spec);
  EXPECT_NEAR(model.r[kUpperTorso], body.torso_length, 1e-9);
  EXPECT_NEAR(model.r[kNeck] + model.r[kHead], body.neck_length + body.head_height, 1e-9);
  EXPECT_NEAR(model.r[kRightUpperArm], body.upper_arm_length, 1e-9);
  EXPECT_NEAR(model.r[kLeftLowerArm], body.forearm_length + body.hand_length, 1e-9);
  EXPECT_NEAR(model.r[kLeftUpperLeg], body.thigh_length, 1e-9);
  EXPECT_NEAR(model.r[kRightLowerLeg], body.shank_length + body.ankle_height, 1e-9);
  EXPECT_NEAR(model.shape.shoulder_half_width, body.shoulder_width / 2, 1e-9);
  EXPECT_NEAR(model.shape.hip_half_width, body.hip_width / 2, 1e-9);
  EXPECT_NEAR(model.shape.proximal_radius[kLeftUpperLeg], body.thigh_girth / (2 * M_PI), 1e-12);
}

TEST(SkeletonModel, AMissingJointIsNamed) {
  auto skeleton = sim::humanSkeleton(sim::HumanBodySpec{});
  skeleton.erase(skeleton.begin());  // head_top
  try {
    modelFromSkeleton(skeleton, sim::Anthropometry::fromStature(1.75));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("head_top"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace body_gait_model::eval
