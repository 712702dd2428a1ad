// BodyFitter: /body_scan/cloud (PointCloud2, world) -> /body_gait/model (BodyModel),
// /body_gait/markers (MarkerArray), /body_gait/joint_states, TF of the model's links and the
// URDF on robot_description (thesis 5.5). The fit is body_gait_model::fitBody; this is the ROS
// wrapper. robot_state_publisher is not installed here, so the nodelet publishes the links' TF
// itself (modelTransforms: the same frames robot_state_publisher would derive from joint_states).
//
// Walk sessions: a cloud's scan id, walk id and pose index are in its ScanReport
// (/body_scan/scan_report, same header stamp). While a report publisher is connected, a cloud
// waits up to ~report_wait for its report. A single scan is fitted at once; a walk's 4 clouds
// are collected and fitted together (fitWalk: one body for the walk), then its 4 models and its
// gait cycle
// (/body_gait/gait_sequence, eqs 5.11-5.13) are published.
#include <body_gait_model/body_fitter.h>
#include <body_gait_model/fit_options_file.h>
#include <body_gait_model/gait_cycle.h>
#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/ros/gait_sequence_msg.h>
#include <body_gait_model/urdf.h>
#include <body_gait_model/walk_collector.h>
#include <body_scan_msgs/GaitSequence.h>
#include <body_scan_msgs/ScanReport.h>
#include <malloc.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <pluginlib/class_list_macros.hpp>

namespace body_gait_model {

namespace {

// The scan a cloud belongs to (from its ScanReport); all 0 when unknown.
struct ScanIds {
  uint32_t scan_id = 0, walk_id = 0;
  uint8_t pose_index = 0;
};

struct TimedFit {
  BodyFit fit;
  double seconds = 0;
};

TimedFit fitScan(const Cloud& cloud, const FitOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  BodyFit fit = fitBody(cloud, options);
  return {std::move(fit),
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()};
}

// The fits of a walk's 4 clouds (poses s1..s4), fitted together (the walk-level fit: one body
// for the walk, body_fitter.h); each scan is charged an equal share of the time.
std::vector<TimedFit> fitWalkScans(const std::vector<Cloud>& clouds, const FitOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  WalkFit walk = fitWalk(clouds, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() /
      static_cast<double>(clouds.size());
  std::vector<TimedFit> fits;
  for (BodyFit& scan : walk.scans) fits.push_back({std::move(scan), seconds});
  return fits;
}

}  // namespace

class BodyFitterNodelet : public nodelet::Nodelet {
 private:
  using CloudPtr = sensor_msgs::PointCloud2::ConstPtr;

  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    world_frame_ = pnh.param<std::string>("world_frame", "world");
    link_prefix_ = pnh.param<std::string>("link_prefix", "body_gait/");
    report_wait_ = pnh.param("report_wait", 5.0);
    const std::string options_file = pnh.param<std::string>("options_file", "");
    if (options_file.empty()) {
      NODELET_WARN("~options_file is not set: fitting with the default FitOptions");
    } else {
      try {
        options_ = loadFitOptions(options_file);
      } catch (const std::exception& e) {
        NODELET_ERROR("%s; fitting with the default FitOptions", e.what());
      }
    }
    model_pub_ = nh.advertise<body_scan_msgs::BodyModel>("body_gait/model", 4, true);
    marker_pub_ = nh.advertise<visualization_msgs::MarkerArray>("body_gait/markers", 2, true);
    joint_pub_ = nh.advertise<sensor_msgs::JointState>("body_gait/joint_states", 2, true);
    sequence_pub_ =
        nh.advertise<body_scan_msgs::GaitSequence>("body_gait/gait_sequence", 1, /*latch=*/true);
    tf_ = std::make_unique<tf2_ros::TransformBroadcaster>();
    // A fit takes ~0.5-1 s; a walk's 4 clouds may come in quick succession.
    cloud_sub_ = nh.subscribe("body_scan/cloud", 4, &BodyFitterNodelet::onCloud, this);
    report_sub_ = nh.subscribe("body_scan/scan_report", 16, &BodyFitterNodelet::onReport, this);
    timer_ = nh.createWallTimer(ros::WallDuration(0.5),
                                [this](const ros::WallTimerEvent&) { fitOverdueClouds(); });
  }

  void onReport(const body_scan_msgs::ScanReport::ConstPtr& report) {
    CloudPtr waiting;
    ScanIds ids{report->scan_id, report->walk_id, report->pose_index};
    {
      std::lock_guard<std::mutex> lock(mutex_);
      reports_[report->header.stamp] = ids;
      while (reports_.size() > 32) reports_.erase(reports_.begin());
      const auto pending = pending_.find(report->header.stamp);
      if (pending == pending_.end()) return;
      waiting = pending->second.cloud;
      pending_.erase(pending);
    }
    handle(waiting, ids);
  }

  void onCloud(const CloudPtr& msg) {
    if (msg->header.frame_id != world_frame_) {
      NODELET_ERROR_THROTTLE(5.0,
                             "cloud in frame '%s' not fitted: the body fitter needs clouds in "
                             "'%s' (floor, z up); publish the merged world cloud",
                             msg->header.frame_id.c_str(), world_frame_.c_str());
      return;
    }
    ScanIds ids;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto report = reports_.find(msg->header.stamp);
      if (report != reports_.end()) {
        ids = report->second;
      } else if (report_sub_.getNumPublishers() > 0) {
        pending_[msg->header.stamp] = {msg, ros::WallTime::now()};
        return;  // onReport or fitOverdueClouds goes on
      }
    }
    handle(msg, ids);
  }

  void fitOverdueClouds() {
    std::vector<CloudPtr> overdue;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const ros::WallTime now = ros::WallTime::now();
      for (auto it = pending_.begin(); it != pending_.end();)
        if ((now - it->second.arrival).toSec() > report_wait_) {
          overdue.push_back(it->second.cloud);
          it = pending_.erase(it);
        } else {
          ++it;
        }
    }
    for (const CloudPtr& cloud : overdue) {
      NODELET_WARN(
          "no scan report with the cloud's stamp within ~report_wait %.1f s: fitted as "
          "a single scan",
          report_wait_);
      handle(cloud, {});
    }
  }

  void handle(const CloudPtr& msg, const ScanIds& ids) {
    if (ids.walk_id == 0) {
      fitAndPublish({msg}, {ids});
      return;
    }
    std::optional<WalkCollector<std::pair<CloudPtr, ScanIds>>::Walk> walk;
    try {
      std::lock_guard<std::mutex> lock(mutex_);
      walk = walks_.add(ids.walk_id, ids.pose_index, {msg, ids});
      for (uint32_t dropped : walks_.takeDropped())
        NODELET_WARN("walk %u dropped before all %d poses arrived (a newer walk started)", dropped,
                     kWalkPoses);
      if (!walk)
        NODELET_INFO("walk %u: pose %u of %d received", ids.walk_id, ids.pose_index, kWalkPoses);
    } catch (const std::invalid_argument& e) {
      NODELET_ERROR("scan %u not fitted: %s", ids.scan_id, e.what());
      return;
    }
    if (!walk) return;
    std::vector<CloudPtr> clouds;
    std::vector<ScanIds> walk_ids;
    for (const auto& [cloud, pose_ids] : *walk) {
      clouds.push_back(cloud);
      walk_ids.push_back(pose_ids);
    }
    fitAndPublish(clouds, walk_ids);
  }

  // Fits one scan, or a walk's 4 (poses in order), and publishes the models (a walk's also as a
  // gait cycle).
  void fitAndPublish(const std::vector<CloudPtr>& msgs, const std::vector<ScanIds>& ids) {
    std::lock_guard<std::mutex> lock(fit_mutex_);  // one fit at a time
    try {
      std::vector<Cloud> clouds;
      for (const CloudPtr& msg : msgs) {
        clouds.push_back(cloudFromMsg(*msg));
        if (clouds.back().empty())
          throw std::invalid_argument("the cloud of scan " + std::to_string(ids[0].scan_id) +
                                      " has no finite points: nothing to fit; check the scan");
      }
      const std::vector<TimedFit> fits = msgs.size() == 1
                                             ? std::vector<TimedFit>{fitScan(clouds[0], options_)}
                                             : fitWalkScans(clouds, options_);
      for (std::size_t i = 0; i < fits.size(); ++i) publish(fits[i], *msgs[i], ids[i], clouds[i]);
      if (fits.size() == static_cast<std::size_t>(kWalkPoses))
        publishCycle(fits, *msgs.back(), ids[0]);
    } catch (const std::exception& e) {  // cloudFromMsg names the bad field
      NODELET_ERROR_THROTTLE(
          5.0, "%s not fitted: %s",
          ids[0].walk_id ? ("walk " + std::to_string(ids[0].walk_id)).c_str() : "cloud", e.what());
    } catch (...) {  // nothing may escape into the nodelet manager
      NODELET_ERROR_THROTTLE(5.0, "%s not fitted: unknown error",
                             ids[0].walk_id ? "walk" : "cloud");
    }
    // A fit's temporaries (tens of MB), once freed, stay with glibc's per-thread arenas (soak:
    // RSS +28 % over 300 scans with 2.5 MB in use); hand them back to the system.
    malloc_trim(0);
  }

  void publish(const TimedFit& timed, const sensor_msgs::PointCloud2& msg, const ScanIds& ids,
               const Cloud& cloud) {
    const BodyFit& fit = timed.fit;
    const std_msgs::Header& header = msg.header;
    body_scan_msgs::BodyModel model = toMsg(fit, header, timed.seconds);
    model.scan_id = ids.scan_id;
    model.walk_id = ids.walk_id;
    model.pose_index = ids.pose_index;
    model_pub_.publish(model);
    marker_pub_.publish(modelMarkers(fit.model, fit.quality.low_quality, header));
    joint_pub_.publish(jointStates(fit.model, header));
    tf_->sendTransform(modelTransforms(fit.model, header, link_prefix_));
    getNodeHandle().setParam("robot_description", modelUrdf(fit.model, "body_gait", link_prefix_));
    const std::string what = ids.walk_id ? "walk " + std::to_string(ids.walk_id) + " pose " +
                                               std::to_string(ids.pose_index) + ": "
                                         : std::string();
    if (fit.quality.low_quality)
      NODELET_WARN("%s%zu points fitted in %.0f ms: LOW QUALITY (%s)", what.c_str(), cloud.size(),
                   1000 * timed.seconds, fit.quality.reason.c_str());
    else
      NODELET_INFO("%s%zu points fitted in %.0f ms: RMS %.1f mm, %.0f %% explained", what.c_str(),
                   cloud.size(), 1000 * timed.seconds, 1000 * fit.quality.rms_distance,
                   100 * fit.quality.explained_fraction);
  }

  void publishCycle(const std::vector<TimedFit>& fits, const sensor_msgs::PointCloud2& last,
                    const ScanIds& ids) {
    RepresentativePoses poses;
    for (int k = 0; k < kWalkPoses; ++k) poses[k] = fits[k].fit.model;
    try {
      body_scan_msgs::GaitSequence sequence = toMsg(reconstructGaitCycle(poses), last.header);
      sequence.walk_id = ids.walk_id;
      sequence_pub_.publish(sequence);
      NODELET_INFO("walk %u: gait cycle of %zu frames published", ids.walk_id,
                   sequence.frames.size());
    } catch (const std::exception& e) {
      NODELET_WARN("walk %u: no gait cycle: %s", ids.walk_id, e.what());
    }
  }

  std::string world_frame_, link_prefix_;
  double report_wait_ = 5.0;
  FitOptions options_;
  std::mutex mutex_;  // reports_, pending_, walks_
  struct Pending {
    CloudPtr cloud;
    ros::WallTime arrival;
  };
  std::map<ros::Time, ScanIds> reports_;  // the latest reports by stamp
  std::map<ros::Time, Pending> pending_;  // clouds waiting for their report
  WalkCollector<std::pair<CloudPtr, ScanIds>> walks_;
  std::mutex fit_mutex_;
  ros::Publisher model_pub_, marker_pub_, joint_pub_, sequence_pub_;
  ros::Subscriber cloud_sub_, report_sub_;
  ros::WallTimer timer_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_;
};

}  // namespace body_gait_model

PLUGINLIB_EXPORT_CLASS(body_gait_model::BodyFitterNodelet, nodelet::Nodelet)
