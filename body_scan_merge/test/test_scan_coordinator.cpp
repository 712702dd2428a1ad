// ScanCoordinator rostest (scan_coordinator.test): the scan service triggers every pair of the
// plan with the scan id, in groups; a pair whose driver is absent is named, the others capture;
// a walk session scans 4 poses, each pattern set stamped with the walk id and pose index.
#include <body_scan_driver/test_time_scale.h>
#include <body_scan_msgs/CaptureWalk.h>
#include <body_scan_msgs/PatternSet.h>
#include <body_scan_msgs/Scan.h>
#include <body_scan_msgs/TimingGroups.h>
#include <body_scan_msgs/WalkProgress.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_msgs/Empty.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <set>

using body_scan_driver::scaledSeconds;

namespace {

const std::vector<std::string> kPresent = {"pole_a/pair_1", "pole_a/pair_3", "pole_c/pair_2"};

struct PatternSets {
  std::mutex mutex;
  std::map<std::string, std::multiset<uint32_t>> scan_ids;              // per pair
  std::map<uint32_t, std::set<std::pair<uint32_t, int>>> walk_of_scan;  // (walk id, pose index)
  std::vector<ros::Subscriber> subscribers;

  explicit PatternSets(ros::NodeHandle& nh) {
    for (const std::string& id : kPresent)
      subscribers.push_back(nh.subscribe<body_scan_msgs::PatternSet>(
          "/" + id + "/pattern_set", 10, [this](const body_scan_msgs::PatternSetConstPtr& set) {
            std::lock_guard<std::mutex> lock(mutex);
            scan_ids[set->pair_id].insert(set->scan_id);
            walk_of_scan[set->scan_id].insert({set->walk_id, set->pose_index});
          }));
    // A set published before the connection is made is lost: a scan that needs no planning
    // (all_at_once) answers within milliseconds of the subscription.
    for (const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(scaledSeconds(10.0));
         ros::WallTime::now() < end; ros::WallDuration(0.02).sleep())
      if (std::all_of(subscribers.begin(), subscribers.end(),
                      [](const ros::Subscriber& s) { return s.getNumPublishers() > 0; }))
        break;
  }
  // Waits (at most 10 s) until every present pair published a set with this scan id.
  bool allHave(uint32_t scan_id) {
    for (const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(scaledSeconds(10.0));
         ros::WallTime::now() < end; ros::WallDuration(0.05).sleep()) {
      std::lock_guard<std::mutex> lock(mutex);
      bool all = true;
      for (const std::string& id : kPresent) all = all && scan_ids[id].count(scan_id) == 1;
      if (all) return true;
    }
    return false;
  }
};

std::set<std::string> membersOf(const std::vector<std::string>& groups) {
  std::set<std::string> members;
  for (const std::string& group : groups) {
    std::istringstream in(group);
    for (std::string id; in >> id;) members.insert(id);
  }
  return members;
}

}  // namespace

TEST(ScanCoordinator, CapturesEveryPairWithTheScanIdInItsGroups) {
  ros::NodeHandle nh;
  PatternSets sets(nh);
  ASSERT_TRUE(ros::service::waitForService("/body_scan/capture", ros::Duration(scaledSeconds(30))));
  body_scan_msgs::Scan scan;
  scan.request.scan_id = 42;
  ASSERT_TRUE(ros::service::call("/body_scan/capture", scan));
  EXPECT_TRUE(scan.response.success) << scan.response.message;
  EXPECT_EQ(scan.response.scan_id, 42u);
  EXPECT_TRUE(scan.response.pairs_missing.empty());
  EXPECT_EQ(membersOf(scan.response.groups),
            std::set<std::string>(kPresent.begin(), kPresent.end()));
  EXPECT_DOUBLE_EQ(scan.response.simulated_capture_seconds, 0.5 * scan.response.groups.size());
  EXPECT_TRUE(sets.allHave(42));
  // The latched plan matches the groups the scan used.
  auto plan = ros::topic::waitForMessage<body_scan_msgs::TimingGroups>(
      "/body_scan/timing_groups", nh, ros::Duration(scaledSeconds(5)));
  ASSERT_TRUE(plan);
  EXPECT_EQ(plan->groups, scan.response.groups);
  std::cout << "[ figure ] " << scan.response.message << "\n";

  // The next scan without an id: the coordinator's next one, all pairs again.
  body_scan_msgs::Scan next;
  ASSERT_TRUE(ros::service::call("/body_scan/capture", next));
  EXPECT_TRUE(next.response.success) << next.response.message;
  EXPECT_EQ(next.response.scan_id, 43u);
  EXPECT_TRUE(sets.allHave(43));
}

TEST(ScanCoordinator, AnAbsentDriverIsNamedAndTheOthersStillCapture) {
  ros::NodeHandle nh;
  PatternSets sets(nh);
  ASSERT_TRUE(ros::service::waitForService("/partial/capture", ros::Duration(scaledSeconds(30))));
  body_scan_msgs::Scan scan;
  scan.request.scan_id = 77;
  const ros::WallTime start = ros::WallTime::now();
  ASSERT_TRUE(ros::service::call("/partial/capture", scan));
  EXPECT_LT((ros::WallTime::now() - start).toSec(), scaledSeconds(30.0))
      << "the coordinator must not hang";
  EXPECT_FALSE(scan.response.success);
  EXPECT_EQ(scan.response.pairs_missing, std::vector<std::string>{"pole_b/pair_1"});
  EXPECT_NE(scan.response.message.find("pole_b/pair_1"), std::string::npos)
      << scan.response.message;
  EXPECT_TRUE(sets.allHave(77));
  // Without its calibration file the absent pair was planned in a group of its own.
  EXPECT_EQ(std::count(scan.response.groups.begin(), scan.response.groups.end(), "pole_b/pair_1"),
            1);
  std::cout << "[ figure ] " << scan.response.message << "\n";
}

TEST(ScanCoordinator, WithoutTfThePosesComeFromTheRigFile) {
  ros::NodeHandle nh;
  PatternSets sets(nh);
  ASSERT_TRUE(ros::service::waitForService("/rig_poses/capture", ros::Duration(scaledSeconds(30))));
  body_scan_msgs::Scan scan, reference;
  scan.request.scan_id = 90;
  ASSERT_TRUE(ros::service::call("/rig_poses/capture", scan));
  EXPECT_TRUE(scan.response.success) << scan.response.message;
  EXPECT_TRUE(sets.allHave(90));
  reference.request.scan_id = 91;
  ASSERT_TRUE(ros::service::call("/body_scan/capture", reference));  // poses from tf
  EXPECT_EQ(scan.response.groups, reference.response.groups);
  EXPECT_EQ(scan.response.groups.size(), 3u);  // the three pairs light each other's views
  // Planned from geometry (a pair planned alone for want of a pose has no conflicts listed).
  auto planned = ros::topic::waitForMessage<body_scan_msgs::TimingGroups>(
      "/rig_poses/timing_groups", nh, ros::Duration(scaledSeconds(5)));
  auto from_tf = ros::topic::waitForMessage<body_scan_msgs::TimingGroups>(
      "/body_scan/timing_groups", nh, ros::Duration(scaledSeconds(5)));
  ASSERT_TRUE(planned && from_tf);
  EXPECT_FALSE(planned->conflicts.empty());
  EXPECT_EQ(planned->conflicts, from_tf->conflicts);
}

TEST(ScanCoordinator, AllAtOnceTriggersEveryPairInOneGroup) {
  ros::NodeHandle nh;
  PatternSets sets(nh);
  ASSERT_TRUE(
      ros::service::waitForService("/all_at_once/capture", ros::Duration(scaledSeconds(30))));
  body_scan_msgs::Scan scan;
  scan.request.scan_id = 120;
  ASSERT_TRUE(ros::service::call("/all_at_once/capture", scan));
  EXPECT_TRUE(scan.response.success) << scan.response.message;
  ASSERT_EQ(scan.response.groups.size(), 1u);
  EXPECT_EQ(membersOf(scan.response.groups),
            std::set<std::string>(kPresent.begin(), kPresent.end()));
  EXPECT_DOUBLE_EQ(scan.response.simulated_capture_seconds, 0.5);
  EXPECT_TRUE(sets.allHave(120));
}

TEST(ScanCoordinator, AWalkScansFourPosesStampedWithWalkIdAndPoseOnTrigger) {
  ros::NodeHandle nh;
  PatternSets sets(nh);
  ASSERT_TRUE(
      ros::service::waitForService("/body_scan/capture_walk", ros::Duration(scaledSeconds(30))));
  // The operator: triggers each pose once it has been prompted.
  std::mutex mutex;
  std::vector<body_scan_msgs::WalkProgress> progress;
  ros::Publisher trigger = nh.advertise<std_msgs::Empty>("/body_scan/walk_trigger", 4);
  ros::Subscriber progress_sub = nh.subscribe<body_scan_msgs::WalkProgress>(
      "/body_scan/walk_progress", 20, [&](const body_scan_msgs::WalkProgressConstPtr& p) {
        std::lock_guard<std::mutex> lock(mutex);
        progress.push_back(*p);
        if (p->state == body_scan_msgs::WalkProgress::PROMPT && p->waiting_for_trigger)
          trigger.publish(std_msgs::Empty());
      });
  for (const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(scaledSeconds(10.0));
       ros::WallTime::now() < end &&
       (trigger.getNumSubscribers() == 0 || progress_sub.getNumPublishers() == 0);
       ros::WallDuration(0.02).sleep()) {
  }
  body_scan_msgs::CaptureWalk walk;
  walk.request.walk_id = 5;
  walk.request.trigger = true;
  ASSERT_TRUE(ros::service::call("/body_scan/capture_walk", walk));
  EXPECT_TRUE(walk.response.success) << walk.response.message;
  EXPECT_EQ(walk.response.walk_id, 5u);
  ASSERT_EQ(walk.response.scan_ids.size(), 4u);
  for (int pose = 1; pose <= 4; ++pose) {
    const uint32_t scan_id = walk.response.scan_ids[pose - 1];
    EXPECT_TRUE(sets.allHave(scan_id)) << "pose " << pose;
    std::lock_guard<std::mutex> lock(sets.mutex);
    // Every pair's set of this scan carries the same walk id and pose index.
    EXPECT_EQ(sets.walk_of_scan[scan_id], (std::set<std::pair<uint32_t, int>>{{5u, pose}}));
  }
  // Prompted, scanned and done in order (the latched DONE is the last message).
  for (const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(scaledSeconds(5.0));
       ros::WallTime::now() < end; ros::WallDuration(0.02).sleep()) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!progress.empty() && progress.back().state == body_scan_msgs::WalkProgress::DONE) break;
  }
  std::lock_guard<std::mutex> lock(mutex);
  std::vector<std::pair<int, int>> steps;  // (state, pose) of prompts and scanned poses
  for (const auto& p : progress)
    if (p.walk_id == 5 && p.state != body_scan_msgs::WalkProgress::SCANNING)
      steps.push_back({p.state, p.pose_index});
  using P = body_scan_msgs::WalkProgress;
  const std::vector<std::pair<int, int>> expected = {
      {P::PROMPT, 1},  {P::SCANNED, 1}, {P::PROMPT, 2},  {P::SCANNED, 2}, {P::PROMPT, 3},
      {P::SCANNED, 3}, {P::PROMPT, 4},  {P::SCANNED, 4}, {P::DONE, 4}};
  EXPECT_EQ(steps, expected);
  std::cout << "[ figure ] " << walk.response.message << "\n";

  // A single scan after the walk is no part of it.
  body_scan_msgs::Scan single;
  ASSERT_TRUE(ros::service::call("/body_scan/capture", single));
  EXPECT_TRUE(sets.allHave(single.response.scan_id));
  std::lock_guard<std::mutex> sets_lock(sets.mutex);
  EXPECT_EQ(sets.walk_of_scan[single.response.scan_id],
            (std::set<std::pair<uint32_t, int>>{{0u, 0}}));
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_scan_coordinator");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
