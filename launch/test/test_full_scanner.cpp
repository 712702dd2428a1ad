// full_scanner.launch headless: one /body_scan/capture gives one merged cloud of the default
// subject with every pair present, 500 000 to 1 000 000 points, all in the scan volume of the
// world frame, and a scan report that accounts for them; the cloud's accuracy against the
// simulator's true surface (evaluation only) meets the whole-body accuracy targets, written as a
// YAML report.
#include <body_scan_driver/test_time_scale.h>
#include <body_scan_merge/eval/scan_accuracy.h>
#include <body_scan_msgs/Scan.h>
#include <body_scan_msgs/ScanReport.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <cmath>
#include <cstring>
#include <mutex>

using body_scan_driver::scaledSeconds;

namespace {

std::mutex mutex;
sensor_msgs::PointCloud2ConstPtr last_cloud;
body_scan_msgs::ScanReportConstPtr last_report;

void onCloud(const sensor_msgs::PointCloud2ConstPtr& cloud) {
  std::lock_guard<std::mutex> lock(mutex);
  last_cloud = cloud;
}

void onReport(const body_scan_msgs::ScanReportConstPtr& report) {
  std::lock_guard<std::mutex> lock(mutex);
  last_report = report;
}

}  // namespace

TEST(FullScanner, OneScanGivesOneWholeBodyCloudFromEveryPair) {
  ros::NodeHandle nh, pnh("~");
  const int min_points = pnh.param("min_points", 500000);
  const int max_points = pnh.param("max_points", 1000000);
  const int expected_pairs = pnh.param("expected_pairs", 12);
  ros::Subscriber cloud_sub = nh.subscribe("/body_scan/cloud", 1, &onCloud);
  ros::Subscriber report_sub = nh.subscribe("/body_scan/scan_report", 1, &onReport);
  ASSERT_TRUE(ros::service::waitForService("/body_scan/capture", ros::Duration(scaledSeconds(60))))
      << "/body_scan/capture not advertised: is the ScanCoordinator running?";

  // Nodes that started with the coordinator may still be connecting their topics.
  ros::WallDuration(scaledSeconds(pnh.param("settle", 0.0))).sleep();
  const ros::WallTime start = ros::WallTime::now();
  body_scan_msgs::Scan scan;
  ASSERT_TRUE(ros::service::call("/body_scan/capture", scan));
  std::vector<std::string> expected_missing;
  pnh.getParam("expected_missing", expected_missing);
  std::cout << "[ figure ] capture response: " << scan.response.message << "\n";
  EXPECT_EQ(scan.response.success, expected_missing.empty()) << scan.response.message;
  EXPECT_EQ(scan.response.pairs_missing, expected_missing);
  std::cout << "[ figure ] " << scan.response.groups.size() << " timing groups, simulated capture "
            << scan.response.simulated_capture_seconds << " s; capture call took "
            << (ros::WallTime::now() - start).toSec() << " s wall\n";

  sensor_msgs::PointCloud2ConstPtr cloud;
  body_scan_msgs::ScanReportConstPtr report;
  for (ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(scaledSeconds(60));
       ros::WallTime::now() < deadline; ros::WallDuration(0.05).sleep()) {
    std::lock_guard<std::mutex> lock(mutex);
    if (last_report && last_report->scan_id == scan.response.scan_id && last_cloud) {
      cloud = last_cloud;
      report = last_report;
      break;
    }
  }
  ASSERT_TRUE(cloud && report) << "no merged cloud and report for scan " << scan.response.scan_id;
  std::cout << "[ figure ] first merged cloud " << (ros::WallTime::now() - start).toSec()
            << " s after the capture call\n";
  EXPECT_EQ(cloud->header.frame_id, "world");
  EXPECT_EQ(static_cast<int>(report->pairs_present.size()), expected_pairs);
  EXPECT_EQ(report->pairs_missing, expected_missing) << report->message;

  const size_t points = static_cast<size_t>(cloud->width) * cloud->height;
  size_t finite = 0, in_volume = 0;
  for (sensor_msgs::PointCloud2ConstIterator<float> it(*cloud, "x"); it != it.end(); ++it) {
    if (!std::isfinite(it[0]) || !std::isfinite(it[1]) || !std::isfinite(it[2])) continue;
    ++finite;
    in_volume += std::hypot(it[0], it[1]) < 0.7 && it[2] > 0 && it[2] < 2.2;
  }
  std::cout << "[ figure ] merged cloud: " << points << " points (" << in_volume
            << " in the scan volume); report: " << report->points_merged << "\n";
  EXPECT_EQ(finite, points);
  EXPECT_EQ(in_volume, points);
  EXPECT_EQ(report->points_merged, points);
  EXPECT_GE(static_cast<int>(points), min_points);
  EXPECT_LE(static_cast<int>(points), max_points);

  // Accuracy against the true surface of the scene the drivers rendered.
  const std::string scene_file = pnh.param<std::string>("scene_file", "");
  if (scene_file.empty()) return;
  std::vector<float> xyzrgb(points * 4);
  std::memcpy(xyzrgb.data(), cloud->data.data(), xyzrgb.size() * sizeof(float));
  const auto scene = body_scan_driver::sim::loadScene(scene_file);
  const auto accuracy = body_scan_merge::eval::evaluateScan(xyzrgb, scene);
  const std::string report_file = pnh.param<std::string>("accuracy_report", "");
  if (!report_file.empty())
    body_scan_merge::eval::writeAccuracyReport(report_file, accuracy,
                                               "full_scanner.test, " + scene_file);
  using body_scan_merge::eval::Region;
  std::cout << "[ figure ] accuracy: mean distance " << 1000 * accuracy.mean_distance
            << " mm (median " << 1000 * accuracy.median_distance << ", " << accuracy.outliers
            << " points > 20 mm), body covered within 5 mm " << 100 * accuracy.body.fraction()
            << " % (soles excluded)";
  for (const auto& [region, coverage] : accuracy.regions)
    std::cout << ", " << body_scan_merge::eval::regionName(region) << " "
              << 100 * coverage.fraction() << " %";
  std::cout << "; report " << report_file << "\n";
  EXPECT_LE(accuracy.mean_distance, 0.002);
  EXPECT_GE(accuracy.body.fraction(), 0.95);
  for (Region region : {Region::kUnderChin, Region::kArmpitLeft, Region::kArmpitRight,
                        Region::kGroin, Region::kTorsoSideLeft, Region::kTorsoSideRight})
    EXPECT_GE(accuracy.regions.at(region).fraction(), 0.80)
        << body_scan_merge::eval::regionName(region);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_full_scanner");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
