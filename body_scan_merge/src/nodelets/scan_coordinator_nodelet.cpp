// ScanCoordinator: /body_scan/capture (Scan.srv) triggers the rig's timing groups in turn
// (thesis 4.3, Fig 4.7): every pair of a group captures at once through its driver's ~capture
// (Capture.srv, active_pairs = the group), and the next group starts when all have answered or
// ~pair_timeout has passed; pairs that fail or never answer are named, never waited for forever.
// The groups come from the calibration files and the tf poses, else the files' alignment, else
// the ~rig_file poses (timing_groups.h), or ~groups. A pair whose calibration or pose is still
// missing after ~plan_wait gets a group of its own (it conflicts with nobody else's slot) and is
// named.
// Before each scan it asks the Merge named by ~merge (its ~inputs_connected service) whether every
// pair's cloud topic is connected, and waits for that up to ~inputs_timeout: a cloud published
// before Merge has connected is lost, which happens to the first scan after a launch.
//
// Walk sessions: /body_scan/capture_walk (CaptureWalk.srv) scans the 4 representative poses of
// thesis 5.3 in turn. Before each pose it prompts the operator on /body_scan/walk_progress
// (latched WalkProgress: prompt, scanning, scanned, done or failed) and waits ~walk_pause
// seconds, or, when the request asks for a trigger, for std_msgs/Empty on /body_scan/walk_trigger
// (at most ~walk_trigger_timeout). Every pair's capture is stamped with the walk id and the pose
// index (Capture.srv), which travel with the pattern sets to the scan report and the models.
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/rig_layout.h>
#include <body_scan_merge/timing_groups.h>
#include <body_scan_msgs/Capture.h>
#include <body_scan_msgs/CaptureWalk.h>
#include <body_scan_msgs/Scan.h>
#include <body_scan_msgs/TimingGroups.h>
#include <body_scan_msgs/WalkProgress.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <std_msgs/Empty.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <pluginlib/class_list_macros.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "master_watch.h"

namespace body_scan_merge {

namespace {

// ~group_seconds when given, else the pairs' pattern frames at the camera's frame rate
// (GroupTiming; the defaults give the thesis's 0.5 s).
double groupSeconds(ros::NodeHandle& pnh) {
  double seconds = 0;
  if (pnh.getParam("group_seconds", seconds)) {
    if (std::isfinite(seconds) && seconds > 0) return seconds;
    ROS_ERROR("~group_seconds %.3f must be positive; timing it from the pattern instead", seconds);
  }
  GroupTiming timing;
  const int bits = pnh.param("pattern_bits", 8);
  const bool inverse = pnh.param("inverse_frames", true);
  timing.camera_fps = pnh.param("camera_fps", timing.camera_fps);
  timing.settle_frames = pnh.param("settle_frames", timing.settle_frames);
  try {
    timing.pattern_frames = body_scan_driver::PatternLayout(bits, inverse).frameCount();
    return timing.seconds();
  } catch (const std::exception& e) {
    ROS_ERROR("timing group period: %s; using the thesis's 0.5 s", e.what());
    return 0.5;
  }
}

}  // namespace

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
    group_seconds_ = groupSeconds(pnh);
    pair_timeout_ = pnh.param("pair_timeout", 10.0);
    all_at_once_ = pnh.param("all_at_once", false);
    plan_wait_ = pnh.param("plan_wait", 30.0);
    rig_file_ = pnh.param<std::string>("rig_file", "");
    merge_ = pnh.param<std::string>("merge", "");
    inputs_timeout_ = pnh.param("inputs_timeout", 10.0);
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
    walk_pause_ = pnh.param("walk_pause", 3.0);
    walk_trigger_timeout_ = pnh.param("walk_trigger_timeout", 120.0);
    std::vector<std::string> prompts;
    if (pnh.getParam("walk_prompts", prompts)) {
      if (prompts.size() == walk_prompts_.size())
        std::copy(prompts.begin(), prompts.end(), walk_prompts_.begin());
      else
        NODELET_ERROR("~walk_prompts needs %zu entries (one per pose), got %zu: using the default",
                      walk_prompts_.size(), prompts.size());
    }
    // The walk service blocks for the whole walk while the trigger must still arrive: both on the
    // multi-threaded queue.
    ros::NodeHandle& mt = getMTNodeHandle();
    progress_pub_ = mt.advertise<body_scan_msgs::WalkProgress>("walk_progress", 4, /*latch=*/true);
    trigger_sub_ =
        mt.subscribe<std_msgs::Empty>("walk_trigger", 4, [this](const std_msgs::EmptyConstPtr&) {
          std::lock_guard<std::mutex> lock(trigger_mutex_);
          ++triggers_;
          trigger_.notify_all();
        });
    walk_srv_ = mt.advertiseService("capture_walk", &ScanCoordinatorNodelet::onCaptureWalk, this);
    master_watch_ = MasterWatch::acquire();  // registers again with a restarted master
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
      scan(request.scan_id, 0, 0, response);
    } catch (const std::exception& e) {
      response.success = false;
      response.message = std::string("scan failed: ") + e.what();
      NODELET_ERROR("%s", response.message.c_str());
    }
    return true;
  }

  bool onCaptureWalk(body_scan_msgs::CaptureWalk::Request& request,
                     body_scan_msgs::CaptureWalk::Response& response) {
    try {
      captureWalk(request, response);
    } catch (const std::exception& e) {
      response.success = false;
      response.message = std::string("walk capture failed: ") + e.what();
      NODELET_ERROR("%s", response.message.c_str());
    }
    return true;
  }

  void captureWalk(const body_scan_msgs::CaptureWalk::Request& request,
                   body_scan_msgs::CaptureWalk::Response& response) {
    std::lock_guard<std::mutex> walk_lock(walk_mutex_);  // one walk at a time
    response.walk_id = next_walk_id_ = request.walk_id != 0 ? request.walk_id : next_walk_id_ + 1;
    const double pause = request.pause >= 0 ? request.pause : walk_pause_;
    body_scan_msgs::WalkProgress progress;
    progress.walk_id = response.walk_id;
    progress.poses = static_cast<uint8_t>(walk_prompts_.size());
    const auto report = [&](uint8_t state, const std::string& prompt) {
      progress.header.stamp = ros::Time::now();
      progress.state = state;
      progress.prompt = prompt;
      progress_pub_.publish(progress);
      NODELET_INFO("walk %u: %s", progress.walk_id, prompt.c_str());
    };
    std::set<std::string> missing;
    for (uint8_t pose = 1; pose <= progress.poses; ++pose) {
      progress.pose_index = pose;
      progress.scan_id = 0;
      progress.waiting_for_trigger = request.trigger;
      const std::string step =
          "pose " + std::to_string(pose) + " of " + std::to_string(progress.poses);
      uint64_t triggers_before;
      {
        std::lock_guard<std::mutex> lock(trigger_mutex_);
        triggers_before = triggers_;
      }
      char when[64];
      std::snprintf(when, sizeof when, " (scan in %.1f s)", pause);
      report(body_scan_msgs::WalkProgress::PROMPT,
             step + ": " + walk_prompts_[pose - 1] +
                 (request.trigger ? std::string(" (then trigger the scan)") : when));
      progress.waiting_for_trigger = false;
      if (request.trigger) {
        std::unique_lock<std::mutex> lock(trigger_mutex_);
        if (!trigger_.wait_for(lock, std::chrono::duration<double>(walk_trigger_timeout_),
                               [&] { return triggers_ > triggers_before || !ros::ok(); }) ||
            !ros::ok()) {
          lock.unlock();
          response.message = "walk " + std::to_string(response.walk_id) +
                             " abandoned: no trigger " + "on " + trigger_sub_.getTopic() +
                             " within ~walk_trigger_timeout (" +
                             std::to_string(walk_trigger_timeout_) + " s) for " + step +
                             "; publish std_msgs/Empty there when the subject is in pose";
          report(body_scan_msgs::WalkProgress::FAILED, response.message);
          return;
        }
      } else if (pause > 0) {
        ros::WallDuration(pause).sleep();
      }
      body_scan_msgs::Scan::Response scanned;
      report(body_scan_msgs::WalkProgress::SCANNING, step + ": scanning");
      scan(0, response.walk_id, pose, scanned);
      progress.scan_id = scanned.scan_id;
      response.scan_ids.push_back(scanned.scan_id);
      missing.insert(scanned.pairs_missing.begin(), scanned.pairs_missing.end());
      if (scanned.groups.empty()) {  // no plan: nothing was captured
        response.message = "walk " + std::to_string(response.walk_id) + " abandoned at " + step +
                           ": " + scanned.message;
        report(body_scan_msgs::WalkProgress::FAILED, response.message);
        return;
      }
      report(body_scan_msgs::WalkProgress::SCANNED, step + ": " + scanned.message);
    }
    response.pairs_missing.assign(missing.begin(), missing.end());
    response.success = missing.empty();
    response.message = "walk " + std::to_string(response.walk_id) + ": " +
                       std::to_string(response.scan_ids.size()) + " poses scanned";
    for (const std::string& id : response.pairs_missing) response.message += "; missing " + id;
    progress.scan_id = 0;
    report(body_scan_msgs::WalkProgress::DONE, response.message);
  }

  // One whole-body scan (walk_id, pose_index: its walk session, 0 for none).
  void scan(uint32_t scan_id, uint32_t walk_id, uint8_t pose_index,
            body_scan_msgs::Scan::Response& response) {
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
        return;
      }
    }
    waitForMergeInputs();
    next_scan_id_ = scan_id != 0 ? scan_id : next_scan_id_ + 1;
    response.scan_id = next_scan_id_;
    const ros::WallTime start = ros::WallTime::now();
    for (const auto& group : plan_.groups) {
      std::string line;
      for (const std::string& id : group) line += (line.empty() ? "" : " ") + id;
      response.groups.push_back(line);
      captureGroup(group, response.scan_id, walk_id, pose_index, response.pairs_missing);
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
  }

  // Returns once the Merge hears every pair, or after ~inputs_timeout with a warning naming the
  // topics it does not hear (their clouds will be missing from the scan).
  void waitForMergeInputs() {
    if (merge_.empty()) return;
    const std::string service = getNodeHandle().resolveName(merge_ + "/inputs_connected");
    std_srvs::Trigger check;
    const ros::WallTime start = ros::WallTime::now();
    for (const ros::WallTime deadline = start + ros::WallDuration(inputs_timeout_);;
         ros::WallDuration(0.05).sleep()) {
      if (callPersistent(service, check) && check.response.success) {
        const double waited = (ros::WallTime::now() - start).toSec();
        if (waited > 0.01)
          NODELET_INFO("the merge heard every running pair after %.2f s: %s", waited,
                       check.response.message.c_str());
        return;
      }
      if (ros::WallTime::now() >= deadline || !ros::ok()) break;
    }
    NODELET_WARN("scanning although the merge is not ready after ~inputs_timeout (%.1f s): %s",
                 inputs_timeout_,
                 check.response.message.empty()
                     ? (service + " does not answer (is the merge running? set ~merge to \"\" "
                                  "when there is none)")
                           .c_str()
                     : check.response.message.c_str());
  }

  // Triggers every pair of the group at once and waits for all (at most pair_timeout).
  void captureGroup(const std::vector<std::string>& group, uint32_t scan_id, uint32_t walk_id,
                    uint8_t pose_index, std::vector<std::string>& missing) {
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
      std::thread([this, call, id, group, scan_id, walk_id, pose_index] {
        body_scan_msgs::Capture capture;
        capture.request.scan_id = scan_id;
        capture.request.walk_id = walk_id;
        capture.request.pose_index = pose_index;
        for (const std::string& other : group)
          if (other != id) capture.request.active_pairs.push_back(other);
        const std::string service = ros::names::append(root_, id + "/driver/capture");
        std::string error;
        // A driver may still be coming up: wait for its service as long as for its answer.
        if (!persistentClient<body_scan_msgs::Capture>(service).isValid() &&
            !ros::service::waitForService(service, ros::Duration(pair_timeout_)))
          error = service + " is not advertised (is the pair's driver running?)";
        else if (!callPersistent(service, capture))
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

  // A persistent connection per service: captures need no master once connected (a restarted
  // master knows no services until they register again); a dropped one is made again.
  template <class Service>
  ros::ServiceClient persistentClient(const std::string& service) {
    std::lock_guard<std::mutex> lock(clients_mutex_);
    ros::ServiceClient& client = clients_[service];
    if (!client.isValid())
      client = getNodeHandle().serviceClient<Service>(service, /*persistent=*/true);
    return client;
  }

  // Calls `service` on its persistent connection. A failed call forgets the connection, so the
  // next call makes a new one: roscpp never marks a link invalid when its connection drops while
  // the link is being made (its server killed at that moment), and every call on it would fail.
  template <class Service>
  bool callPersistent(const std::string& service, Service& call) {
    ros::ServiceClient client = persistentClient<Service>(service);
    if (client.call(call)) return true;
    if (client.isValid())
      NODELET_WARN(
          "%s: the call failed on a connection that still looks open; the next call "
          "makes a new one",
          service.c_str());
    std::lock_guard<std::mutex> lock(clients_mutex_);
    const auto stored = clients_.find(service);
    if (stored != clients_.end() && stored->second == client) clients_.erase(stored);
    return false;
  }

  std::vector<std::string> pairs_;
  std::map<std::string, ros::ServiceClient> clients_;
  std::mutex clients_mutex_;
  std::string calibration_dir_, calibration_suffix_, world_frame_, root_;
  double group_seconds_ = 0.5, pair_timeout_ = 10.0, plan_wait_ = 30.0;
  bool all_at_once_ = false;
  std::string rig_file_, merge_;
  double inputs_timeout_ = 10.0;
  std::optional<body_scan_driver::RigLayout> rig_;
  InterferenceProxy proxy_;
  TimingPlan plan_;
  uint32_t next_scan_id_ = 0;
  std::mutex scan_mutex_;
  // Walk sessions
  double walk_pause_ = 3.0, walk_trigger_timeout_ = 120.0;
  std::array<std::string, 4> walk_prompts_{
      "right heel strike: right leg and left arm forward, longest stride",
      "right mid-stance: weight on the right leg, left leg swinging past it",
      "left heel strike: left leg and right arm forward, longest stride",
      "left mid-stance: weight on the left leg, right leg swinging past it"};
  uint32_t next_walk_id_ = 0;
  std::mutex walk_mutex_, trigger_mutex_;
  std::condition_variable trigger_;
  uint64_t triggers_ = 0;
  ros::Publisher progress_pub_;
  ros::Subscriber trigger_sub_;
  ros::ServiceServer walk_srv_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Publisher groups_pub_;
  ros::ServiceServer capture_srv_;
  ros::WallTimer scan_timer_;
  std::shared_ptr<MasterWatch> master_watch_;
};

}  // namespace body_scan_merge

PLUGINLIB_EXPORT_CLASS(body_scan_merge::ScanCoordinatorNodelet, nodelet::Nodelet)
