// loadFitOptions: the shipped config reads back its documented values; overrides land in
// their fields; unknown keys, wrong types and missing files are errors naming the problem.
#include <body_gait_model/fit_options_file.h>
#include <gtest/gtest.h>
#include <ros/package.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>

namespace body_gait_model {
namespace {

std::string writeTemp(const std::string& text) {
  const std::string path = "/tmp/test_fit_options_" + std::to_string(::getpid()) + ".yaml";
  std::ofstream(path) << text;
  return path;
}

TEST(FitOptionsFile, ShippedConfigHoldsTheDefaults) {
  const FitOptions read = loadFitOptions(ros::package::getPath("body_gait_model") +
                                         "/config/body_fitter.yaml"),
                   defaults;
  EXPECT_EQ(read.refine, defaults.refine);
  EXPECT_EQ(read.torso.sectors, defaults.torso.sectors);
  EXPECT_DOUBLE_EQ(read.quality.max_rms, defaults.quality.max_rms);
  EXPECT_DOUBLE_EQ(read.quality.max_leg_share_deviation, defaults.quality.max_leg_share_deviation);
  EXPECT_DOUBLE_EQ(read.axes.shoulder_band_high, defaults.axes.shoulder_band_high);
  EXPECT_EQ(read.refinement.sample_points, defaults.refinement.sample_points);
  EXPECT_DOUBLE_EQ(read.hip_height, defaults.hip_height);
  EXPECT_DOUBLE_EQ(read.hip_depth_fraction, defaults.hip_depth_fraction);
  EXPECT_EQ(read.refinement.hold_thighs_in_walks, defaults.refinement.hold_thighs_in_walks);
  EXPECT_DOUBLE_EQ(read.shoulder_depth, defaults.shoulder_depth);
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    SCOPED_TRACE(segmentInfo(segment).name);
    EXPECT_NEAR(read.joint_limits[segment].x_min, walkingJointLimits()[segment].x_min, 1e-12);
    EXPECT_NEAR(read.joint_limits[segment].x_max, walkingJointLimits()[segment].x_max, 1e-12);
    EXPECT_NEAR(read.joint_limits[segment].z_min, walkingJointLimits()[segment].z_min, 1e-12);
    EXPECT_NEAR(read.joint_limits[segment].z_max, walkingJointLimits()[segment].z_max, 1e-12);
  }
}

TEST(FitOptionsFile, JointLimitSetsAreSelectable) {
  const std::string thesis_path = writeTemp("joint_limits: thesis\n");
  const FitOptions thesis = loadFitOptions(thesis_path);
  std::remove(thesis_path.c_str());
  EXPECT_DOUBLE_EQ(thesis.joint_limits[kLeftLowerLeg].x_max, jointLimits(kLeftLowerLeg).x_max);
  const std::string knee_path = writeTemp("joint_limits: {lower_leg: {x: [0, 90], z: [-5, 5]}}\n");
  const FitOptions knee = loadFitOptions(knee_path);
  std::remove(knee_path.c_str());
  EXPECT_NEAR(knee.joint_limits[kRightLowerLeg].x_max, 3.14159265358979323846 / 2, 1e-12);
  EXPECT_NEAR(knee.joint_limits[kLeftLowerLeg].z_min, -5 * 3.14159265358979323846 / 180, 1e-12);
  EXPECT_DOUBLE_EQ(knee.joint_limits[kLeftUpperArm].x_max,
                   walkingJointLimits()[kLeftUpperArm].x_max);  // untouched
}

TEST(FitOptionsFile, OverridesLandInTheirFields) {
  const std::string path =
      writeTemp("refine: false\ntorso: {sectors: 24}\nrefinement:\n  huber_scale: 0.05\n");
  const FitOptions options = loadFitOptions(path);
  std::remove(path.c_str());
  EXPECT_FALSE(options.refine);
  EXPECT_EQ(options.torso.sectors, 24);
  EXPECT_DOUBLE_EQ(options.refinement.huber_scale, 0.05);
  EXPECT_DOUBLE_EQ(options.torso.delta_ut, TorsoOptions{}.delta_ut);  // untouched
}

void expectError(const std::string& text, const std::string& part) {
  const std::string path = writeTemp(text);
  try {
    loadFitOptions(path);
    ADD_FAILURE() << "no error for: " << text;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

TEST(FitOptionsFile, BadFilesAreClearErrors) {
  expectError("torso: {sector: 24}\n", "unknown key 'torso.sector'");
  expectError("refine: maybe\n", "'refine' has value 'maybe' of the wrong type");
  expectError("[1, 2]\n", "must be a map");
  expectError("joint_limits: table52\n", "use walking, thesis or a map");
  expectError("joint_limits: {knee: {x: [0, 90], z: [0, 0]}}\n", "unknown key 'joint_limits.knee'");
  expectError("joint_limits: {lower_leg: {x: [90, 0], z: [0, 0]}}\n", "min <= max");
  expectError("hip_height: 53\n", "use 0 < hip_height < 1");
  expectError("hip_depth_fraction: 40\n", "use 0 < hip_depth_fraction < 1");
  expectError("shoulder_depth: -1\n", "use 0 .. 4");
  EXPECT_THROW(loadFitOptions("/nonexistent/body_fitter.yaml"), std::runtime_error);
}

}  // namespace
}  // namespace body_gait_model
