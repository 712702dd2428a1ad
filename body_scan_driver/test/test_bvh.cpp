// The BVH reader: hand-computed forward kinematics, Euler order, the CMU walks
// (data/cmu_walks), malformed files with their line numbers, and the fuzz entry point over its
// seed corpus.
#include <body_scan_driver/sim/bvh.h>
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/tools/package_file.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace body_scan_driver::sim {
namespace {

// Seed files of the BVH fuzz target (fuzz/corpus/bvh): valid and malformed motion capture.
std::string fuzzCorpus() {
  return body_scan_driver::tools::packageDir("body_scan_driver") + "/fuzz/corpus/bvh";
}

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

const char* const kCmuWalks[] = {"07_02", "07_08", "08_03", "08_08", "35_01", "35_02"};

#define EXPECT_VECTOR_NEAR(actual, ex, ey, ez, tolerance) \
  EXPECT_LT(((actual)-Eigen::Vector3d(ex, ey, ez)).norm(), tolerance) << (actual).transpose()

TEST(Bvh, TwoJointsPoseAsComputedByHand) {
  const BvhMotion motion = loadBvh(fuzzCorpus() + "/valid_two_joints.bvh");
  ASSERT_EQ(motion.joints.size(), 2u);
  EXPECT_EQ(motion.channel_count, 9);
  EXPECT_EQ(motion.frames.size(), 2u);
  EXPECT_DOUBLE_EQ(motion.frame_time, 0.01);
  EXPECT_EQ(motion.joints[1].parent, 0);
  EXPECT_EQ(motion.joints[1].first_channel, 6);
  EXPECT_EQ(motion.jointIndex("Leg"), 1);
  EXPECT_EQ(motion.jointIndex("Arm"), -1);
  // Frame 0: root at (0, 10, 0), the leg turned 90 deg about x: its end site (0, -3, 0) -> z.
  const BvhPose first = poseBvhFrame(motion, 0);
  EXPECT_VECTOR_NEAR(first.position[1], 1, 8, 0, 1e-12);
  EXPECT_VECTOR_NEAR(first.end_site[1], 1, 8, -3, 1e-12);
  // Frame 1: root at (1, 10, 0) turned 30 deg about z; the leg's own 45 deg about y leaves its
  // end site direction (0, -3, 0) unchanged. cos 30 = 0.866025, sin 30 = 0.5.
  const BvhPose second = poseBvhFrame(motion, 1);
  EXPECT_VECTOR_NEAR(second.position[1], 1 + 0.866025 + 1, 10 + 0.5 - 2 * 0.866025, 0, 1e-5);
  EXPECT_VECTOR_NEAR(second.end_site[1], 2.866025 + 1.5, 8.767949 - 3 * 0.866025, 0, 1e-5);
  EXPECT_THROW(poseBvhFrame(motion, 2), std::out_of_range);
}

TEST(Bvh, RotationChannelsApplyInFileOrder) {
  auto endSite = [](const std::string& channels) {
    const BvhMotion motion = parseBvh("HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 2 " + channels +
                                      "\nEnd Site\n{\nOFFSET 0 -1 0\n}\n}\nMOTION\nFrames: 1\n"
                                      "Frame Time: 0.1\n90 90\n");
    return poseBvhFrame(motion, 0).end_site[0];
  };
  // Rz(90) Rx(90) (0,-1,0) = (0,0,-1); Rx(90) Rz(90) (0,-1,0) = (1,0,0).
  EXPECT_VECTOR_NEAR(endSite("Zrotation Xrotation"), 0, 0, -1, 1e-12);
  EXPECT_VECTOR_NEAR(endSite("Xrotation Zrotation"), 1, 0, 0, 1e-12);
}

TEST(Bvh, CmuWalksLoadWithRigidBonesAndWalkAlongZ) {
  const std::string dir = cmuWalksDir();
  ASSERT_TRUE(fs::exists(dir + "/07_02.bvh"))
      << "CMU walks not found in " << dir
      << " (body_scan_driver/data/cmu_walks, or BODY_SCAN_BVH_DIR naming a folder with them)";
  for (const char* walk : kCmuWalks) {
    SCOPED_TRACE(walk);
    const BvhMotion motion = loadBvh(dir + "/" + walk + ".bvh");
    EXPECT_EQ(motion.joints.size(), 31u);
    EXPECT_EQ(motion.channel_count, 96);
    ASSERT_EQ(motion.frames.size(), 200u);
    EXPECT_NEAR(motion.frame_time, 0.0083333, 1e-9);
    const int knee = motion.jointIndex("LeftLeg"), ankle = motion.jointIndex("LeftFoot");
    const int hips = motion.jointIndex("Hips"), head = motion.jointIndex("Head");
    ASSERT_GE(knee, 0);
    ASSERT_GE(ankle, 0);
    const double shank = motion.joints[ankle].offset.norm();
    double lowest_ankle = 1e9, highest_head = -1e9;
    for (int f = 0; f < 200; ++f) {
      const BvhPose pose = poseBvhFrame(motion, f);
      EXPECT_NEAR((pose.position[ankle] - pose.position[knee]).norm(), shank, 1e-9);
      lowest_ankle = std::min(lowest_ankle, pose.position[ankle].y());
      highest_head = std::max(highest_head, pose.position[head].y());
    }
    // 200 frames at 1.2-1.8 m/s: 2.0-3.0 m along +Z (0.056444 m per unit), little sideways.
    const Eigen::Vector3d walked =
        poseBvhFrame(motion, 199).position[hips] - poseBvhFrame(motion, 0).position[hips];
    EXPECT_GT(walked.z() * 0.056444, 1.9);
    EXPECT_LT(walked.z() * 0.056444, 3.1);
    EXPECT_LT(std::abs(walked.x()), 0.25 * walked.z());
    // Y is up: the head is ~1.5 m above the lowest ankle.
    EXPECT_NEAR((highest_head - lowest_ankle) * 0.056444, 1.45, 0.25);
  }
}

struct Malformed {
  const char* what;
  std::string text;
  int line;
  const char* message;  // a part of the error text
};

TEST(Bvh, MalformedFilesFailNamingTheLine) {
  const std::string head = "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 2 Xrotation Yrotation\n";
  const std::string motion = "}\nMOTION\nFrames: 2\nFrame Time: 0.01\n";
  const Malformed cases[] = {
      {"no header", "ROOT A\n", 1, "expected HIERARCHY"},
      {"unknown keyword", head + "BONE B\n}\n", 6, "unknown keyword 'BONE'"},
      {"unknown channel", "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrot\n}\n", 5,
       "unknown channel 'Xrot'"},
      {"channel count too big", "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 7 Xrotation\n", 5,
       "integer 0..6"},
      {"too few values", head + motion + "1 2\n3\n", 11, "frame 2 has 1 values"},
      {"too many values", head + motion + "1 2 3\n", 10, "frame 1 has 3 values"},
      {"missing frames", head + motion + "1 2\n", 10, "only 1 frame lines"},
      {"extra frames", head + motion + "1 2\n3 4\n5 6\n", 12, "more frame lines"},
      {"non-number", head + motion + "1 2\n3 x4\n", 11, "must be a number, got 'x4'"},
      {"NaN", head + motion + "1 2\nnan 4\n", 11, "must be finite"},
      {"infinity", head + motion + "1 2\n3 -inf\n", 11, "must be finite"},
      {"bad offset", "HIERARCHY\nROOT A\n{\nOFFSET 0 1,5 0\n", 4, "got '1,5'"},
      {"zero frame time", head + "}\nMOTION\nFrames: 1\nFrame Time: 0\n1 2\n", 9,
       "frame time must be > 0"},
      {"fractional frames", head + "}\nMOTION\nFrames: 1.5\n", 8, "frame count must be"},
      {"duplicate joint", head + "JOINT A\n{\n", 6, "'A' appears twice"},
      {"two roots", head + "}\nROOT B\n", 7, "a second ROOT"},
      {"truncated", head, 5, "unexpected end of file"},
      {"values on the header line", head + "}\nMOTION\nFrames: 1\nFrame Time: 0.01 1 2\n", 9,
       "must start on the line after"},
      {"empty", "", 1, "unexpected end of file"},
  };
  for (const Malformed& c : cases) {
    SCOPED_TRACE(c.what);
    try {
      parseBvh(c.text, "test.bvh");
      ADD_FAILURE() << "accepted";
    } catch (const BvhError& error) {
      EXPECT_EQ(error.line(), c.line) << error.what();
      EXPECT_NE(std::string(error.what()).find(c.message), std::string::npos) << error.what();
      EXPECT_EQ(std::string(error.what()).rfind("test.bvh:" + std::to_string(c.line) + ": ", 0), 0u)
          << error.what();
    }
  }
}

TEST(Bvh, MissingFileIsAnError) { EXPECT_THROW(loadBvh("/nonexistent/walk.bvh"), BvhError); }

TEST(Bvh, CrlfLineEndingsAndPlusSignsAreAccepted) {
  const BvhMotion motion = parseBvh(
      "HIERARCHY\r\nROOT A\r\n{\r\nOFFSET 0 +1 0\r\nCHANNELS 1 Xrotation\r\n}\r\nMOTION\r\n"
      "Frames: 1\r\nFrame Time: .0083333\r\n-.5\r\n");
  EXPECT_DOUBLE_EQ(motion.joints[0].offset.y(), 1.0);
  EXPECT_DOUBLE_EQ(motion.frames[0][0], -0.5);
}

// The fuzz target (fuzz/fuzz_bvh.cpp) over its seed corpus and the CMU files: what the fuzzer
// once found stays fixed in CI. Aborts (test crash) on a finding.
TEST(Bvh, FuzzEntryPointAcceptsTheSeedCorpus) {
  std::vector<fs::path> seeds;
  for (const auto& entry : fs::directory_iterator(fuzzCorpus())) seeds.push_back(entry.path());
  ASSERT_GE(seeds.size(), 5u);
  for (const char* walk : kCmuWalks) seeds.push_back(cmuWalksDir() + "/" + walk + ".bvh");
  for (const fs::path& seed : seeds) {
    SCOPED_TRACE(seed.string());
    const std::string text = readText(seed);
    EXPECT_EQ(
        LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), 0);
    // Every prefix of a small seed must fail cleanly or parse: truncation anywhere.
    if (text.size() < 2000)
      for (size_t cut = 0; cut < text.size(); ++cut)
        LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(text.data()), cut);
  }
}

}  // namespace
}  // namespace body_scan_driver::sim
