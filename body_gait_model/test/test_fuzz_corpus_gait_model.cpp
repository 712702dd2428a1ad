// This package's fuzz targets (fuzz/*.cpp) over their checked-in corpus (fuzz/corpus/<target>):
// what make fuzz found once stays fixed. A finding aborts the test.
#include <body_scan_driver/fuzz_target.h>
#include <body_scan_driver/tools/package_file.h>
#include <body_scan_msgs/BodyModel.h>
#include <body_scan_msgs/GaitSequence.h>
#include <gtest/gtest.h>
#include <sensor_msgs/PointCloud2.h>

TEST(FuzzCorpus, EveryTargetReplaysItsCorpus) {
  const auto runs = body_scan_driver::fuzz::replayCorpus(
      body_scan_driver::tools::packageDir("body_gait_model") + "/fuzz/corpus");
  for (const char* target :
       {"point_cloud2", "body_model", "gait_sequence", "body_model_yaml", "fit_options"}) {
    ASSERT_TRUE(runs.count(target)) << target << " is not registered";
    EXPECT_GE(runs.at(target), 2u) << target << ": seeds in fuzz/corpus/" << target;
  }
}

// Each message seed is one whole message of today's definition (a seed serialized before a field
// was added would be rejected at deserialization and test nothing).
TEST(FuzzCorpus, MessageSeedsAreWholeMessages) {
  const std::string corpus =
      body_scan_driver::tools::packageDir("body_gait_model") + "/fuzz/corpus";
  using body_scan_driver::fuzz::staleMessageSeeds;
  const std::vector<std::string> none;
  EXPECT_EQ(staleMessageSeeds<sensor_msgs::PointCloud2>(corpus, "point_cloud2"), none);
  EXPECT_EQ(staleMessageSeeds<body_scan_msgs::BodyModel>(corpus, "body_model"), none);
  EXPECT_EQ(staleMessageSeeds<body_scan_msgs::GaitSequence>(corpus, "gait_sequence"), none);
}
