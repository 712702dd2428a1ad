// The body fit's robustness cases on the product's clouds: the simulated full scanner with one pair
// missing, the arms touching the torso, and hair and trunks so dark (albedo 0.03) that little of
// them decodes. Each stays within 2x the targets (50 mm) with every unflagged fit facing right;
// a fit that goes wrong must come back flagged low quality. Subjects 5 and 9 of 10: the one
// whose dark fit once faced backwards (stray points above the dark hair taken for the
// shoulders' top) and the tallest.
#include <body_gait_model/body_fitter.h>
#include <body_gait_model/eval/full_scanner_body.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <string>

namespace body_gait_model {
namespace {

constexpr double kTwiceTheTarget = 0.050;  // m

void expectWithinTwiceTheTargets(
    const std::string& name, const eval::FullScannerOptions& options,
    const std::function<void(body_scan_driver::sim::HumanBodySpec&)>& adjust) {
  const auto subjects = eval::simulatedSubjects(10);
  double joint = 0;
  int unflagged = 0, right = 0, flagged = 0, cases = 0;
  for (int s : {5, 9}) {
    for (int pose = 1; pose <= 4; ++pose, ++cases) {
      auto spec = subjects[s];
      spec.pose = eval::gaitPose(pose, eval::fullScannerHeading(4 * s + pose - 1));
      adjust(spec);
      const eval::SampledBody body = eval::scanBodyWithFullScanner(spec, options);
      const BodyFit fit = fitBody(body.points);
      const eval::FitErrors errors = eval::compareWithTruth(fit.model, body);
      if (fit.quality.low_quality) {
        ++flagged;
        continue;
      }
      ++unflagged;
      joint += errors.mean_joint_error;
      right += errors.front_right && errors.left_right;
      EXPECT_LE(errors.mean_joint_error, 2 * kTwiceTheTarget)
          << name << ": " << spec.name << " pose " << pose << " unflagged but beyond 100 mm";
    }
  }
  joint /= std::max(unflagged, 1);
  std::printf(
      "[ figure ] full scanner, %s: %d fits, %d flagged; unflagged: mean joint-centre error "
      "%.1f mm, front/left right %d/%d\n",
      name.c_str(), cases, flagged, 1000 * joint, right, unflagged);
  EXPECT_GE(unflagged, cases - 1) << name << ": more than one fit flagged";
  EXPECT_EQ(right, unflagged);
  EXPECT_LE(joint, kTwiceTheTarget);
}

TEST(FullScannerRobustness, OnePairMissing) {
  eval::FullScannerOptions options;
  options.missing_pairs = {"pole_b/pair_2"};
  expectWithinTwiceTheTargets("one pair missing", options, [](auto&) {});
}

TEST(FullScannerRobustness, ArmsTouchingTheTorso) {
  expectWithinTwiceTheTargets("arms touching the torso", {}, [](auto& spec) {
    spec.pose.left_shoulder_abduction = spec.pose.right_shoulder_abduction = 0;
  });
}

TEST(FullScannerRobustness, DarkHairAndTrunks) {
  expectWithinTwiceTheTargets("hair and trunks at albedo 0.03", {}, [](auto& spec) {
    spec.materials.hair.albedo = spec.materials.clothing.albedo = 0.03;
  });
}

}  // namespace
}  // namespace body_gait_model
