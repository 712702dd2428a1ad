// Cross-walk identification (eval/cross_walk.h): three people of different build and gait, two
// walks each (the second a slightly different repetition); every probe frame must find its
// person, and the protocol must refuse people with a single walk.
#include <body_gait_id/eval/cross_walk.h>
#include <gtest/gtest.h>

#include <random>

namespace body_gait_id::eval {
namespace {

using namespace body_gait_model;
constexpr double kDegree = 3.14159265358979323846 / 180;

struct Legs {
  double right_thigh, right_knee, left_thigh, left_knee;
};

// A walking pose on the standing model (test_gait_cycle's convention): a thigh swings forward
// under a negative theta_x, a knee bends under a positive one; the arms swing against the legs.
BodyModel walkingPose(const Legs& legs, double stature, double arm_swing, std::mt19937& noise,
                      double noise_deg) {
  std::normal_distribution<double> jitter(0.0, noise_deg * kDegree);
  BodyModel pose = standingModel(stature);
  pose.setJointAngles(kRightUpperLeg, -legs.right_thigh + jitter(noise), 2 * kDegree);
  pose.setJointAngles(kRightLowerLeg, legs.right_knee + jitter(noise), -1 * kDegree);
  pose.setJointAngles(kLeftUpperLeg, -legs.left_thigh + jitter(noise), -3 * kDegree);
  pose.setJointAngles(kLeftLowerLeg, legs.left_knee + jitter(noise), 1 * kDegree);
  pose.setJointAngles(kRightUpperArm, arm_swing * legs.right_thigh + jitter(noise), -5 * kDegree);
  pose.setJointAngles(kLeftUpperArm, arm_swing * legs.left_thigh + jitter(noise), 5 * kDegree);
  pose.setJointAngles(kRightLowerArm, -10 * kDegree + jitter(noise), 0);
  pose.setJointAngles(kLeftLowerArm, -12 * kDegree + jitter(noise), 0);
  for (int i = 0; i < pose.r.size(); ++i) pose.r[i] += 0.003 * jitter(noise) / kDegree;
  return pose;
}

// A person's walk: stride amplitude, knee bend and arm swing are the person's own.
WalkModels walk(const std::string& person, const std::string& name, double stature, double stride,
                double knee, double arms, std::uint32_t seed) {
  std::mt19937 noise(seed);
  const double noise_deg = 1.0;
  const double a = stride * kDegree, k = knee * kDegree;
  WalkModels w{person, name, {}};
  w.poses = {walkingPose({a, 0.2 * k, -0.8 * a, 0.6 * k}, stature, arms, noise, noise_deg),
             walkingPose({0, 0.1 * k, -0.6 * a, k}, stature, arms, noise, noise_deg),
             walkingPose({-0.8 * a, 0.6 * k, a, 0.2 * k}, stature, arms, noise, noise_deg),
             walkingPose({-0.6 * a, k, 0, 0.1 * k}, stature, arms, noise, noise_deg)};
  return w;
}

std::vector<WalkModels> threePeopleTwoWalks() {
  return {walk("A", "A_1", 1.62, 22, 30, 0.5, 1),  walk("B", "B_1", 1.75, 26, 22, 0.9, 2),
          walk("C", "C_1", 1.88, 18, 38, 0.3, 3),  walk("A", "A_2", 1.62, 22, 30, 0.5, 11),
          walk("B", "B_2", 1.75, 26, 22, 0.9, 12), walk("C", "C_2", 1.88, 18, 38, 0.3, 13)};
}

TEST(CrossWalk, EveryProbeFrameFindsItsPerson) {
  const CrossWalkResult result =
      identifyAcrossWalks(threePeopleTwoWalks(), FeatureSet::kDynamicStatic);
  // 2 rounds (gallery walk 1, then walk 2) x 3 probe walks x 20 frames.
  ASSERT_EQ(result.walks.size(), 6u);
  EXPECT_EQ(result.metrics.identification.n, 120);
  EXPECT_EQ(result.metrics.identification.count, 120);
  EXPECT_EQ(result.walks_right, 6);
  EXPECT_LT(result.metrics.average_cyclic_pose_error, 2.0);  // measured 1.29; chance ~5
  for (const auto& w : result.walks) {
    EXPECT_EQ(w.voted_person, w.person) << w.probe_walk;
    EXPECT_EQ(w.gallery_walks.size(), 3u);
    // The probe walk is never in the gallery.
    for (const auto& g : w.gallery_walks) EXPECT_NE(g, w.probe_walk);
  }
  EXPECT_EQ(result.walks[0].probe_walk, "A_2");
  EXPECT_EQ(result.walks[0].gallery_walks, (std::vector<std::string>{"A_1", "B_1", "C_1"}));
  EXPECT_EQ(result.walks[3].probe_walk, "A_1");
}

TEST(CrossWalk, APersonWithOneWalkOrASinglePersonIsRefused) {
  auto walks = threePeopleTwoWalks();
  walks.pop_back();  // C has one walk left
  EXPECT_THROW(identifyAcrossWalks(walks, FeatureSet::kDynamic), std::invalid_argument);
  const std::vector<WalkModels> alone = {threePeopleTwoWalks()[0], threePeopleTwoWalks()[3]};
  EXPECT_THROW(identifyAcrossWalks(alone, FeatureSet::kDynamic), std::invalid_argument);
}

}  // namespace
}  // namespace body_gait_id::eval
