// Whole-model fit (5.5) against the simulator's skeleton: subjects x the four gait poses of 5.3
// at arbitrary headings, joint-centre / segment-length / swing-angle errors, front and left
// right in every case; a non-human cloud is flagged or refused, never a crash.
#include <body_gait_model/body_fitter.h>
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(BodyFitter, FitsSubjectsInTheFourGaitPoses) {
  const auto subjects = eval::simulatedSubjects(3);
  eval::ScanRig rig;
  rig.columns = 200;
  rig.rows = 162;
  rig.noise_sigma = 0.002;
  double joint = 0, length = 0, swing = 0, fit_seconds = 0;
  int cases = 0, right = 0;
  for (const auto& subject : subjects) {
    for (int pose = 1; pose <= 4; ++pose) {
      auto spec = subject;
      spec.pose = eval::gaitPose(pose, 0.3 + 1.7 * pose);
      const auto body = eval::sampleBody(spec, rig);
      const auto start = std::chrono::steady_clock::now();
      const BodyFit fit = fitBody(body.points);
      fit_seconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      EXPECT_TRUE(withinJointLimits(fit.model, FitOptions{}.joint_limits));
      const eval::FitErrors errors = eval::compareWithTruth(fit.model, body);
      EXPECT_TRUE(errors.front_right && errors.left_right) << spec.name << " pose " << pose;
      right += errors.front_right && errors.left_right;
      joint += errors.mean_joint_error;
      length += errors.mean_length_error;
      swing += errors.mean_swing_error;
      ++cases;
    }
  }
  joint /= cases;
  length /= cases;
  swing /= cases;
  std::printf(
      "[ figure ] %d fits (3 subjects x 4 gait poses, ~70k points, 2 mm noise): mean "
      "joint-centre error %.1f mm, segment-length error %.1f %%, swing-angle error %.2f "
      "deg, front/left right %d/%d, %.0f ms per fit\n",
      cases, 1000 * joint, 100 * length, swing * 180 / kPi, right, cases,
      1000 * fit_seconds / cases);
  EXPECT_EQ(right, cases);
  // The body fit's targets: swing 4 deg, joints 25 mm, lengths 5 %.
  EXPECT_LE(swing, 4 * kPi / 180);
  EXPECT_LE(joint, 0.025);
  EXPECT_LE(length, 0.05);
}

// fitWalk: the 4 poses of one subject fitted together share one body (lengths, radii, joint
// offsets), each with its own pose; the lengths are no worse than fitting each scan alone.
TEST(BodyFitter, WalkFitSharesOneBodyAcrossTheScans) {
  const auto subject = eval::simulatedSubjects(2)[1];
  eval::ScanRig rig;
  rig.columns = 200;
  rig.rows = 162;
  rig.noise_sigma = 0.002;
  std::vector<eval::SampledBody> bodies;
  std::vector<Cloud> walk;
  for (int pose = 1; pose <= 4; ++pose) {
    auto spec = subject;
    spec.pose = eval::gaitPose(pose, 0.3 + 1.7 * pose);
    bodies.push_back(eval::sampleBody(spec, rig));
    walk.push_back(bodies.back().points);
  }
  const WalkFit fits = fitWalk(walk);
  ASSERT_EQ(fits.scans.size(), 4u);
  double walk_joint = 0, walk_length = 0, scan_joint = 0, scan_length = 0;
  for (int k = 0; k < 4; ++k) {
    const BodyModel& model = fits.scans[k].model;
    for (int s = 0; s < kSegmentCount; ++s) {
      EXPECT_DOUBLE_EQ(model.r[s], fits.scans[0].model.r[s]) << segmentInfo(s).name;
      EXPECT_DOUBLE_EQ(model.shape.proximal_radius[s],
                       fits.scans[0].model.shape.proximal_radius[s]);
    }
    EXPECT_DOUBLE_EQ(model.shape.hip_half_width, fits.scans[0].model.shape.hip_half_width);
    EXPECT_FALSE(fits.scans[k].quality.low_quality) << fits.scans[k].quality.reason;
    const eval::FitErrors errors = eval::compareWithTruth(model, bodies[k]);
    EXPECT_TRUE(errors.front_right && errors.left_right) << "pose " << k + 1;
    walk_joint += errors.mean_joint_error / 4;
    walk_length += errors.mean_length_error / 4;
    const eval::FitErrors alone = eval::compareWithTruth(fitBody(walk[k]).model, bodies[k]);
    scan_joint += alone.mean_joint_error / 4;
    scan_length += alone.mean_length_error / 4;
  }
  std::printf(
      "[ figure ] walk fit of 4 poses: joint %.1f mm, length %.1f %% (each scan alone: %.1f mm, "
      "%.1f %%); sampled RMS %.1f -> %.1f mm\n",
      1000 * walk_joint, 100 * walk_length, 1000 * scan_joint, 100 * scan_length,
      1000 * fits.refinement.initial_rms, 1000 * fits.refinement.final_rms);
  EXPECT_LT(fits.refinement.final_rms, fits.refinement.initial_rms);
  EXPECT_LE(walk_length, scan_length + 0.005);
  EXPECT_LE(walk_joint, 0.025);
  std::vector<BodyModel> two(2, fits.scans[0].model);
  EXPECT_THROW(refineWalk(two, {&walk[0]}), std::invalid_argument);
}

TEST(BodyFitter, RefinementLowersTheSurfaceDistanceWithinJointLimits) {
  auto spec = eval::simulatedSubjects(3)[1];
  spec.pose = eval::gaitPose(3, -0.7);
  eval::ScanRig rig;
  rig.columns = 200;
  rig.rows = 162;
  const auto body = eval::sampleBody(spec, rig);
  FitOptions direct_only;
  direct_only.refine = false;
  const BodyFit direct = fitBody(body.points, direct_only);
  BodyModel model = direct.model;
  const RefinementReport report = refineModel(model, body.points);
  const double before = eval::compareWithTruth(direct.model, body).mean_joint_error;
  const double after = eval::compareWithTruth(model, body).mean_joint_error;
  std::printf(
      "[ figure ] refinement: sampled RMS %.1f -> %.1f mm in %d iterations; joint error "
      "%.1f -> %.1f mm\n",
      1000 * report.initial_rms, 1000 * report.final_rms, report.iterations, 1000 * before,
      1000 * after);
  EXPECT_LT(report.final_rms, report.initial_rms);
  EXPECT_TRUE(withinJointLimits(model));
  for (int s : {kHead, kRightLowerArm, kLeftLowerLeg})  // free ends keep their lengths
    EXPECT_DOUBLE_EQ(model.r[s], direct.model.r[s]);
}

TEST(BodyFitter, ACylinderIsFlaggedLowQuality) {
  // The calibration cylinder: 0.15 m radius, 1.8 m tall, sampled on its side.
  Cloud cylinder;
  for (int i = 0; i < 60000; ++i) {
    const double angle = 2 * kPi * (i % 300) / 300.0, height = 1.8 * (i / 300) / 200.0;
    cylinder.emplace_back(0.15 * std::cos(angle), 0.15 * std::sin(angle), height);
  }
  const BodyFit fit = fitBody(cylinder);
  EXPECT_TRUE(fit.quality.low_quality) << "a cylinder passed as a body";
  EXPECT_NE(fit.quality.reason.find("not a human body"), std::string::npos) << fit.quality.reason;
  std::printf("[ figure ] cylinder: low quality, RMS %.0f mm, %.0f %% explained (%s)\n",
              1000 * fit.quality.rms_distance, 100 * fit.quality.explained_fraction,
              fit.quality.reason.c_str());
}

// The body of the good-fit checks: subject 1 of 2 in gait pose 2, a 200 x 162 ray grid.
eval::SampledBody goodFitBody() {
  auto spec = eval::simulatedSubjects(2)[1];
  spec.pose = eval::gaitPose(2, 1.0);
  eval::ScanRig rig;
  rig.columns = 200;
  rig.rows = 162;
  return eval::sampleBody(spec, rig);
}

TEST(BodyFitter, GoodFitsAreNotFlagged) {
  const BodyFit fit = fitBody(goodFitBody().points);
  std::printf("[ figure ] good fit: RMS %.1f mm, %.0f %% explained, low quality %d %s\n",
              1000 * fit.quality.rms_distance, 100 * fit.quality.explained_fraction,
              fit.quality.low_quality, fit.quality.reason.c_str());
  EXPECT_FALSE(fit.quality.low_quality) << fit.quality.reason;
  for (int s = 0; s < kSegmentCount; ++s)
    EXPECT_GT(fit.quality.points_per_segment[s], 100) << segmentInfo(s).name;
}

TEST(BodyFitter, ImplausibleLimbProportionsAreFlagged) {
  // The good fit above with its right knee moved 15 % of the leg's length down the leg (as
  // when the hip lies far off the leg's line) or its left elbow run to the hand.
  const auto body = goodFitBody();
  const BodyFit fit = fitBody(body.points);
  ASSERT_FALSE(fit.quality.low_quality) << fit.quality.reason;
  BodyModel knee_low = fit.model;
  const double leg = knee_low.r[kRightUpperLeg] + knee_low.r[kRightLowerLeg];
  knee_low.r[kRightUpperLeg] += 0.15 * leg;
  knee_low.r[kRightLowerLeg] -= 0.15 * leg;
  const FitQuality knee_quality = evaluateFit(knee_low, body.points);
  EXPECT_TRUE(knee_quality.low_quality);
  EXPECT_NE(knee_quality.reason.find("right_upper_leg is"), std::string::npos)
      << knee_quality.reason;
  BodyModel elbow_at_hand = fit.model;
  elbow_at_hand.r[kLeftUpperArm] += 0.8 * elbow_at_hand.r[kLeftLowerArm];
  elbow_at_hand.r[kLeftLowerArm] *= 0.2;
  const FitQuality elbow_quality = evaluateFit(elbow_at_hand, body.points);
  EXPECT_TRUE(elbow_quality.low_quality);
  EXPECT_NE(elbow_quality.reason.find("left_upper_arm is"), std::string::npos)
      << elbow_quality.reason;
}

struct MeshSamplerFit {
  BodyFit fit;
  eval::FitErrors errors;
};

// Simulated subject k of 10 in gait pose `pose` as the mesh human, sampled as evaluate_body_fit's
// sampler does (its heading, 300 columns, 2 mm noise).
eval::SampledBody sampleMeshCase(int k, int pose) {
  eval::ScanRig rig;
  rig.columns = 300;
  rig.rows = 243;
  rig.noise_sigma = 0.002;
  rig.body = eval::BodyKind::kMesh;
  auto spec = eval::simulatedSubjects(10)[k];
  spec.pose = eval::gaitPose(pose, 0.3 + 1.7 * (pose + 4 * k + pose - 1));
  return eval::sampleBody(spec, rig);
}

// That case fitted alone and compared with the truth.
MeshSamplerFit fitMeshSamplerCase(int k, int pose) {
  const auto body = sampleMeshCase(k, pose);
  MeshSamplerFit result{fitBody(body.points), {}};
  result.errors = eval::compareWithTruth(result.fit.model, body);
  return result;
}

// A measure of the fit's errors, averaged over the 4 gait poses of each of these people.
double meanOverMeshPoses(std::initializer_list<int> people,
                         const std::function<double(const eval::FitErrors&)>& measure) {
  double sum = 0;
  int cases = 0;
  for (int k : people)
    for (int pose = 1; pose <= 4; ++pose, ++cases)
      sum += measure(fitMeshSamplerCase(k, pose).errors);
  return sum / cases;
}

TEST(BodyFitter, MeshHumanShouldersHangTwoArmRadiiBelowTheShouldersTop) {
  // The mesh human's trapezius slopes up from the acromion to the neck; the shoulder joints hang
  // from the top of the shoulder no higher than the slice as wide as shoulders, two arm radii
  // down (FitOptions::shoulder_depth). Mean |vertical shoulder error| over two people's 4 poses
  // at evaluate_body_fit's headings (the sampler).
  const double vertical = meanOverMeshPoses({5, 7}, [](const eval::FitErrors& errors) {
    return (std::abs(errors.joint_offset.at("left_shoulder").z()) +
            std::abs(errors.joint_offset.at("right_shoulder").z())) /
           2;
  });
  std::printf("[ figure ] mesh human: shoulders %.1f mm off vertically\n", 1000 * vertical);
  // 10.2 mm; 21.2 mm one radius down; 73.9 mm with the trapezius taken for the shoulder top.
  EXPECT_LE(vertical, 0.016);
}

TEST(BodyFitter, MeshHumanHipsSitBehindTheLowerTorsosAxis) {
  // Belly and buttocks centre the lower torso's axis 35-40 mm in front of the mesh human's hip
  // joints; the hips are placed 40 % of the body's depth in front of the buttocks
  // (FitOptions::hip_depth_fraction). Mean forward hip error over two people's 4 poses at
  // evaluate_body_fit's headings (the sampler).
  const double forward = meanOverMeshPoses({1, 4}, [](const eval::FitErrors& errors) {
    return (errors.joint_offset.at("left_hip").x() + errors.joint_offset.at("right_hip").x()) / 2;
  });
  std::printf("[ figure ] mesh human: hips %.1f mm in front of the true ones\n", 1000 * forward);
  // 19.8 mm (the refinement moves the lower torso forward); on its axis the direct fit's hips
  // stood 26 mm and the refined ones 35-40 mm in front (evaluate_body_fit, full scanner).
  EXPECT_LE(std::abs(forward), 0.03);
}

TEST(BodyFitter, MeshHumanWomanTallManAndLongStrideAreFitted) {
  // Cases the mesh human failed (the sampler at evaluate_body_fit's headings): a woman's waist
  // at g narrower than her chest (the torso's top found in the head), a long stride whose
  // sections below the crotch tilted the lower torso by 49 deg (one leg took every leg point),
  // an arm swung across the body whose line met the buttocks (the arm not fitted). Measured:
  // 35-47 mm, none flagged; 93-283 mm, 4 of 5 flagged before.
  for (const auto& [k, pose] : {std::pair{0, 1}, {0, 2}, {8, 3}, {9, 1}, {9, 3}}) {
    const auto [fit, errors] = fitMeshSamplerCase(k, pose);
    std::printf("[ figure ] mesh human subject %d pose %d: %.1f mm%s\n", k, pose,
                1000 * errors.mean_joint_error, fit.quality.low_quality ? ", flagged" : "");
    EXPECT_FALSE(fit.quality.low_quality)
        << "subject " << k << " pose " << pose << ": " << fit.quality.reason;
    EXPECT_LT(errors.mean_joint_error, 0.06) << "subject " << k << " pose " << pose;
  }
}

TEST(BodyFitter, MeshHumanSolesFollowTheShankAboveTheAnkle) {
  // The mesh human's calf bulges behind the tibia, so the shank's surface axis misses the ankle;
  // each lower leg is aimed at its section's centre just above the ankle. Mean sole error over two
  // people's 4 poses at evaluate_body_fit's headings (the sampler).
  const double sole = meanOverMeshPoses({2, 6}, [](const eval::FitErrors& errors) {
    return (errors.joint_error.at("left_sole") + errors.joint_error.at("right_sole")) / 2;
  });
  std::printf("[ figure ] mesh human: soles %.1f mm off\n", 1000 * sole);
  EXPECT_LE(sole, 0.035);  // 19.5 mm; 62.3 mm along the shank's surface axis
}

TEST(BodyFitter, MeshHumanElbowsOnSlightlyBentArmsFollowTheProportion) {
  // Two lines meet at a slightly bent elbow far along the arm when one lies off its bone (a
  // muscle's bulge): the meeting point moves by the offset / sin(bend). Mean elbow error over two
  // people's 4 poses at evaluate_body_fit's headings (the sampler).
  const double elbow = meanOverMeshPoses({4, 6}, [](const eval::FitErrors& errors) {
    return (errors.joint_error.at("left_elbow") + errors.joint_error.at("right_elbow")) / 2;
  });
  std::printf("[ figure ] mesh human: elbows %.1f mm off\n", 1000 * elbow);
  EXPECT_LE(elbow, 0.028);  // 25.1 mm; 31.7 mm with the meeting point trusted alone from 14 deg
}

TEST(BodyFitter, MeshHumanWalkKeepsStraightKneesWhereTheDirectFitPutThem) {
  // A straight knee fits the cylinders' surface anywhere along the leg: a walk's refinement moved
  // the thighs' lengths by the legs' radius profiles and raised the mesh people's knees (their 4
  // poses bend the knees < 20 deg). Thighs are refined only for a leg whose knee bends clearly in
  // some scan. Mean |vertical knee error| over two people's walks (the sampler, fitWalk).
  double vertical = 0;
  for (int k : {1, 3}) {
    std::vector<eval::SampledBody> bodies;
    std::vector<Cloud> walk;
    for (int pose = 1; pose <= 4; ++pose) {
      bodies.push_back(sampleMeshCase(k, pose));
      walk.push_back(bodies.back().points);
    }
    const WalkFit fits = fitWalk(walk);
    for (int pose = 0; pose < 4; ++pose) {
      const eval::FitErrors errors = eval::compareWithTruth(fits.scans[pose].model, bodies[pose]);
      vertical += (std::abs(errors.joint_offset.at("left_knee").z()) +
                   std::abs(errors.joint_offset.at("right_knee").z())) /
                  16;
    }
  }
  std::printf("[ figure ] mesh human walks: knees %.1f mm off vertically\n", 1000 * vertical);
  EXPECT_LE(vertical, 0.018);  // 12.9 mm; 26.4 mm with every walk's thighs refined
}

TEST(BodyFitter, MeshHumanWalkKeepsTheWholeBodysTiltOfTheDirectFit) {
  // Every segment hangs from the two torsos, whose joints turn about the whole body's X and Z
  // axes: a tilted whole body with counter-tilted torsos has the same surface. A walk's
  // refinement left free drifted along that valley (the torsos' theta_z up to 1.5 rad, truth 0).
  // Largest |theta_z| of the upper torso over two people's walks (the sampler, fitWalk).
  double largest = 0;
  for (int k : {0, 4}) {
    std::vector<Cloud> walk;
    for (int pose = 1; pose <= 4; ++pose) walk.push_back(sampleMeshCase(k, pose).points);
    const WalkFit fits = fitWalk(walk);
    for (const BodyFit& fit : fits.scans)
      largest = std::max(largest, std::abs(fit.model.thetaZ(kUpperTorso)));
  }
  std::printf("[ figure ] mesh human walks: upper torso theta_z up to %.3f rad\n", largest);
  EXPECT_LE(largest, 0.1);
}

TEST(BodyFitter, MeshHumanWalkThighsSidewaysAngleIsTheLegsNotThePelvisTilt) {
  // Both thighs hang from the lower torso, a short wide cylinder whose sideways tilt its surface
  // barely fixes: any error of that tilt turned both thighs' theta_z the other way. The walking
  // joint limits hold the lower torso level across. RMS theta_z of both thighs over two people's
  // walks (the sampler, fitWalk); the simulated people walk with their thighs within a few
  // degrees of their pelvis's vertical.
  double sum = 0;
  int count = 0;
  for (int k : {0, 4}) {
    std::vector<Cloud> walk;
    for (int pose = 1; pose <= 4; ++pose) walk.push_back(sampleMeshCase(k, pose).points);
    for (const BodyFit& fit : fitWalk(walk).scans) {
      for (int thigh : {kRightUpperLeg, kLeftUpperLeg}) sum += std::pow(fit.model.thetaZ(thigh), 2);
      count += 2;
      EXPECT_EQ(fit.model.thetaZ(kLowerTorso), 0.0);
    }
  }
  const double rms = std::sqrt(sum / count);
  std::printf("[ figure ] mesh human walks: thighs' theta_z RMS %.3f rad\n", rms);
  EXPECT_LE(rms, 0.06);
}

TEST(BodyFitter, MeshPeoplesNeckAndHeadKeepTheirLengthsAcrossTheirWalks) {
  // A head held forward of the trunk's axis leaves its sections about that axis open though the
  // head is seen whole: taken for unseen hair, the chin came from those open sections (mesh
  // people: 10-90 mm off the chin of the person's other scans). The neck's and head's lengths
  // over 2 walks x 4 poses of each person (single-scan fits), SD averaged over 4 people.
  eval::ScanRig rig;
  rig.columns = 200;
  rig.rows = 162;
  rig.body = eval::BodyKind::kMesh;
  const auto people = eval::simulatedPeople(4, 3);
  double mean_sd[2] = {0, 0};
  for (const auto& person : people) {
    std::vector<double> lengths[2];
    for (int trial = 0; trial < 2; ++trial)
      for (int pose = 1; pose <= 4; ++pose) {
        const auto body = eval::sampleBody(eval::walkingSubject(person, pose, trial), rig);
        const BodyFit fit = fitBody(body.points);
        lengths[0].push_back(fit.model.r[kNeck]);
        lengths[1].push_back(fit.model.r[kHead]);
      }
    for (int s = 0; s < 2; ++s) {
      double mean = 0, square = 0;
      for (double r : lengths[s]) mean += r / lengths[s].size();
      for (double r : lengths[s]) square += (r - mean) * (r - mean) / lengths[s].size();
      mean_sd[s] += std::sqrt(square) / people.size();
    }
  }
  std::printf("[ figure ] mesh people, 4 x 2 walks x 4 poses: neck SD %.1f mm, head SD %.1f mm\n",
              1000 * mean_sd[0], 1000 * mean_sd[1]);
  // Neck 7.4 mm (10.3 refined, 12.3 with the open sections' chin); head 8.2 mm (7.3 with the
  // hips on the lower torso's axis).
  EXPECT_LT(mean_sd[0], 0.0115);
  EXPECT_LT(mean_sd[1], 0.0095);
}

TEST(BodyFitter, MeshPeoplesLowerLegsKeepTheirLengthsAcrossTheirWalks) {
  // A knee that bends clearly in no scan hangs from the hip by the held thigh, so its height
  // moves with the pelvis between scans; the lower leg's length from the one scan whose foot is
  // planted carried that scan's error into the walk. Each lower leg's walk length (fitWalk) in
  // 2 walks of 4 people (the sampler, evaluate_gait_id's headings): SD between the walks, RMS
  // over both legs of everybody.
  eval::ScanRig rig;
  rig.columns = 200;
  rig.rows = 162;
  rig.noise_sigma = 0.002;
  rig.body = eval::BodyKind::kMesh;
  const auto people = eval::simulatedPeople(4, 3);
  double square = 0;
  int legs = 0;
  for (size_t k = 0; k < people.size(); ++k) {
    std::array<double, 2> lengths[2];
    for (int trial = 0; trial < 2; ++trial) {
      std::vector<Cloud> walk;
      for (int pose = 1; pose <= 4; ++pose) {
        const double heading = 0.4 * ((4 * k + pose - 1 + 2 * trial) % 5) - 0.8;
        walk.push_back(
            eval::sampleBody(eval::walkingSubject(people[k], pose, trial, heading), rig).points);
      }
      const WalkFit fits = fitWalk(walk);
      lengths[trial] = {fits.scans[0].model.r[kRightLowerLeg],
                        fits.scans[0].model.r[kLeftLowerLeg]};
    }
    for (int side = 0; side < 2; ++side, ++legs) {
      const double difference = lengths[0][side] - lengths[1][side];
      square += difference * difference / 2;  // the SD of two values, squared
    }
  }
  const double sd = std::sqrt(square / legs);
  std::printf("[ figure ] mesh people, 4 x 2 walks: lower legs' SD between walks %.1f mm\n",
              1000 * sd);
  // 5.1 mm (14.7 before the body's tilt and the pelvis were held); 25.6 from the planted scan.
  EXPECT_LT(sd, 0.019);
}

}  // namespace
}  // namespace body_gait_model
