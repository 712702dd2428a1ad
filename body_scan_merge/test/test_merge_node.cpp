// Merge nodelet against three simulated pairs: one cloud + report per scan with every pair's
// points; a pair that does not deliver is named missing after the timeout; its late cloud is
// dropped.
#include <body_scan_driver/test_time_scale.h>
#include <body_scan_msgs/Capture.h>
#include <body_scan_msgs/PairCloud.h>
#include <body_scan_msgs/ScanReport.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <std_srvs/Trigger.h>

#include <cmath>
#include <map>
#include <mutex>
#include <thread>

using body_scan_driver::scaledSeconds;

namespace {

class MergeNode : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(ros::NodeHandle("~").getParam("pairs", pairs_));
    ASSERT_EQ(pairs_.size(), 3u);
    report_sub_ = nh_.subscribe("/body_scan/scan_report", 10, &MergeNode::onReport, this);
    cloud_sub_ = nh_.subscribe("/body_scan/cloud", 10, &MergeNode::onCloud, this);
    for (const auto& pair : pairs_) {
      pair_subs_.push_back(nh_.subscribe<body_scan_msgs::PairCloud>(
          "/" + pair + "/scan_points", 10, [this](const body_scan_msgs::PairCloud::ConstPtr& c) {
            size_t valid = 0;
            for (sensor_msgs::PointCloud2ConstIterator<float> z(c->cloud, "z"); z != z.end(); ++z)
              valid += std::isfinite(*z);
            std::lock_guard<std::mutex> lock(mutex_);
            valid_[{c->pair_id, c->scan_id}] = valid;
          }));
      ASSERT_TRUE(ros::service::waitForService("/" + pair + "/driver/capture",
                                               ros::Duration(scaledSeconds(30))))
          << pair;
    }
    for (int i = 0; i < 100 && report_sub_.getNumPublishers() == 0; ++i)
      ros::WallDuration(0.1).sleep();
    ASSERT_GT(report_sub_.getNumPublishers(), 0u) << "merge is not publishing scan_report";
    // Each pair's Triangulate loads after its driver's capture service is up (a slow start, as
    // under a sanitizer, showed it): wait for every pair's cloud publisher.
    for (size_t i = 0; i < pairs_.size(); ++i) {
      const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(scaledSeconds(30));
      while (pair_subs_[i].getNumPublishers() == 0 && ros::WallTime::now() < deadline)
        ros::WallDuration(0.05).sleep();
      ASSERT_GT(pair_subs_[i].getNumPublishers(), 0u) << "no publisher: " << pairs_[i];
    }
    // What the ScanCoordinator asks before a scan: are the merge's subscriptions connected?
    ASSERT_TRUE(ros::service::waitForService("/body_scan/merge/inputs_connected",
                                             ros::Duration(scaledSeconds(30))));
    std_srvs::Trigger inputs;
    for (const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(scaledSeconds(30));
         ros::WallTime::now() < deadline; ros::WallDuration(0.05).sleep())
      if (ros::service::call("/body_scan/merge/inputs_connected", inputs) &&
          inputs.response.success)
        break;
    ASSERT_TRUE(inputs.response.success) << inputs.response.message;
    EXPECT_EQ(inputs.response.message, "every running pair's scan_points is connected");
  }

  void capture(const std::string& pair, uint32_t scan_id) {
    body_scan_msgs::Capture srv;
    srv.request.scan_id = scan_id;
    ASSERT_TRUE(ros::service::call("/" + pair + "/driver/capture", srv)) << pair;
    ASSERT_TRUE(srv.response.success) << srv.response.message;
  }

  // The report of `scan_id`, waiting up to `wait` s; nullptr if none.
  body_scan_msgs::ScanReport::ConstPtr waitReport(uint32_t scan_id, double wait) {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(scaledSeconds(wait));
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& r : reports_)
          if (r->scan_id == scan_id) return r;
      }
      ros::WallDuration(0.02).sleep();
    }
    return nullptr;
  }

  void onReport(const body_scan_msgs::ScanReport::ConstPtr& report) {
    std::lock_guard<std::mutex> lock(mutex_);
    reports_.push_back(report);
    report_times_.push_back(ros::WallTime::now());
  }
  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& cloud) {
    std::lock_guard<std::mutex> lock(mutex_);
    clouds_.push_back(cloud);
  }

  // The cloud of a report (same stamp: cloud and report arrive in any order), waiting up to 5 s.
  sensor_msgs::PointCloud2::ConstPtr cloudOf(const body_scan_msgs::ScanReport& report) {
    for (int i = 0; i < 250; ++i) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& cloud : clouds_)
          if (cloud->header.stamp == report.header.stamp) return cloud;
      }
      ros::WallDuration(0.02).sleep();
    }
    return nullptr;
  }

  ros::NodeHandle nh_;
  std::vector<std::string> pairs_;
  ros::Subscriber report_sub_, cloud_sub_;
  std::vector<ros::Subscriber> pair_subs_;
  std::mutex mutex_;
  std::vector<body_scan_msgs::ScanReport::ConstPtr> reports_;
  std::vector<ros::WallTime> report_times_;
  std::vector<sensor_msgs::PointCloud2::ConstPtr> clouds_;
  std::map<std::pair<std::string, uint32_t>, size_t> valid_;
};

TEST_F(MergeNode, MergesAllPairsThenReportsMissingPairAfterTimeout) {
  // 1. Every pair captures scan 10 (at once, as the coordinator triggers a group: one after the
  //    other, the last cloud came later than the merge's timeout after the first): one report,
  //    all present, counts = each pair's own cloud.
  std::vector<std::thread> captures;
  for (const auto& pair : pairs_) captures.emplace_back([this, pair] { capture(pair, 10); });
  for (auto& capturing : captures) capturing.join();
  const auto report = waitReport(10, 10.0);
  ASSERT_TRUE(report) << "no scan_report for scan 10";
  EXPECT_EQ(report->pairs_present.size(), 3u);
  EXPECT_TRUE(report->pairs_missing.empty());
  ASSERT_EQ(report->points_per_pair.size(), report->pairs_present.size());
  const auto cloud = cloudOf(*report);
  ASSERT_TRUE(cloud) << "no /body_scan/cloud with the report's stamp";
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (size_t i = 0; i < report->pairs_present.size(); ++i) {
      const auto key = std::make_pair(report->pairs_present[i], 10u);
      ASSERT_TRUE(valid_.count(key)) << report->pairs_present[i];
      EXPECT_EQ(report->points_per_pair[i], valid_[key]) << report->pairs_present[i];
      EXPECT_GT(valid_[key], 20000u) << "the person fills much of each view";
    }
    ASSERT_EQ(reports_.size(), 1u) << "one report per scan";
    EXPECT_EQ(cloud->header.frame_id, "world");
    EXPECT_EQ(cloud->width, report->points_merged);
    // The person from three sides: points on the front (x > 0.1), back (x < -0.1) and left
    // (y > 0.1) halves, all inside the scan volume.
    size_t front = 0, back = 0, left = 0, outside = 0;
    sensor_msgs::PointCloud2ConstIterator<float> it(*cloud, "x");
    for (; it != it.end(); ++it) {
      const float x = it[0], y = it[1], z = it[2];
      front += x > 0.1f;
      back += x < -0.1f;
      left += y > 0.1f;
      outside += z < 0.005f || z > 2.2f || x * x + y * y > 0.6f * 0.6f + 1e-4f;
    }
    EXPECT_GT(front, 5000u);
    EXPECT_GT(back, 5000u);
    EXPECT_GT(left, 5000u);
    EXPECT_EQ(outside, 0u);
  }

  // 2. The middle pair does not capture scan 11: the report names it after the merge's timeout
  //    and the cloud comes from the other two.
  double timeout = 0;
  ASSERT_TRUE(ros::param::get("/body_scan/merge/timeout", timeout));
  const ros::WallTime start = ros::WallTime::now();
  capture(pairs_[0], 11);
  capture(pairs_[2], 11);
  const auto partial = waitReport(11, 10.0);
  ASSERT_TRUE(partial) << "no scan_report for the incomplete scan 11";
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_GE((report_times_.back() - start).toSec(), timeout - 0.1);
  }
  ASSERT_EQ(partial->pairs_missing.size(), 1u);
  EXPECT_EQ(partial->pairs_missing[0], pairs_[1]);
  EXPECT_EQ(partial->pairs_present, (std::vector<std::string>{pairs_[0], pairs_[2]}));
  EXPECT_GT(partial->points_merged, 0u);
  EXPECT_NE(partial->message.find(pairs_[1]), std::string::npos);

  // 3. Its late cloud is dropped: no second report for scan 11.
  capture(pairs_[1], 11);
  ros::WallDuration(timeout + 1.0).sleep();
  std::lock_guard<std::mutex> lock(mutex_);
  EXPECT_EQ(reports_.size(), 2u);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_merge_node");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
