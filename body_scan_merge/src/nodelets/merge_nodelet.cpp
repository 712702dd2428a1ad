// Merge: the pair clouds of one scan id (/<pair>/scan_points) -> /body_scan/cloud (world frame,
// cropped to the scan volume, optional voxel grid and outlier removal) + /body_scan/scan_report.
// A pair that never answers is reported after ~timeout and the scan is assembled without it.
// ~inputs_connected (std_srvs/Trigger) says whether every running pair's scan_points is connected
// yet: ROS drops a message published before the subscriber's connection is made, so the
// ScanCoordinator asks before it triggers a scan.
#include <body_scan_driver/ros/conversions.h>
#include <body_scan_driver/ros/message_checks.h>
#include <body_scan_merge/cloud_merge.h>
#include <body_scan_merge/ros/cloud_view_msg.h>
#include <body_scan_merge/scan_assembler.h>
#include <body_scan_msgs/PairCloud.h>
#include <body_scan_msgs/ScanReport.h>
#include <body_scan_msgs/TimingGroups.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <mutex>
#include <pluginlib/class_list_macros.hpp>

#include "master_watch.h"

namespace body_scan_merge {

class MergeNodelet : public nodelet::Nodelet {
 private:
  using Part = body_scan_msgs::PairCloudConstPtr;

  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    std::vector<std::string> pairs;
    if (!pnh.getParam("pairs", pairs) || pairs.empty()) {
      for (const char* pole : {"pole_a", "pole_b", "pole_c"})
        for (int i = 1; i <= 4; ++i)
          pairs.push_back(std::string(pole) + "/pair_" + std::to_string(i));
      NODELET_INFO("~pairs not set: expecting the 12 pairs of the thesis rig");
    }
    world_frame_ = pnh.param<std::string>("world_frame", "world");
    const double timeout = pnh.param("timeout", 60.0);
    options_.crop_radius = pnh.param("crop_radius", options_.crop_radius);
    options_.crop_min_z = pnh.param("crop_min_z", options_.crop_min_z);
    options_.crop_max_z = pnh.param("crop_max_z", options_.crop_max_z);
    options_.voxel_leaf = pnh.param("voxel_leaf", options_.voxel_leaf);
    options_.outlier_removal = pnh.param("outlier_removal", options_.outlier_removal);
    options_.outlier_neighbours = pnh.param("outlier_neighbours", options_.outlier_neighbours);
    options_.outlier_std_ratio = pnh.param("outlier_std_ratio", options_.outlier_std_ratio);
    assembler_ = std::make_unique<ScanAssembler<Part>>(pairs, timeout);

    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);
    cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>("cloud", 2);
    report_pub_ = nh.advertise<body_scan_msgs::ScanReport>("scan_report", 10);
    // The pairs live next to this node's namespace (/body_scan -> /pole_a/pair_1/scan_points;
    // under a replay prefix /replay/body_scan -> /replay/pole_a/pair_1/scan_points).
    const std::string root = ros::names::parentNamespace(nh.getNamespace());
    for (const std::string& pair : pairs)
      subscribers_.push_back(
          nh.subscribe<body_scan_msgs::PairCloud>(ros::names::append(root, pair + "/scan_points"),
                                                  2, [this](const Part& part) { onPart(part); }));
    inputs_srv_ = pnh.advertiseService("inputs_connected", &MergeNodelet::onInputsConnected, this);
    groups_sub_ = nh.subscribe<body_scan_msgs::TimingGroups>(
        "timing_groups", 1, [this](const body_scan_msgs::TimingGroupsConstPtr& groups) {
          if (const auto problem = body_scan_driver::checkTimingGroups(*groups)) {
            if (throttle_.shouldReport(*problem, ros::WallTime::now().toSec()))
              NODELET_ERROR("timing_groups rejected: %s", problem->c_str());
            return;
          }
          std::lock_guard<std::mutex> lock(mutex_);
          groups_ = groups;
        });
    master_watch_ = MasterWatch::acquire();
    timer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) {
      std::vector<ScanAssembler<Part>::Scan> done;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        assembler_->poll(ros::WallTime::now().toSec(), done);
      }
      for (auto& scan : done) publishGuarded(scan);
    });
    NODELET_INFO(
        "merging scans of %zu pairs into %s (frame %s), pair timeout %.1f s, voxel %.4f m%s",
        pairs.size(), cloud_pub_.getTopic().c_str(), world_frame_.c_str(), timeout,
        options_.voxel_leaf, options_.outlier_removal ? ", outlier removal" : "");
  }

  // Ready when every pair cloud topic that has a publisher registered is connected here: a pair
  // whose Triangulate is down is not waited for (Merge reports it missing). Connected means a
  // link to the Triangulate exists; its connection header follows within milliseconds, long
  // before that pair's capture can produce a cloud.
  bool onInputsConnected(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
    ros::master::V_TopicInfo published;
    bool asked = false, master_answered = false;
    std::string waiting, absent;
    for (const ros::Subscriber& subscriber : subscribers_) {
      if (subscriber.getNumPublishers() > 0) continue;
      if (!asked) {  // the master only when a topic is not connected (once per call)
        master_answered = ros::master::getTopics(published);
        asked = true;
      }
      const bool registered = std::any_of(
          published.begin(), published.end(),
          [&](const ros::master::TopicInfo& t) { return t.name == subscriber.getTopic(); });
      (registered || !master_answered ? waiting : absent) += " " + subscriber.getTopic();
    }
    response.success = waiting.empty();
    response.message = response.success ? "every running pair's scan_points is connected"
                                        : "connecting to:" + waiting;
    if (!absent.empty()) response.message += "; no publisher (pair not running):" + absent;
    return true;
  }

  // A cloud that fails checkPairCloud never reaches the assembler; no exception leaves a
  // callback (it would terminate the whole nodelet manager).
  void onPart(const Part& part) {
    if (const auto problem = body_scan_driver::checkPairCloud(*part)) {
      if (throttle_.shouldReport(part->pair_id + *problem, ros::WallTime::now().toSec()))
        NODELET_ERROR("scan_points of '%s' (scan %u) rejected: %s", part->pair_id.c_str(),
                      part->scan_id, problem->c_str());
      return;
    }
    std::vector<ScanAssembler<Part>::Scan> done;
    ScanAssembler<Part>::Arrival arrival;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      arrival =
          assembler_->add(part->pair_id, part->scan_id, part, ros::WallTime::now().toSec(), done);
    }
    if (arrival == ScanAssembler<Part>::Arrival::kLate)
      NODELET_WARN("[%s] cloud of scan %u arrived after the scan was published (raise ~timeout)",
                   part->pair_id.c_str(), part->scan_id);
    else if (arrival == ScanAssembler<Part>::Arrival::kUnknownPair)
      NODELET_WARN_THROTTLE(10.0, "cloud from '%s', which is not in ~pairs: ignored",
                            part->pair_id.c_str());
    else if (arrival == ScanAssembler<Part>::Arrival::kRepeated)
      NODELET_WARN("[%s] second cloud for scan %u: ignored", part->pair_id.c_str(), part->scan_id);
    for (auto& scan : done) publishGuarded(scan);
  }

  void publishGuarded(const ScanAssembler<Part>::Scan& scan) {
    try {
      publish(scan);
    } catch (const std::exception& e) {
      NODELET_ERROR_THROTTLE(5.0, "scan %u not merged: %s", scan.scan_id, e.what());
    } catch (...) {
      NODELET_ERROR_THROTTLE(5.0, "scan %u not merged: unknown error", scan.scan_id);
    }
  }

  void publish(const ScanAssembler<Part>::Scan& scan) {
    const ros::WallTime start = ros::WallTime::now();
    body_scan_msgs::ScanReportPtr report(new body_scan_msgs::ScanReport);
    report->scan_id = scan.scan_id;
    report->pairs_expected = assembler_->expectedPairs();
    report->pairs_missing = scan.missing;
    // Every pair of a scan was triggered with the same walk id and pose index.
    if (!scan.parts.empty()) {
      report->walk_id = scan.parts.begin()->second->walk_id;
      report->pose_index = scan.parts.begin()->second->pose_index;
    }
    std::vector<CloudView> views;
    double slowest_pair = 0;
    ros::Time stamp;
    for (const auto& [pair_id, part] : scan.parts) {
      const sensor_msgs::PointCloud2& cloud = part->cloud;
      Eigen::Isometry3d world_from_cloud;
      try {
        const auto t = tf_buffer_
                           ->lookupTransform(world_frame_, cloud.header.frame_id, ros::Time(0),
                                             ros::Duration(0.5))
                           .transform;
        world_from_cloud =
            Eigen::Translation3d(t.translation.x, t.translation.y, t.translation.z) *
            Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z);
      } catch (const tf2::TransformException& e) {
        NODELET_ERROR_THROTTLE(5.0,
                               "[%s] no transform %s -> %s (%s): left out of scan %u. Start the "
                               "drivers with their factory tf or the world_alignment_publisher",
                               pair_id.c_str(), world_frame_.c_str(), cloud.header.frame_id.c_str(),
                               e.what(), scan.scan_id);
        report->pairs_missing.push_back(pair_id);
        continue;
      }
      CloudView view = cloudView(cloud);
      view.world_from_cloud = world_from_cloud;
      views.push_back(view);
      report->pairs_present.push_back(pair_id);
      slowest_pair = std::max(slowest_pair, part->processing_seconds);
      stamp = std::max(stamp, part->header.stamp);
    }
    MergedCloud merged;
    {
      std::lock_guard<std::mutex> lock(merge_mutex_);  // publish() runs from two callbacks
      merged = merger_.merge(views, options_);
    }
    for (size_t count : merged.valid_per_part)
      report->points_per_pair.push_back(static_cast<uint32_t>(count));

    sensor_msgs::PointCloud2Ptr cloud(new sensor_msgs::PointCloud2);
    cloud->header.stamp = stamp.isZero() ? ros::Time::now() : stamp;
    cloud->header.frame_id = world_frame_;
    body_scan_driver::layoutFloatCloud(*cloud, static_cast<uint32_t>(merged.size()), 1,
                                       /*rgb=*/true);
    cloud->is_dense = true;
    std::memcpy(cloud->data.data(), merged.xyzrgb.data(), merged.xyzrgb.size() * sizeof(float));

    report->header = cloud->header;
    report->points_merged = cloud->width;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (groups_) {
        report->timing_groups = static_cast<uint32_t>(groups_->groups.size());
        report->simulated_capture_seconds = groups_->groups.size() * groups_->group_seconds;
      }
    }
    report->stage_names.push_back("decode+triangulate (slowest pair)");
    report->stage_seconds.push_back(slowest_pair);
    for (const auto& [name, seconds] : merged.stage_seconds) {
      report->stage_names.push_back(name);
      report->stage_seconds.push_back(seconds);
    }
    report->stage_names.push_back("merge total");
    report->stage_seconds.push_back((ros::WallTime::now() - start).toSec());
    std::sort(report->pairs_missing.begin(), report->pairs_missing.end());
    report->message = "scan " + std::to_string(scan.scan_id) + ": " +
                      std::to_string(report->points_merged) + " points from " +
                      std::to_string(report->pairs_present.size()) + "/" +
                      std::to_string(report->pairs_expected.size()) + " pairs";
    if (!report->pairs_missing.empty()) {
      report->message += "; missing:";
      for (const std::string& id : report->pairs_missing) report->message += " " + id;
    }
    if (report->walk_id != 0)
      report->message += " (walk " + std::to_string(report->walk_id) + " pose " +
                         std::to_string(report->pose_index) + ")";
    // The report first: a consumer of the cloud finds its ids in the report of the same stamp.
    report_pub_.publish(report);
    cloud_pub_.publish(cloud);
    if (report->pairs_missing.empty())
      NODELET_INFO("%s, merged in %.0f ms", report->message.c_str(),
                   1000 * report->stage_seconds.back());
    else
      NODELET_WARN("%s", report->message.c_str());
  }

  std::string world_frame_;
  body_scan_driver::ProblemThrottle throttle_;
  MergeOptions options_;
  std::mutex mutex_;
  std::unique_ptr<ScanAssembler<Part>> assembler_;
  std::mutex merge_mutex_;
  CloudMerger merger_;  // its buffers stay allocated from one scan to the next
  body_scan_msgs::TimingGroupsConstPtr groups_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Publisher cloud_pub_, report_pub_;
  std::vector<ros::Subscriber> subscribers_;
  ros::Subscriber groups_sub_;
  ros::ServiceServer inputs_srv_;
  ros::WallTimer timer_;
  std::shared_ptr<MasterWatch> master_watch_;
};

}  // namespace body_scan_merge

PLUGINLIB_EXPORT_CLASS(body_scan_merge::MergeNodelet, nodelet::Nodelet)
