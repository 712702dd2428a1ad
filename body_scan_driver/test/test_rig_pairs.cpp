// See rig_pairs.test: a rig pair's ~capture honours active_pairs (the other pair's light shows
// in the frames) and names an unknown pair id.
#include <body_scan_driver/test_time_scale.h>
#include <body_scan_msgs/Capture.h>
#include <body_scan_msgs/PatternSet.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <mutex>

using body_scan_driver::scaledSeconds;

namespace {

const std::string kPair = "/pole_a/pair_2";

// Calls ~capture and returns the published pattern set of that scan.
body_scan_msgs::PatternSet::ConstPtr capture(ros::NodeHandle& nh, uint32_t scan_id,
                                             const std::vector<std::string>& active,
                                             body_scan_msgs::Capture& call) {
  std::mutex mutex;
  body_scan_msgs::PatternSet::ConstPtr received;
  const auto sub = nh.subscribe<body_scan_msgs::PatternSet>(
      kPair + "/pattern_set", 2, [&](const body_scan_msgs::PatternSet::ConstPtr& set) {
        std::lock_guard<std::mutex> lock(mutex);
        if (set->scan_id == scan_id) received = set;
      });
  const ros::WallTime wait_start = ros::WallTime::now();
  while (sub.getNumPublishers() == 0 &&
         ros::WallTime::now() - wait_start < ros::WallDuration(scaledSeconds(20)))
    ros::WallDuration(0.05).sleep();
  call.request.scan_id = scan_id;
  call.request.active_pairs = active;
  EXPECT_TRUE(ros::service::call(kPair + "/driver/capture", call));
  const ros::WallTime start = ros::WallTime::now();
  while (call.response.success &&
         ros::WallTime::now() - start < ros::WallDuration(scaledSeconds(20))) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (received) break;
    }
    ros::WallDuration(0.02).sleep();
  }
  std::lock_guard<std::mutex> lock(mutex);
  return received;
}

}  // namespace

TEST(RigPairs, CaptureHonoursActivePairs) {
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  ASSERT_TRUE(
      ros::service::waitForService(kPair + "/driver/capture", ros::Duration(scaledSeconds(30))));

  body_scan_msgs::Capture alone_call, both_call, bad_call;
  const auto alone = capture(nh, 5, {}, alone_call);
  ASSERT_TRUE(alone_call.response.success) << alone_call.response.message;
  ASSERT_TRUE(alone);
  const auto both = capture(nh, 5, {"pole_b/pair_2"}, both_call);
  ASSERT_TRUE(both_call.response.success) << both_call.response.message;
  ASSERT_TRUE(both);

  // Same scan id: same sensor noise; only the other pair's light differs. Count pixels of the
  // first Gray code frame brighter by > 20 grey levels.
  ASSERT_EQ(alone->frames.size(), both->frames.size());
  const auto& a = alone->frames[0].data;
  const auto& b = both->frames[0].data;
  ASSERT_EQ(a.size(), b.size());
  size_t brighter = 0, darker = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (b[i] > a[i] + 20) ++brighter;
    if (a[i] > b[i] + 20) ++darker;
  }
  std::cout << "[ figure ] pole_b/pair_2's light brightens " << brighter << " of " << a.size()
            << " pixels of pole_a/pair_2's first frame by > 20 grey levels\n";
  EXPECT_GT(brighter, a.size() / 50);
  EXPECT_EQ(darker, 0u);  // light only adds

  capture(nh, 6, {"pole_x/pair_9"}, bad_call);
  EXPECT_FALSE(bad_call.response.success);
  EXPECT_NE(bad_call.response.message.find("pole_x/pair_9"), std::string::npos)
      << bad_call.response.message;
  EXPECT_NE(bad_call.response.message.find("pole_b/pair_2"), std::string::npos)
      << bad_call.response.message;  // the known ids
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_rig_pairs");
  return RUN_ALL_TESTS();
}
