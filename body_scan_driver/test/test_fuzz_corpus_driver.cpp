// The driver's fuzz targets (fuzz/*.cpp) over their checked-in corpus (fuzz/corpus/<target>):
// what make fuzz found once stays fixed. A finding aborts the test.
#include <body_scan_driver/fuzz_target.h>
#include <body_scan_driver/ros/message_checks.h>
#include <body_scan_driver/tools/package_file.h>
#include <body_scan_msgs/PatternSet.h>
#include <gtest/gtest.h>

TEST(FuzzCorpus, EveryTargetReplaysItsCorpus) {
  const auto runs = body_scan_driver::fuzz::replayCorpus(
      body_scan_driver::tools::packageDir("body_scan_driver") + "/fuzz/corpus");
  for (const char* target : {"pattern_set", "calibration_yaml", "scene", "rig", "pair"}) {
    ASSERT_TRUE(runs.count(target)) << target << " is not registered";
    EXPECT_GE(runs.at(target), 2u) << target << ": seeds in fuzz/corpus/" << target;
  }
}

// Each message seed is one whole message of today's definition (a seed serialized before a field
// was added would be rejected at deserialization and test nothing).
TEST(FuzzCorpus, MessageSeedsAreWholeMessages) {
  const std::string corpus =
      body_scan_driver::tools::packageDir("body_scan_driver") + "/fuzz/corpus";
  using body_scan_driver::fuzz::staleMessageSeeds;
  const std::vector<std::string> none;
  EXPECT_EQ(staleMessageSeeds<body_scan_msgs::PatternSet>(corpus, "pattern_set"), none);
  // The valid seed passes the check, so its replay runs Triangulate's path (PatternSetCloud).
  std::ifstream in(corpus + "/pattern_set/valid_32x24.bin", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  body_scan_msgs::PatternSet set;
  ASSERT_TRUE(body_scan_driver::fuzz::deserialize(reinterpret_cast<const uint8_t*>(bytes.data()),
                                                  bytes.size(), set));
  EXPECT_EQ(body_scan_driver::checkPatternSet(set), std::nullopt);
  EXPECT_EQ(set.frames.at(0).width, 32u);
}
