// ScanCoordinator: /body_scan/capture (Scan.srv) triggers the rig's timing groups in turn
// (thesis 4.3, Fig 4.7): every pair of a group captures at once through its driver's ~capture
// (Capture.srv, active_pairs = the group), and the next group starts when all have answered or
// ~pair_timeout has passed; pairs that fail or never answer are named, never waited for forever.
// The groups come from the calibration files and the tf poses, else the files' alignment, else
// the ~rig_file poses (timing_groups.h), or ~groups. A pair whose calibration or pose is still
// missing after ~plan_wait gets a group of its own (it conflicts with nobody else's slot) and is
// named.
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/rig_layout.h>
#include <body_scan_merge/timing_groups.h>
#include <body_scan_msgs/Capture.h>
#include <body_scan_msgs/Scan.h>
#include <body_scan_msgs/TimingGroups.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <algorithm>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <pluginlib/class_list_macros.hpp>
#include <set>
#include <sstream>
#include <thread>

namespace body_scan_merge {

class ScanCoordinatorNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    if (!pnh.getParam("pairs", pairs_) || pairs_.empty()) {
      for (const char* pole : {"pole_a", "pole_b", "pole_c"})
        for (int i = 1; i <= 4; ++i)
          pairs_.push_back(std::string(pole) + "/pair_" + std::to_string(i));
    }
    calibration_dir_ = pnh.param<std::string>("calibration_dir", "");
    calibration_suffix_ = pnh.param<std::string>("calibration_suffix", "_factory");
    world_frame_ = pnh.param<std::string>("world_frame", "world");
    group_seconds_ = pnh.param("group_seconds", 0.5);
    pair_timeout_ = pnh.param("pair_timeout", 10.0);
    all_at_once_ = pnh.param("all_at_once", false);
    plan_wait_ = pnh.param("plan_wait", 30.0);
    rig_file_ = pnh.param<std::string>("rig_file", "");
    proxy_.spacing = pnh.param("proxy_spacing", proxy_.spacing);
    proxy_.image_margin = pnh.param("image_margin", proxy_.image_margin);
    proxy_.min_overlap_area = pnh.param("min_overlap_area", proxy_.min_overlap_area);
    proxy_.light_margin = pnh.param("light_margin", proxy_.light_margin);
    proxy_.floor_radius = pnh.param("floor_radius", proxy_.floor_radius);
    if (proxy_.spacing <= 0.001 || proxy_.spacing > 0.2) {
      NODELET_ERROR("~proxy_spacing %.4f m is out of range (0.001 .. 0.2); using 0.01",
                    proxy_.spacing);
      proxy_.spacing = 0.01;
    }
    std::vector<std::string> groups;
    if (pnh.getParam("groups", groups))
      for (const std::string& group : groups) {
        std::istringstream members(group);
        plan_.groups.emplace_back();
        for (std::string id; members >> id;) plan_.groups.back().push_back(id);
      }
    if (all_at_once_) plan_.groups = {pairs_};
    root_ = ros::names::parentNamespace(nh.getNamespace());
    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);
    groups_pub_ = nh.advertise<body_scan_msgs::TimingGroups>("timing_groups", 1, /*latch=*/true);
    capture_srv_ = nh.advertiseService("capture", &ScanCoordinatorNodelet::onScan, this);
    if (!plan_.groups.empty()) publishPlan("given");
    const double rate = pnh.param("rate", 0.0);
    if (rate > 0)
      scan_timer_ =
          nh.createWallTimer(ros::WallDuration(1.0 / rate), [this](const ros::WallTimerEvent&) {
            body_scan_msgs::Scan scan;
            onScan(scan.request, scan.response);
          });
    NODELET_INFO("coordinating %zu pairs; scans on %s%s", pairs_.size(),
                 capture_srv_.getService().c_str(),
                 rate > 0 ? (", every " + std::to_string(1.0 / rate) + " s").c_str() : "");
  }

  // The pose of a pair: tf (world -> <pair>_camera_optical_frame), else its calibration file's
  // world_alignment, else (only once ~plan_wait is over: drivers announce their pose as they
  // come up) the rig file's.
  std::optional<Eigen::Isometry3d> poseOf(const std::string& id,
                                          const body_scan_driver::PairCalibration& calibration,
                                          bool use_rig, std::string& why) {
    try {
      const geometry_msgs::TransformStamped t = tf_buffer_->lookupTransform(
          world_frame_, id + "_camera_optical_frame", ros::Time(0), ros::Duration(0.2));
      const auto& r = t.transform.rotation;
      const auto& p = t.transform.translation;
      return Eigen::Isometry3d(Eigen::Translation3d(p.x, p.y, p.z) *
                               Eigen::Quaterniond(r.w, r.x, r.y, r.z));
    } catch (const tf2::TransformException& e) {
      why = "no pose on tf (" + std::string(e.what()) + ")";
    }
    if (calibration.alignment) return calibration.alignment->world_from_camera;
    if (!rig_file_.empty() && use_rig) {
      try {
        if (!rig_) rig_ = body_scan_driver::loadRigLayout(rig_file_);
        return rig_->pair(id).world_from_camera;
      } catch (const std::exception& e) {
        why += "; ~rig_file: " + std::string(e.what());
      }
    }
    why +=
        ": start its driver (factory tf) or the world_alignment_publisher, set ~rig_file, "
        "or give ~groups";
    return std::nullopt;
  }

  // Plans the groups from the calibration files and the pairs' poses. Returns the pairs whose
  // geometry is missing, each with what is missing and how to provide it; with `partial`, they
  // get a group of their own each and the rest is planned.
  std::vector<std::string> planFromCalibration(bool partial) {
    std::vector<PairGeometry> geometry;
    std::vector<std::string> missing, problems;
    for (const std::string& id : pairs_) {
      std::string stem = id;
      std::replace(stem.begin(), stem.end(), '/', '_');
      const std::string path = calibration_dir_ + "/" + stem + calibration_suffix_ + ".yaml";
      PairGeometry pair;
      pair.pair_id = id;
      try {
        pair.calibration = body_scan_driver::loadCalibration(path);  // throws naming the file
      } catch (const std::exception& e) {
        missing.push_back(id);
        problems.push_back(id + ": " + e.what());
        continue;
      }
      std::string why;
      const auto pose = poseOf(id, pair.calibration, partial, why);
      if (!pose) {
        missing.push_back(id);
        problems.push_back(id + ": " + why);
        continue;
      }
      pair.world_from_camera = *pose;
      geometry.push_back(std::move(pair));
    }
    if (!missing.empty() && !partial) return problems;
    TimingPlan plan = planTimingGroups(geometry, proxy_);
    for (const std::string& id : missing) plan.groups.push_back({id});
    plan_ = std::move(plan);
    for (const std::string& problem : problems)
      NODELET_ERROR("timing groups: %s; planned alone", problem.c_str());
    publishPlan(missing.empty() ? "computed from the calibrated rig"
                                : "computed; " + std::to_string(missing.size()) +
                                      " pair(s) without geometry in groups of their own");
    return problems;
  }

  void publishPlan(const std::string& origin) {
    body_scan_msgs::TimingGroups message;
    message.header.stamp = ros::Time::now();
    message.header.frame_id = world_frame_;
    message.group_seconds = group_seconds_;
    std::string text;
    for (const auto& group : plan_.groups) {
      std::string line;
      for (const std::string& id : group) line += (line.empty() ? "" : " ") + id;
      message.groups.push_back(line);
      text += " {" + line + "}";
    }
    for (const auto& [a, b] : plan_.conflicts) message.conflicts.push_back(a + " " + b);
    groups_pub_.publish(message);
    NODELET_INFO("%zu timing groups (%s), simulated acquisition %.1f s:%s", plan_.groups.size(),
                 origin.c_str(), plan_.groups.size() * group_seconds_, text.c_str());
  }

  // Also run by the ~rate timer: no exception may escape into the nodelet manager.
  bool onScan(body_scan_msgs::Scan::Request& request, body_scan_msgs::Scan::Response& response) {
    try {
      return scan(request, response);
    } catch (const std::exception& e) {
      response.success = false;
      response.message = std::string("scan failed: ") + e.what();
      NODELET_ERROR("%s", response.message.c_str());
      return true;
    }
  }

  bool scan(body_scan_msgs::Scan::Request& request, body_scan_msgs::Scan::Response& response) {
    std::lock_guard<std::mutex> lock(scan_mutex_);  // one scan at a time
    // Drivers write their factory calibration and announce their pose as they come up: wait
    // up to ~plan_wait for the whole rig before giving up.
    for (const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(plan_wait_);
         plan_.groups.empty();) {
      const bool last_try = ros::WallTime::now() >= deadline || !ros::ok();
      try {
        if (!planFromCalibration(last_try).empty() && !last_try) ros::WallDuration(0.5).sleep();
      } catch (const std::exception& e) {  // e.g. a calibration file with no usable planes
        response.success = false;
        response.message = std::string("cannot plan the timing groups: ") + e.what();
        NODELET_ERROR("%s", response.message.c_str());
        return true;
      }
    }
    next_scan_id_ = request.scan_id != 0 ? request.scan_id : next_scan_id_ + 1;
    response.scan_id = next_scan_id_;
    const ros::WallTime start = ros::WallTime::now();
    for (const auto& group : plan_.groups) {
      std::string line;
      for (const std::string& id : group) line += (line.empty() ? "" : " ") + id;
      response.groups.push_back(line);
      captureGroup(group, response.scan_id, response.pairs_missing);
    }
    std::sort(response.pairs_missing.begin(), response.pairs_missing.end());
    response.simulated_capture_seconds = plan_.groups.size() * group_seconds_;
    response.success = response.pairs_missing.empty();
    std::ostringstream message;
    message << "scan " << response.scan_id << ": " << plan_.groups.size() << " groups, "
            << pairs_.size() - response.pairs_missing.size() << "/" << pairs_.size()
            << " pairs captured in " << (ros::WallTime::now() - start).toSec() << " s wall";
    for (const std::string& id : response.pairs_missing) message << "; missing " << id;
    response.message = message.str();
    if (response.success)
      NODELET_INFO("%s", response.message.c_str());
    else
      NODELET_WARN("%s", response.message.c_str());
    return true;
  }

  // Triggers every pair of the group at once and waits for all (at most pair_timeout).
  void captureGroup(const std::vector<std::string>& group, uint32_t scan_id,
                    std::vector<std::string>& missing) {
    struct Call {
      std::mutex mutex;
      std::condition_variable done;
      size_t pending = 0;
      std::set<std::string> answered, failed;
    };
    auto call = std::make_shared<Call>();
    call->pending = group.size();
    for (const std::string& id : group) {
      // Detached: a pair that never answers must not block the scan; it reports on its own.
      std::thread([this, call, id, group, scan_id] {
        body_scan_msgs::Capture capture;
        capture.request.scan_id = scan_id;
        for (const std::string& other : group)
          if (other != id) capture.request.active_pairs.push_back(other);
        const std::string service = ros::names::append(root_, id + "/driver/capture");
        std::string error;
        // A driver may still be coming up: wait for its service as long as for its answer.
        if (!ros::service::waitForService(service, ros::Duration(pair_timeout_)))
          error = service + " is not advertised (is the pair's driver running?)";
        else if (!ros::service::call(service, capture))
          error = service + " call failed";
        else if (!capture.response.success)
          error = capture.response.message;
        std::lock_guard<std::mutex> lock(call->mutex);
        call->answered.insert(id);
        if (!error.empty()) {
          call->failed.insert(id);
          NODELET_ERROR("[%s] scan %u: %s", id.c_str(), scan_id, error.c_str());
        }
        --call->pending;
        call->done.notify_all();
      }).detach();
    }
    std::unique_lock<std::mutex> lock(call->mutex);
    if (!call->done.wait_for(lock, std::chrono::duration<double>(pair_timeout_),
                             [&] { return call->pending == 0; }))
      NODELET_ERROR("scan %u: %zu pair(s) of a group did not answer within %.1f s", scan_id,
                    call->pending, pair_timeout_);
    for (const std::string& id : group)
      if (!call->answered.count(id) || call->failed.count(id)) missing.push_back(id);
  }

  std::vector<std::string> pairs_;
  std::string calibration_dir_, calibration_suffix_, world_frame_, root_;
  double group_seconds_ = 0.5, pair_timeout_ = 10.0, plan_wait_ = 30.0;
  bool all_at_once_ = false;
  std::string rig_file_;
  std::optional<body_scan_driver::RigLayout> rig_;
  InterferenceProxy proxy_;
  TimingPlan plan_;
  uint32_t next_scan_id_ = 0;
  std::mutex scan_mutex_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Publisher groups_pub_;
  ros::ServiceServer capture_srv_;
  ros::WallTimer scan_timer_;
};

}  // namespace body_scan_merge

PLUGINLIB_EXPORT_CLASS(body_scan_merge::ScanCoordinatorNodelet, nodelet::Nodelet)
