// The test cloud sampler: the rig sees every body part, range noise has the requested spread,
// dark surfaces and missing viewpoints remove what they should.
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <map>

namespace body_gait_model::eval {
namespace {

TEST(BodyCloudSampler, FullRigSamplesHalfAMillionPointsCoveringEveryPart) {
  const auto start = std::chrono::steady_clock::now();
  auto spec = simulatedSubjects(1).front();
  spec.pose = gaitPose(1, 0.4);
  ScanRig rig;
  rig.columns = 560;
  rig.rows = 460;
  const SampledBody body = sampleBody(spec, rig);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("[ figure ] full rig: %zu points in %.2f s\n", body.points.size(), seconds);
  EXPECT_GE(body.points.size(), 500000u);
  EXPECT_LE(body.points.size(), 1000000u);
  std::map<std::string, int> per_surface;
  for (int index : body.surface_of_point) ++per_surface[body.surface_names[index]];
  // Every outer surface (joint spheres inside the trunk, like the hips, are hidden).
  for (const char* part : {"head", "hair", "neck", "chest", "abdomen", "pelvis", "left_upper_arm",
                           "right_forearm", "left_hand", "right_thigh", "left_shank", "right_foot"})
    EXPECT_GT(per_surface[spec.name + "/" + part], 1000) << part << " is barely seen by the rig";
  EXPECT_EQ(body.skeleton.size(), body_scan_driver::sim::humanSkeleton(spec).size());
}

TEST(BodyCloudSampler, NoiseHasTheRequestedSpreadAlongTheRays) {
  auto spec = simulatedSubjects(1).front();
  ScanRig rig;
  rig.columns = 120;
  rig.rows = 100;
  const SampledBody exact = sampleBody(spec, rig);
  rig.noise_sigma = 0.002;
  const SampledBody noisy = sampleBody(spec, rig);
  ASSERT_EQ(exact.points.size(), noisy.points.size());  // same rays, same hits
  double sum_squares = 0;
  for (size_t i = 0; i < exact.points.size(); ++i)
    sum_squares += (noisy.points[i] - exact.points[i]).squaredNorm();
  const double sigma = std::sqrt(sum_squares / exact.points.size());
  std::printf("[ figure ] sampled noise sigma %.3f mm (requested 2 mm)\n", 1000 * sigma);
  EXPECT_NEAR(sigma, 0.002, 0.0001);
}

TEST(BodyCloudSampler, DarkSurfacesAndMissingViewpointsReturnNothing) {
  auto spec = simulatedSubjects(1).front();
  ScanRig rig;
  rig.columns = 120;
  rig.rows = 100;
  const SampledBody all = sampleBody(spec, rig);
  rig.min_albedo = 0.3;  // hair and clothing (albedo 0.15) return no light
  const SampledBody dark = sampleBody(spec, rig);
  for (int index : dark.surface_of_point) {
    const std::string& name = dark.surface_names[index];
    EXPECT_EQ(name.find("hair"), std::string::npos);
    EXPECT_EQ(name.find("pelvis"), std::string::npos);
  }
  EXPECT_LT(dark.points.size(), all.points.size());
  rig.min_albedo = 0;
  rig.missing_viewpoints = {0, 1, 2, 3};  // one whole pole
  const SampledBody missing = sampleBody(spec, rig);
  EXPECT_LT(missing.points.size(), 0.8 * all.points.size());
  EXPECT_GT(missing.points.size(), 0.5 * all.points.size());
}

TEST(BodyCloudSampler, GaitPosesMoveTheLimbsAsSection53Describes) {
  auto spec = simulatedSubjects(1).front();
  for (int index = 1; index <= 4; ++index) {
    spec.pose = gaitPose(index, 0.0);  // facing world +x
    const auto skeleton = body_scan_driver::sim::humanSkeleton(spec);
    std::map<std::string, Eigen::Vector3d> joint;
    for (const auto& j : skeleton) joint[j.name] = j.position;
    const double right_ahead = joint["right_ankle"].x() - joint["left_ankle"].x();
    if (index == 1) {  // right leg and left arm in front, longest stride
      EXPECT_GT(right_ahead, 0.2);
      EXPECT_GT(joint["left_wrist"].x(), joint["right_wrist"].x() + 0.2);
    } else if (index == 3) {
      EXPECT_LT(right_ahead, -0.2);
    } else if (index == 2) {  // left leg behind
      EXPECT_GT(right_ahead, 0.05);
    } else {
      EXPECT_LT(right_ahead, -0.05);
    }
  }
  EXPECT_THROW(gaitPose(5), std::invalid_argument);
}

}  // namespace
}  // namespace body_gait_model::eval
