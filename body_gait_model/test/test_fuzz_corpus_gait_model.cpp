// This package's fuzz targets (fuzz/*.cpp) over their checked-in corpus (fuzz/corpus/<target>):
// what make fuzz found once stays fixed. A finding aborts the test.
#include <body_scan_driver/fuzz_target.h>
#include <body_scan_driver/tools/package_file.h>
#include <gtest/gtest.h>

TEST(FuzzCorpus, EveryTargetReplaysItsCorpus) {
  const auto runs = body_scan_driver::fuzz::replayCorpus(
      body_scan_driver::tools::packageDir("body_gait_model") + "/fuzz/corpus");
  for (const char* target :
       {"point_cloud2", "body_model", "gait_sequence", "body_model_yaml", "fit_options"}) {
    ASSERT_TRUE(runs.count(target)) << target << " is not registered";
    EXPECT_GE(runs.at(target), 2u) << target << ": seeds in fuzz/corpus/" << target;
  }
}
