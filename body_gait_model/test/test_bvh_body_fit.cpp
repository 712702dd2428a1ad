// The fitter on a real walk: the CMU walk 07_02 (motion capture, body_scan_driver/data/cmu_walks)
// drives the simulated body; its 4 representative poses of 5.3 are scanned by the full
// scanner and fitted; errors are against the BVH joints. Figures: evaluate_body_fit --bvh.
#include <body_gait_model/body_fitter.h>
#include <body_gait_model/eval/full_scanner_body.h>
#include <body_scan_driver/sim/bvh_body.h>
#include <body_scan_driver/sim/data_paths.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace body_gait_model {
namespace {

namespace sim = body_scan_driver::sim;
constexpr double kPi = 3.14159265358979323846;

std::string walkPath(const std::string& walk) { return sim::cmuWalksDir() + "/" + walk + ".bvh"; }

sim::BvhSubject loadWalk(const std::string& walk) {
  return sim::BvhSubject(sim::loadBvh(walkPath(walk)),
                         sim::loadBvhJointMap(sim::driverConfigDir() + "/bvh/cmu_joint_map.yaml"),
                         walk);
}

// A walk's 4 representative poses on the ellipsoid body, scanned by the full scanner once per
// test binary: two tests fit 07_02's scans, and a scan takes seconds.
const std::vector<eval::SampledBody>& scannedWalk(const std::string& walk) {
  static std::map<std::string, std::vector<eval::SampledBody>> scanned;
  auto [entry, added] = scanned.try_emplace(walk);
  if (added) {
    const sim::BvhSubject subject = loadWalk(walk);
    const sim::GaitPoseFrames poses = sim::pickGaitPoses(subject);
    for (int pose = 0; pose < 4; ++pose)
      entry->second.push_back(eval::scanBodyWithFullScanner(subject.body(poses.frame[pose])));
  }
  return entry->second;
}

TEST(BvhBodyFit, FourPosesOfARealWalkScannedAndFitted) {
  const std::string path = walkPath("07_02");
  ASSERT_TRUE(std::filesystem::exists(path))
      << "CMU walk not found: " << path
      << " (body_scan_driver/data/cmu_walks, or BODY_SCAN_BVH_DIR naming a folder with it)";
  const sim::BvhSubject subject = loadWalk("07_02");
  const sim::GaitPoseFrames poses = sim::pickGaitPoses(subject);
  // The frames bvh_gait_poses reports (README), 0-based here.
  EXPECT_EQ(poses.frame, (std::array<int, 4>{10, 38, 74, 107}));
  double joint = 0, length = 0, swing = 0;
  int right = 0;
  for (int pose = 0; pose < 4; ++pose) {
    SCOPED_TRACE("pose " + std::to_string(pose + 1));
    const eval::SampledBody& body = scannedWalk("07_02")[pose];
    // The truth the fit is judged against is the BVH's joints, placed in the scanner.
    const auto bvh = subject.joints(poses.frame[pose]);
    EXPECT_NEAR((eval::trueJoint(body, "left_knee") - eval::trueJoint(body, "left_ankle")).norm(),
                (bvh.at("left_knee") - bvh.at("left_ankle")).norm(), 1e-9);
    EXPECT_GT(body.points.size(), 300000u);
    const BodyFit fit = fitBody(body.points);
    const eval::FitErrors errors = eval::compareWithTruth(fit.model, body);
    EXPECT_TRUE(errors.front_right && errors.left_right);
    EXPECT_LT(errors.mean_joint_error, 0.10);
    joint += errors.mean_joint_error / 4;
    length += errors.mean_length_error / 4;
    swing += errors.mean_swing_error / 4;
    right += errors.front_right && errors.left_right;
  }
  std::printf(
      "[ figure ] 07_02, 4 poses (frames %d %d %d %d): mean joint-centre error %.1f mm, "
      "segment-length error %.1f %%, swing-angle error %.2f deg, front/left right %d/4\n",
      poses.frame[0] + 1, poses.frame[1] + 1, poses.frame[2] + 1, poses.frame[3] + 1, 1000 * joint,
      100 * length, swing * 180 / kPi, right);
  // Measured 36.6 mm, 9.1 %, 3.2 deg with the legs tracked apart slice by slice (52.3 mm,
  // 14.4 %, 6.0 deg when split at the hips' centre, where the feet cross it in mid-stance; 56 mm
  // with Table 5.2's knee +-30 deg, which cannot follow a real swing leg).
  EXPECT_LT(joint, 0.045);
  EXPECT_LT(length, 0.12);
  EXPECT_LT(swing, 5 * kPi / 180);
}

TEST(BvhBodyFit, ALiftedShankMeetingTheOtherFootKeepsItsLength) {
  // CMU walk 08_03 on the mesh human, walk-level fit: in pose 2 the left foot swings past the
  // planted right one, whose floor points the left leg's slices took in; a line aimed at the
  // left shank's ankle met the floor among them, and that distance (0.70 m instead of 0.47 m)
  // counted as a planted sole: the left lower leg came out 26 % long and all 4 fits flagged.
  const std::string path = walkPath("08_03");
  ASSERT_TRUE(std::filesystem::exists(path)) << "CMU walk not found: " << path;
  const sim::BvhSubject subject = loadWalk("08_03");
  const sim::GaitPoseFrames poses = sim::pickGaitPoses(subject);
  eval::FullScannerOptions scanner;
  scanner.body = eval::BodyKind::kMesh;
  std::vector<eval::SampledBody> bodies;
  std::vector<Cloud> clouds;
  for (int pose = 0; pose < 4; ++pose) {
    bodies.push_back(eval::scanBodyWithFullScanner(subject.body(poses.frame[pose]), scanner));
    clouds.push_back(bodies.back().points);
  }
  const WalkFit walk = fitWalk(clouds);
  double length_bias = 0;
  for (int pose = 0; pose < 4; ++pose) {
    SCOPED_TRACE("pose " + std::to_string(pose + 1));
    EXPECT_FALSE(walk.scans[pose].quality.low_quality) << walk.scans[pose].quality.reason;
    length_bias += eval::compareWithTruth(walk.scans[pose].model, bodies[pose])
                       .segment_length_bias.at("left_lower_leg") /
                   4;
  }
  std::printf("[ figure ] 08_03 on the mesh human: left lower leg %+.1f %%\n", 100 * length_bias);
  EXPECT_LT(std::abs(length_bias), 0.1);  // measured +4.6 %; +25.9 % before
}

// Pose `pose` (0-based) of a CMU walk on the mesh human, scanned by the full scanner, fitted
// alone and compared with the BVH's joints.
eval::FitErrors meshPoseErrors(const std::string& walk, int pose) {
  const std::string path = walkPath(walk);
  EXPECT_TRUE(std::filesystem::exists(path)) << "CMU walk not found: " << path;
  const sim::BvhSubject subject = loadWalk(walk);
  eval::FullScannerOptions scanner;
  scanner.body = eval::BodyKind::kMesh;
  const eval::SampledBody body =
      eval::scanBodyWithFullScanner(subject.body(sim::pickGaitPoses(subject).frame[pose]), scanner);
  return eval::compareWithTruth(fitBody(body.points).model, body);
}

TEST(BvhBodyFit, AShortPersonsSeenCrownPlacesTheHead) {
  // CMU walk 35_01 on the mesh human: the head's highest point lies 12-21 mm below the stature
  // its shoulders' top implies, which was taken for a crown above the viewpoints' sight; the
  // head was not aimed at it and the refinement left it pitched 30-50 deg forward (head top
  // 65-95 mm off, 50-80 mm low). The crown closes as a dome: seen.
  const eval::FitErrors errors = meshPoseErrors("35_01", 0);
  const double head = errors.joint_error.at("head_top");
  std::printf("[ figure ] 35_01 pose 1 on the mesh human: head top %.1f mm off\n", 1000 * head);
  EXPECT_LT(head, 0.045);  // measured 29.5 mm; 54.2 mm before
}

TEST(BvhBodyFit, AForearmAcrossTheThighReachesItsHand) {
  // CMU walk 07_02 on the mesh human, pose 1: the left forearm turns across the thigh, 15 deg
  // beyond the elbow's coronal limit that the walking limits had (the model has no humeral
  // twist, the elbow's theta_z stands for it): the hand tip was held 80-90 mm lateral.
  const eval::FitErrors errors = meshPoseErrors("07_02", 0);
  const double hand = errors.joint_error.at("left_hand_tip");
  std::printf("[ figure ] 07_02 pose 1 on the mesh human: left hand tip %.1f mm off\n",
              1000 * hand);
  EXPECT_LT(hand, 0.05);  // measured 32.6 mm; 87.5 mm with the elbow's z within +-15 deg
}

TEST(BvhBodyFit, OnePersonsTwoWalksShareTheirNeckLength) {
  // CMU person 07's walks 07_02 and 07_08 (one skeleton), walk-level fits: the neck is short and
  // its surface hardly tells where it ends, so a walk refinement that let its length go moved it
  // with the rest of the chain (07_08: 82 mm against 07_02's 98) and the person's walks no
  // longer matched in identify_walks. It keeps the direct fits' median.
  double neck[2] = {0, 0};
  const char* walks[2] = {"07_02", "07_08"};
  for (int w = 0; w < 2; ++w) {
    std::vector<Cloud> clouds;
    for (const eval::SampledBody& body : scannedWalk(walks[w])) clouds.push_back(body.points);
    const WalkFit fit = fitWalk(clouds);
    ASSERT_EQ(fit.scans.size(), 4u);
    neck[w] = fit.scans.front().model.r[kNeck];
  }
  std::printf("[ figure ] person 07's walks: neck %.1f and %.1f mm\n", 1000 * neck[0],
              1000 * neck[1]);
  EXPECT_LT(std::abs(neck[0] - neck[1]), 0.010);  // 5 mm; 16 mm with the neck refined
}

}  // namespace
}  // namespace body_gait_model
