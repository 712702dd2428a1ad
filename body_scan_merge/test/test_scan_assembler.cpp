#include <body_scan_merge/scan_assembler.h>
#include <gtest/gtest.h>

using body_scan::ScanAssembler;
using Assembler = ScanAssembler<int>;

namespace {
const std::vector<std::string> kPairs = {"pole_a/pair_1", "pole_a/pair_2", "pole_b/pair_1"};
}

TEST(ScanAssembler, CompleteWhenEveryPairArrived) {
  Assembler assembler(kPairs, 2.0);
  EXPECT_EQ(assembler.add(kPairs[0], 7, 10, 0.0), Assembler::AddResult::kAccepted);
  EXPECT_EQ(assembler.add(kPairs[1], 7, 11, 0.1), Assembler::AddResult::kAccepted);
  EXPECT_TRUE(assembler.poll(0.2).empty());
  EXPECT_EQ(assembler.add(kPairs[2], 7, 12, 0.3), Assembler::AddResult::kAccepted);
  const auto ready = assembler.poll(0.3);  // well before the timeout
  ASSERT_EQ(ready.size(), 1u);
  EXPECT_EQ(ready[0].scan_id, 7u);
  EXPECT_EQ(ready[0].clouds.size(), 3u);
  EXPECT_EQ(ready[0].clouds.at(kPairs[1]), 11);
  EXPECT_TRUE(ready[0].missing.empty());
  EXPECT_EQ(assembler.pendingScans(), 0u);
}

TEST(ScanAssembler, TimeoutReportsMissingPairs) {
  Assembler assembler(kPairs, 2.0);
  assembler.add(kPairs[0], 3, 1, 10.0);
  assembler.add(kPairs[2], 3, 3, 11.0);
  EXPECT_TRUE(assembler.poll(11.99).empty());  // timeout counts from the first cloud
  const auto ready = assembler.poll(12.0);
  ASSERT_EQ(ready.size(), 1u);
  EXPECT_EQ(ready[0].clouds.size(), 2u);
  ASSERT_EQ(ready[0].missing.size(), 1u);
  EXPECT_EQ(ready[0].missing[0], kPairs[1]);
}

TEST(ScanAssembler, LateCloudOfPublishedScanIsDropped) {
  Assembler assembler(kPairs, 1.0);
  assembler.add(kPairs[0], 5, 1, 0.0);
  ASSERT_EQ(assembler.poll(1.5).size(), 1u);
  EXPECT_EQ(assembler.add(kPairs[1], 5, 2, 1.6), Assembler::AddResult::kLate);
  EXPECT_EQ(assembler.pendingScans(), 0u);
  EXPECT_TRUE(assembler.poll(10.0).empty());
}

TEST(ScanAssembler, NewerScanDoesNotLoseOlderIncompleteOne) {
  Assembler assembler(kPairs, 2.0);
  assembler.add(kPairs[0], 1, 100, 0.0);
  assembler.add(kPairs[1], 1, 101, 0.1);
  for (size_t i = 0; i < kPairs.size(); ++i)  // scan 2 completes first
    assembler.add(kPairs[i], 2, 200 + static_cast<int>(i), 0.5);
  auto ready = assembler.poll(0.6);
  ASSERT_EQ(ready.size(), 1u);
  EXPECT_EQ(ready[0].scan_id, 2u);
  EXPECT_EQ(assembler.add(kPairs[2], 1, 102, 0.7), Assembler::AddResult::kAccepted);
  ready = assembler.poll(0.7);
  ASSERT_EQ(ready.size(), 1u);
  EXPECT_EQ(ready[0].scan_id, 1u);
  EXPECT_EQ(ready[0].clouds.size(), 3u);
  EXPECT_EQ(ready[0].clouds.at(kPairs[2]), 102);
}

TEST(ScanAssembler, DuplicateAndUnknownPairsAreRejected) {
  Assembler assembler(kPairs, 2.0);
  EXPECT_EQ(assembler.add(kPairs[0], 1, 1, 0.0), Assembler::AddResult::kAccepted);
  EXPECT_EQ(assembler.add(kPairs[0], 1, 9, 0.1), Assembler::AddResult::kDuplicate);
  EXPECT_EQ(assembler.add("pole_z/pair_9", 1, 1, 0.1), Assembler::AddResult::kUnexpectedPair);
  const auto ready = assembler.poll(3.0);
  ASSERT_EQ(ready.size(), 1u);
  EXPECT_EQ(ready[0].clouds.at(kPairs[0]), 1);  // the first cloud is kept
  EXPECT_EQ(ready[0].missing.size(), 2u);
}
