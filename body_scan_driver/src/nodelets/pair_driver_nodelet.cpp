// PairDriver: captures pattern sets from one pair and publishes them (DESIGN.md section 3).
// The pair comes from the backend plugin named by ~backend (pair_backends.xml: sim, the
// virtual pair; usb, a real pair); device health goes to /diagnostics for every backend.
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/pair_device.h>
#include <body_scan_driver/ros/conversions.h>
#include <body_scan_driver/ros/pair_backend.h>
#include <body_scan_driver/simulator_control.h>
#include <body_scan_msgs/Capture.h>
#include <body_scan_msgs/PatternSet.h>
#include <body_scan_msgs/SetScene.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/TransformStamped.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/UInt32.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <atomic>
#include <mutex>
#include <pluginlib/class_list_macros.hpp>
#include <pluginlib/class_loader.hpp>

namespace body_scan_driver {

class PairDriverNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    const std::string backend = pnh.param<std::string>("backend", "sim");
    pair_id_ = pnh.param<std::string>("pair_id", "pole_a/pair_1");
    frame_id_ = pnh.param<std::string>("frame_id", pair_id_ + "_camera_optical_frame");
    world_frame_ = pnh.param<std::string>("world_frame", "world");
    const double rate = pnh.param("rate", 0.0);

    // The device is assigned before any callback can run (services, trigger, diagnostics):
    // ROS serves callbacks as soon as they are advertised, and device_ is read without a lock.
    try {
      device_ = openDevice(backend, nh, pnh);
      simulator_ = dynamic_cast<SimulatorControl*>(device_.get());
    } catch (const std::exception& e) {
      // Stay alive so the other pairs in this manager keep working; captures report the error.
      device_error_ = e.what();
      NODELET_ERROR("[%s] cannot open the pair: %s", pair_id_.c_str(), e.what());
    }

    pattern_pub_ = nh.advertise<body_scan_msgs::PatternSet>("pattern_set", 2);
    image_pub_ = nh.advertise<sensor_msgs::Image>("image_raw", 2);
    info_pub_ = nh.advertise<sensor_msgs::CameraInfo>("camera_info", 2);
    capture_srv_ = pnh.advertiseService("capture", &PairDriverNodelet::onCapture, this);
    trigger_sub_ = nh.subscribe("scan_trigger", 4, &PairDriverNodelet::onTrigger, this);
    // Simulator only: replace the scene (e.g. to place a calibration target); a bad scene or a
    // real pair is an error reply and the current scene stays.
    set_scene_srv_ =
        pnh.advertiseService<body_scan_msgs::SetScene::Request, body_scan_msgs::SetScene::Response>(
            "set_scene", [this](auto& request, auto& response) {
              std::lock_guard<std::mutex> lock(capture_mutex_);
              response.success = false;
              try {
                if (!device_) throw std::runtime_error("pair not available: " + device_error_);
                if (!simulator_)
                  throw std::runtime_error(
                      "this pair captures the real world: its scene cannot be set; place the "
                      "target by hand (or use backend:=sim)");
                simulator_->replaceScene(request.scene_yaml);
                response.success = true;
                response.message = "scene replaced";
              } catch (const std::exception& e) {
                response.message = std::string("set_scene failed: ") + e.what();
                NODELET_ERROR("[%s] %s", pair_id_.c_str(), response.message.c_str());
              }
              return true;
            });

    diagnostics_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
    diagnostics_->setHardwareID("none");
    diagnostics_->add("pair " + pair_id_, this, &PairDriverNodelet::diagnose);
    diagnostics_timer_ = nh.createWallTimer(
        ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) { diagnostics_->update(); });

    if (!device_) return;  // stays alive; captures and set_scene answer with device_error_
    if (simulator_)
      publishFactoryData(pnh.param<std::string>("factory_calibration_file", ""),
                         pnh.param("publish_factory_tf", true));
    if (rate > 0)
      timer_ = nh.createTimer(ros::Duration(1.0 / rate), [this](const ros::TimerEvent&) {
        std::string message;
        captureAndPublish(0, message);
      });
    NODELET_INFO("[%s] %s pair ready: %d bits%s, %s", pair_id_.c_str(), backend.c_str(),
                 device_->layout().bits(), device_->layout().inverseFrames() ? " + inverses" : "",
                 rate > 0 ? ("capturing at " + std::to_string(rate) + " Hz").c_str()
                          : "capturing on ~capture or scan_trigger");
  }

  // The pair from the backend plugin `backend`: a short name (sim, usb) or a plugin name of
  // pair_backends.xml. Throws naming the backends there are when it cannot be loaded.
  std::unique_ptr<PairDevice> openDevice(const std::string& backend, ros::NodeHandle& nh,
                                         ros::NodeHandle& pnh) {
    backend_loader_ = std::make_unique<pluginlib::ClassLoader<PairBackend>>(
        "body_scan_driver", "body_scan_driver::PairBackend");
    const std::string plugin =
        backend.find('/') == std::string::npos ? "body_scan_driver/" + backend : backend;
    std::string available;
    for (const std::string& name : backend_loader_->getDeclaredClasses()) {
      const bool ours = name.rfind("body_scan_driver/", 0) == 0;
      available += (available.empty() ? "" : ", ") + (ours ? name.substr(17) : name);
    }
    if (!backend_loader_->isClassAvailable(plugin))
      throw std::runtime_error("backend '" + backend + "' is unknown; available backends: " +
                               available + " (set ~backend, e.g. backend:=usb)");
    try {
      backend_ = backend_loader_->createUniqueInstance(plugin);
    } catch (const pluginlib::PluginlibException& e) {
      throw std::runtime_error("backend '" + backend + "' (plugin " + plugin +
                               ") cannot be loaded: " + e.what() +
                               "; available backends: " + available);
    }
    return backend_->open(nh, pnh, pair_id_);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    if (!device_) {
      stat.hardware_id = "none";
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "pair not available: " + device_error_);
      return;
    }
    const DeviceStatus status = device_->status();
    static constexpr uint8_t kLevels[] = {diagnostic_msgs::DiagnosticStatus::OK,
                                          diagnostic_msgs::DiagnosticStatus::WARN,
                                          diagnostic_msgs::DiagnosticStatus::ERROR};
    stat.hardware_id = status.hardware_id;
    stat.summary(kLevels[static_cast<int>(status.level)], status.message);
    stat.add("state", status.state);
    stat.addf("frame rate (Hz)", "%.2f", status.frame_rate_hz);
    stat.add("dropped frames", status.dropped_frames);
    stat.add("pattern sets published", published_sets_.load());
    for (const auto& [key, value] : status.values) stat.add(key, value);
  }

  // The simulator knows its true geometry: write it as a calibration file and announce its
  // pose, so triangulation works before the pair is calibrated.
  void publishFactoryData(const std::string& calibration_file, bool publish_tf) {
    if (!calibration_file.empty()) {
      try {
        saveCalibration(calibration_file, simulator_->factoryCalibration());
        NODELET_INFO("[%s] factory calibration written to %s", pair_id_.c_str(),
                     calibration_file.c_str());
      } catch (const std::exception& e) {
        NODELET_ERROR("[%s] %s", pair_id_.c_str(), e.what());
      }
    }
    if (publish_tf) {
      const Eigen::Isometry3d pose = simulator_->factoryPose();
      geometry_msgs::TransformStamped transform;
      transform.header.stamp = ros::Time::now();
      transform.header.frame_id = world_frame_;
      transform.child_frame_id = frame_id_;
      const Eigen::Quaterniond q(pose.linear());
      transform.transform.translation.x = pose.translation().x();
      transform.transform.translation.y = pose.translation().y();
      transform.transform.translation.z = pose.translation().z();
      transform.transform.rotation.x = q.x();
      transform.transform.rotation.y = q.y();
      transform.transform.rotation.z = q.z();
      transform.transform.rotation.w = q.w();
      tf_broadcaster_.sendTransform(transform);
    }
  }

  bool onCapture(body_scan_msgs::Capture::Request& request,
                 body_scan_msgs::Capture::Response& response) {
    response.scan_id = request.scan_id;
    response.success = captureAndPublish(request.scan_id, response.message, &request.active_pairs,
                                         request.walk_id, request.pose_index);
    response.scan_id = last_scan_id_;
    return true;
  }

  void onTrigger(const std_msgs::UInt32::ConstPtr& scan_id) {
    std::string message;
    if (!captureAndPublish(scan_id->data, message))
      NODELET_ERROR_THROTTLE(5.0, "[%s] %s", pair_id_.c_str(), message.c_str());
  }

  // active_pairs: the other pairs projecting during this capture (nullptr: this pair alone).
  // walk_id, pose_index: the walk session the scan belongs to (0: none), stamped on the set.
  bool captureAndPublish(uint32_t scan_id, std::string& message,
                         const std::vector<std::string>* active_pairs = nullptr,
                         uint32_t walk_id = 0, uint8_t pose_index = 0) {
    std::lock_guard<std::mutex> lock(capture_mutex_);  // one pattern sequence at a time
    if (!device_) {
      message = "pair not available: " + device_error_;
      return false;
    }
    // Real pairs need not be told: the other pairs' light interferes physically.
    if (simulator_) {
      try {
        simulator_->setActivePairs(active_pairs ? *active_pairs : std::vector<std::string>{});
      } catch (const std::exception& e) {
        message = std::string("capture refused: ") + e.what();
        return false;
      }
    }
    last_scan_id_ = scan_id != 0 ? scan_id : last_scan_id_ + 1;
    PatternCapture capture;
    try {
      capture = device_->capture(last_scan_id_);
    } catch (const std::exception& e) {
      message = std::string("capture failed: ") + e.what();
      return false;
    } catch (...) {
      message = "capture failed: unknown error";
      return false;
    }
    std_msgs::Header header;
    header.stamp = ros::Time::now();
    header.frame_id = frame_id_;
    try {  // nothing may escape into the nodelet manager (a trigger is a callback)
      const body_scan_msgs::PatternSetPtr set = toPatternSet(
          capture, device_->layout(), device_->camera(), header, pair_id_, last_scan_id_);
      set->walk_id = walk_id;
      set->pose_index = pose_index;
      pattern_pub_.publish(set);  // shared pointer: zero copy to nodelets in this manager
      ++published_sets_;
      if (image_pub_.getNumSubscribers() > 0) image_pub_.publish(set->texture);
      info_pub_.publish(set->camera_info);
    } catch (const std::exception& e) {
      message = std::string("publishing the pattern set failed: ") + e.what();
      return false;
    }
    message = "captured scan " + std::to_string(last_scan_id_);
    return true;
  }

  // Declared before the device: the device's code lives in the backend's library, which the
  // loader unloads when it is destroyed.
  std::unique_ptr<pluginlib::ClassLoader<PairBackend>> backend_loader_;
  pluginlib::UniquePtr<PairBackend> backend_;
  std::unique_ptr<PairDevice> device_;
  SimulatorControl* simulator_ = nullptr;  // device_ if it is a simulated pair
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  ros::WallTimer diagnostics_timer_;
  std::atomic<uint64_t> published_sets_{0};
  std::string device_error_, pair_id_, frame_id_, world_frame_;
  uint32_t last_scan_id_ = 0;
  std::mutex capture_mutex_;
  ros::Publisher pattern_pub_, image_pub_, info_pub_;
  ros::ServiceServer capture_srv_, set_scene_srv_;
  ros::Subscriber trigger_sub_;
  ros::Timer timer_;
  tf2_ros::StaticTransformBroadcaster tf_broadcaster_;
};

}  // namespace body_scan_driver

PLUGINLIB_EXPORT_CLASS(body_scan_driver::PairDriverNodelet, nodelet::Nodelet)
