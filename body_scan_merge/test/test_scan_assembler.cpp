#include <body_scan_merge/scan_assembler.h>
#include <gtest/gtest.h>

using body_scan_merge::ScanAssembler;
using Assembler = ScanAssembler<int>;

TEST(ScanAssembler, AScanIsCompleteWhenEveryPairHasDeliveredInTheExpectedOrder) {
  Assembler assembler({"a", "b", "c"}, 5.0);
  std::vector<Assembler::Scan> done;
  EXPECT_EQ(assembler.add("c", 7, 3, 0.0, done), Assembler::Arrival::kAccepted);
  EXPECT_EQ(assembler.add("a", 7, 1, 0.1, done), Assembler::Arrival::kAccepted);
  EXPECT_TRUE(done.empty());
  assembler.add("b", 7, 2, 0.2, done);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].scan_id, 7u);
  ASSERT_EQ(done[0].parts.size(), 3u);
  EXPECT_EQ(done[0].parts[0], (std::pair<std::string, int>{"a", 1}));
  EXPECT_EQ(done[0].parts[2], (std::pair<std::string, int>{"c", 3}));
  EXPECT_TRUE(done[0].missing.empty());
  EXPECT_EQ(assembler.pendingScans(), 0u);
}

TEST(ScanAssembler, APairThatNeverAnswersIsReportedMissingAfterTheTimeout) {
  Assembler assembler({"a", "b", "c"}, 5.0);
  std::vector<Assembler::Scan> done;
  assembler.add("a", 1, 1, 10.0, done);
  assembler.add("c", 1, 3, 11.0, done);
  assembler.poll(14.9, done);
  EXPECT_TRUE(done.empty());
  assembler.poll(15.0, done);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].parts.size(), 2u);
  EXPECT_EQ(done[0].missing, std::vector<std::string>{"b"});
  // Its cloud arriving later is recognised as late, not started as a new scan.
  EXPECT_EQ(assembler.add("b", 1, 2, 16.0, done), Assembler::Arrival::kLate);
  EXPECT_EQ(assembler.pendingScans(), 0u);
}

TEST(ScanAssembler, InterleavedScansDoNotLoseEachOther) {
  Assembler assembler({"a", "b"}, 5.0);
  std::vector<Assembler::Scan> done;
  assembler.add("a", 1, 10, 0.0, done);
  assembler.add("a", 2, 20, 0.5, done);  // a newer scan starts before scan 1 is complete
  assembler.add("b", 2, 21, 0.6, done);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].scan_id, 2u);
  assembler.add("b", 1, 11, 0.7, done);
  ASSERT_EQ(done.size(), 2u);
  EXPECT_EQ(done[1].scan_id, 1u);
  EXPECT_EQ(done[1].parts[1].second, 11);
}

TEST(ScanAssembler, UnknownPairsAndRepeatsAreRejected) {
  Assembler assembler({"a", "b"}, 5.0);
  std::vector<Assembler::Scan> done;
  EXPECT_EQ(assembler.add("z", 1, 0, 0.0, done), Assembler::Arrival::kUnknownPair);
  EXPECT_EQ(assembler.pendingScans(), 0u);
  EXPECT_EQ(assembler.add("a", 1, 1, 0.0, done), Assembler::Arrival::kAccepted);
  EXPECT_EQ(assembler.add("a", 1, 9, 0.1, done), Assembler::Arrival::kRepeated);
  assembler.add("b", 1, 2, 0.2, done);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].parts[0].second, 1);  // the first cloud, not the repeat
  EXPECT_THROW(Assembler({}, 1.0), std::invalid_argument);
}
