// WalkCollector: a walk's 4 poses are handed over once all are in, in pose order, whatever the
// arrival order; abandoned walks are dropped; bad ids are refused.
#include <body_gait_model/walk_collector.h>
#include <gtest/gtest.h>

#include <string>

using body_gait_model::WalkCollector;

TEST(WalkCollector, HandsOverAWalkInPoseOrderOnceAllFourPosesAreIn) {
  WalkCollector<std::string> walks;
  EXPECT_FALSE(walks.add(7, 3, "c"));
  EXPECT_FALSE(walks.add(7, 1, "a"));
  EXPECT_FALSE(walks.add(8, 1, "other walk"));
  EXPECT_FALSE(walks.add(7, 4, "d"));
  EXPECT_EQ(walks.posesOf(7), 3);
  const auto walk = walks.add(7, 2, "b");
  ASSERT_TRUE(walk);
  EXPECT_EQ(*walk, (WalkCollector<std::string>::Walk{"a", "b", "c", "d"}));
  EXPECT_EQ(walks.posesOf(7), 0);  // handed over
  EXPECT_EQ(walks.posesOf(8), 1);
  EXPECT_TRUE(walks.takeDropped().empty());
}

TEST(WalkCollector, APoseGivenTwiceReplacesTheEarlierOne) {
  WalkCollector<std::string> walks;
  walks.add(1, 1, "first try");
  walks.add(1, 1, "a");
  walks.add(1, 2, "b");
  walks.add(1, 3, "c");
  const auto walk = walks.add(1, 4, "d");
  ASSERT_TRUE(walk);
  EXPECT_EQ((*walk)[0], "a");
}

TEST(WalkCollector, AnAbandonedWalkIsDroppedWhenTooManyAreOpen) {
  WalkCollector<int> walks(2);
  walks.add(1, 1, 10);
  walks.add(2, 1, 20);
  EXPECT_TRUE(walks.takeDropped().empty());
  walks.add(3, 1, 30);  // walk 1 is abandoned
  EXPECT_EQ(walks.takeDropped(), std::deque<std::uint32_t>{1});
  EXPECT_EQ(walks.posesOf(1), 0);
  EXPECT_EQ(walks.posesOf(3), 1);
}

TEST(WalkCollector, RefusesWalkIdZeroAndPoseIndicesOutsideOneToFour) {
  WalkCollector<int> walks;
  EXPECT_THROW(walks.add(0, 1, 0), std::invalid_argument);
  EXPECT_THROW(walks.add(1, 0, 0), std::invalid_argument);
  EXPECT_THROW(walks.add(1, 5, 0), std::invalid_argument);
}
