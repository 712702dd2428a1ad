// Robustness of the fit: one projector-camera pair missing and arms touching the
// torso stay within 2x the joint-centre target (2 x 25 mm) with front/left right; dark hair
// and trunks either fit within 2x or come back flagged low quality.
#include <body_gait_model/body_fitter.h>
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwiceTheTarget = 0.050;  // m

struct CaseResult {
  double mean_joint_error = 0;
  int right = 0, flagged = 0, cases = 0, unflagged_beyond_twice = 0;
};

CaseResult run(const std::string& name, const eval::ScanRig& rig,
               const std::function<void(body_scan_driver::sim::BodyPose&)>& adjust = {}) {
  CaseResult result;
  const auto subjects = eval::simulatedSubjects(4);
  for (int s : {1, 2}) {
    for (int pose = 1; pose <= 4; ++pose) {
      auto spec = subjects[s];
      spec.pose = eval::gaitPose(pose, 0.9 * pose - 2.0);
      if (adjust) adjust(spec.pose);
      const auto body = eval::sampleBody(spec, rig);
      const BodyFit fit = fitBody(body.points);
      const eval::FitErrors errors = eval::compareWithTruth(fit.model, body);
      result.mean_joint_error += errors.mean_joint_error;
      result.right += errors.front_right && errors.left_right;
      result.flagged += fit.quality.low_quality;
      result.unflagged_beyond_twice +=
          !fit.quality.low_quality && errors.mean_joint_error > kTwiceTheTarget;
      ++result.cases;
    }
  }
  result.mean_joint_error /= result.cases;
  std::printf(
      "[ figure ] %s: mean joint-centre error %.1f mm, front/left right %d/%d, flagged "
      "%d, unflagged beyond 50 mm %d\n",
      name.c_str(), 1000 * result.mean_joint_error, result.right, result.cases, result.flagged,
      result.unflagged_beyond_twice);
  return result;
}

eval::ScanRig testRig() {
  eval::ScanRig rig;
  rig.columns = 180;
  rig.rows = 146;
  rig.noise_sigma = 0.002;
  return rig;
}

TEST(BodyFitterRobustness, OnePairMissing) {
  eval::ScanRig rig = testRig();
  rig.missing_viewpoints = {5};  // pole 2, second height
  const CaseResult result = run("one pair missing", rig);
  EXPECT_EQ(result.right, result.cases);
  EXPECT_LE(result.mean_joint_error, kTwiceTheTarget);
}

TEST(BodyFitterRobustness, ArmsTouchingTheTorso) {
  const CaseResult result = run("arms touching the torso", testRig(), [](auto& pose) {
    pose.left_shoulder_abduction = pose.right_shoulder_abduction = 0;
  });
  EXPECT_EQ(result.right, result.cases);
  EXPECT_LE(result.mean_joint_error, kTwiceTheTarget);
}

TEST(BodyFitterRobustness, DarkHairAndTrunksAreFittedOrFlagged) {
  eval::ScanRig rig = testRig();
  rig.min_albedo = 0.3;  // hair and trunks (albedo 0.15) return no light
  const CaseResult result = run("dark hair and trunks", rig);
  EXPECT_EQ(result.right, result.cases);
  EXPECT_EQ(result.unflagged_beyond_twice, 0);
}

TEST(BodyFitterRobustness, DarkHairKeepsTheStatureAndTheHipsHeight) {
  // Dark hair leaves the head's upper half open and its visible top 40-53 mm below the vertex;
  // the vertex then comes from the chin by proportion, and the hips' height (0.53 of the
  // stature) with it. Mean |vertical error| of the head top and the hips, and the head top's
  // error, over 3 subjects x 4 poses (only the hair dark).
  eval::ScanRig rig = testRig();
  rig.min_albedo = 0.3;
  double head_vertical = 0, hip_vertical = 0, head = 0;
  int cases = 0;
  for (const auto& subject : eval::simulatedSubjects(3)) {
    for (int pose = 1; pose <= 4; ++pose) {
      auto spec = subject;
      spec.pose = eval::gaitPose(pose, 0.4 + 1.1 * pose);
      spec.materials.clothing = spec.materials.skin;  // the hair alone is dark
      const auto body = eval::sampleBody(spec, rig);
      const BodyFit fit = fitBody(body.points);
      const eval::FitErrors errors = eval::compareWithTruth(fit.model, body);
      head_vertical += std::abs(errors.joint_offset.at("head_top").z());
      head += errors.joint_error.at("head_top");
      hip_vertical += (std::abs(errors.joint_offset.at("left_hip").z()) +
                       std::abs(errors.joint_offset.at("right_hip").z())) /
                      2;
      ++cases;
    }
  }
  head_vertical /= cases;
  hip_vertical /= cases;
  head /= cases;
  std::printf(
      "[ figure ] dark hair: head top %.1f mm off (vertically %.1f mm), hips vertically %.1f "
      "mm\n",
      1000 * head, 1000 * head_vertical, 1000 * hip_vertical);
  EXPECT_LE(head_vertical, 0.025);  // 51.4 mm from the visible top
  EXPECT_LE(hip_vertical, 0.015);   // 16.4 mm from the visible top
}

TEST(BodyFitterRobustness, DarkHairAndTrunksInAWalkKeepTheHipsAndTheHead) {
  // A walk's four scans with hair and trunks returning no light: the refinement has no pelvis
  // to hold the hips (the thighs keep the direct fit's lengths) and only the face to turn the
  // head to (it is aimed at the vertex placed from the chin). Mean hip and head-top errors over
  // 2 subjects' walks.
  eval::ScanRig rig = testRig();
  rig.min_albedo = 0.3;
  double hips = 0, head = 0;
  int cases = 0;
  const auto subjects = eval::simulatedSubjects(4);
  for (int s : {1, 2}) {
    std::vector<Cloud> walk;
    std::vector<eval::SampledBody> bodies;
    for (int pose = 1; pose <= 4; ++pose) {
      auto spec = subjects[s];
      spec.pose = eval::gaitPose(pose, 0.9 * pose - 2.0);
      bodies.push_back(eval::sampleBody(spec, rig));
      walk.push_back(bodies.back().points);
    }
    const WalkFit fits = fitWalk(walk);
    for (size_t k = 0; k < fits.scans.size(); ++k, ++cases) {
      const eval::FitErrors errors = eval::compareWithTruth(fits.scans[k].model, bodies[k]);
      hips += (errors.joint_error.at("left_hip") + errors.joint_error.at("right_hip")) / 2;
      head += errors.joint_error.at("head_top");
    }
  }
  hips /= cases;
  head /= cases;
  std::printf("[ figure ] dark hair and trunks, walk fits: hips %.1f mm, head top %.1f mm off\n",
              1000 * hips, 1000 * head);
  EXPECT_LE(hips, 0.020);  // 14.8 mm; 25.0 mm with the thighs refined
  EXPECT_LE(head, 0.025);  // 14.9 mm; 46.6 mm with the head turned to the face
}

}  // namespace
}  // namespace body_gait_model
