// The poses file of play_gait_cycle: a written file reads back to the same poses, the shape
// defaults to a standard adult of the legs' stature, and bad files are errors naming the fix.
#include <body_gait_model/gait_poses_file.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <string>

namespace body_gait_model {
namespace {

std::string temporaryPath(const std::string& name) {
  return "/tmp/test_gait_poses_file_" + std::to_string(getpid()) + "_" + name;
}

RepresentativePoses somePoses() {
  RepresentativePoses poses;
  for (int i = 0; i < 4; ++i) {
    poses[i] = standingModel(1.65 + 0.02 * i);
    poses[i].p << 0.1 * i, -0.05, 0.95, 0.01, 0.3, -0.02;
    poses[i].setJointAngles(kRightUpperLeg, -0.1 * i, 0.01 * i);
    poses[i].setJointAngles(kLeftLowerArm, -0.123456789012345, 0);
    poses[i].shape.shoulder_drop = 0.02 + 0.001 * i;
    poses[i].shape.hip_back = 0.03 + 0.001 * i;
  }
  return poses;
}

TEST(GaitPosesFile, WrittenPosesReadBackExactly) {
  const std::string path = temporaryPath("round_trip.yaml");
  const RepresentativePoses poses = somePoses();
  saveRepresentativePoses(path, poses);
  const RepresentativePoses back = loadRepresentativePoses(path);
  std::remove(path.c_str());
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(back[i].p, poses[i].p) << "s" << i + 1;
    EXPECT_EQ(back[i].q, poses[i].q) << "s" << i + 1;
    EXPECT_EQ(back[i].r, poses[i].r) << "s" << i + 1;
    EXPECT_EQ(back[i].shape.distal_radius, poses[i].shape.distal_radius) << "s" << i + 1;
    EXPECT_EQ(back[i].shape.shoulder_drop, poses[i].shape.shoulder_drop) << "s" << i + 1;
    EXPECT_EQ(back[i].shape.hip_back, poses[i].shape.hip_back) << "s" << i + 1;
  }
}

// Four standing poses of `adult` with p, q, r only, then extra(i) under pose i; read back.
RepresentativePoses loadMinimalPoses(const BodyModel& adult,
                                     const std::function<std::string(int)>& extra) {
  const std::string path = temporaryPath("minimal.yaml");
  {
    std::ofstream file(path);
    file << "poses:\n";
    for (int i = 0; i < 4; ++i) {
      file << "  - p: [0, 0, 1.04, 0, 0, 0]\n    q: [";
      for (int k = 0; k < 22; ++k) file << (k ? ", " : "") << 0;
      file << "]\n    r: [";
      for (int k = 0; k < 12; ++k) file << (k ? ", " : "") << adult.r[k];
      file << "]\n" << extra(i);
    }
  }
  const RepresentativePoses poses = loadRepresentativePoses(path);
  std::remove(path.c_str());
  return poses;
}

TEST(GaitPosesFile, ShapeDefaultsToTheLegsStature) {
  const BodyModel adult = standingModel(1.8);
  const RepresentativePoses poses = loadMinimalPoses(adult, [](int) { return ""; });
  EXPECT_NEAR(poses[2].shape.shoulder_half_width, adult.shape.shoulder_half_width, 1e-12);
  EXPECT_NEAR(poses[2].shape.proximal_radius[kHead], adult.shape.proximal_radius[kHead], 1e-12);
}

// A model written before hip_back existed (hip_rise, no hip_back) had its hips on the lower
// torso's axis; a model without any placement gets the standard adult's.
TEST(GaitPosesFile, ModelsWithoutHipBackKeepTheirHipsOnTheAxis) {
  const BodyModel adult = standingModel(1.8);
  ASSERT_GT(adult.shape.hip_back, 0.01);
  const RepresentativePoses poses =
      loadMinimalPoses(adult, [](int i) { return i < 2 ? "    hip_rise: 0.2\n" : ""; });
  EXPECT_EQ(poses[0].shape.hip_back, 0.0);
  EXPECT_EQ(poses[0].shape.hip_rise, 0.2);
  EXPECT_NEAR(poses[3].shape.hip_back, adult.shape.hip_back, 1e-12);
}

void expectLoadError(const std::string& content, const std::string& words) {
  const std::string path = temporaryPath("bad.yaml");
  {
    std::ofstream file(path);
    file << content;
  }
  try {
    loadRepresentativePoses(path);
    ADD_FAILURE() << "expected std::runtime_error mentioning '" << words << "'";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
  }
  std::remove(path.c_str());
}

TEST(GaitPosesFile, BadFilesNameTheProblem) {
  try {
    loadRepresentativePoses("/nonexistent/poses.yaml");
    ADD_FAILURE() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("cannot be read"), std::string::npos);
  }
  expectLoadError("poses: []\n", "exactly 4 poses");
  const std::string pose =
      "  - {p: [0,0,1,0,0,0], q: [0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0], "
      "r: [.4,.07,.2,.3,.4,.3,.4,.1,.4,.5,.4,.5]}\n";
  expectLoadError("poses:\n" + pose + pose + pose +
                      "  - {p: [0,0,1,0,0], q: [0], r: [.4,.07,.2,.3,.4,.3,.4,.1,.4,.5,.4,.5]}\n",
                  "pose s4.p has 5 numbers, not 6");
  expectLoadError(
      "poses:\n" + pose + pose + pose +
          "  - {p: [0,0,1,0,0,0], qq: [0], r: [.4,.07,.2,.3,.4,.3,.4,.1,.4,.5,.4,.5]}\n",
      "unknown key 'qq'");
}

}  // namespace
}  // namespace body_gait_model
