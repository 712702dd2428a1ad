// This package's fuzz targets (fuzz/*.cpp) over their checked-in corpus (fuzz/corpus/<target>):
// what make fuzz found once stays fixed. A finding aborts the test.
#include <body_scan_driver/fuzz_target.h>
#include <body_scan_driver/tools/package_file.h>
#include <body_scan_msgs/PairCloud.h>
#include <body_scan_msgs/TimingGroups.h>
#include <gtest/gtest.h>

TEST(FuzzCorpus, EveryTargetReplaysItsCorpus) {
  const auto runs = body_scan_driver::fuzz::replayCorpus(
      body_scan_driver::tools::packageDir("body_scan_merge") + "/fuzz/corpus");
  for (const char* target : {"pair_cloud", "timing_groups", "timing_groups_yaml", "ply"}) {
    ASSERT_TRUE(runs.count(target)) << target << " is not registered";
    EXPECT_GE(runs.at(target), 2u) << target << ": seeds in fuzz/corpus/" << target;
  }
}

// Each message seed is one whole message of today's definition (a seed serialized before a field
// was added would be rejected at deserialization and test nothing).
TEST(FuzzCorpus, MessageSeedsAreWholeMessages) {
  const std::string corpus =
      body_scan_driver::tools::packageDir("body_scan_merge") + "/fuzz/corpus";
  using body_scan_driver::fuzz::staleMessageSeeds;
  const std::vector<std::string> none;
  EXPECT_EQ(staleMessageSeeds<body_scan_msgs::PairCloud>(corpus, "pair_cloud"), none);
  EXPECT_EQ(staleMessageSeeds<body_scan_msgs::TimingGroups>(corpus, "timing_groups"), none);
}
