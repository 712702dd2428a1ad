// PairDriver: captures pattern sets from one pair and publishes them (DESIGN.md section 3).
// backend:=sim (the virtual pair) or backend:=usb (a real pair, issue 8); device health goes
// to /diagnostics for every backend.
#include <body_scan_driver/UsbPairSettingsConfig.h>
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/hw/usb_pair_device.h>
#include <body_scan_driver/pair_device.h>
#include <body_scan_driver/ros/conversions.h>
#include <body_scan_msgs/Capture.h>
#include <body_scan_msgs/PatternSet.h>
#include <body_scan_msgs/SetScene.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
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
      if (backend == "sim") {
        // A pair of a rig (interference from the rig's other pairs) or a single pair file.
        const std::string rig_file = pnh.param<std::string>("rig_file", "");
        const std::string scene_file = pnh.param<std::string>("scene_file", "");
        device_ = rig_file.empty()
                      ? makeSimulatedPair(pnh.param<std::string>("pair_file", ""), scene_file)
                      : makeSimulatedRigPair(rig_file, pair_id_, scene_file);
      } else if (backend == "usb") {
        const hw::UsbPairSettings settings = usbSettings(pnh);
        usb_camera_settings_ = settings.camera_settings;
        auto usb = std::make_unique<hw::UsbPairDevice>(settings, hw::realHardware());
        usb_device_ = usb.get();
        device_ = std::move(usb);
        reconfigure_server_ =
            std::make_unique<dynamic_reconfigure::Server<body_scan_driver::UsbPairSettingsConfig>>(
                pnh);
        reconfigure_server_->setCallback([this](body_scan_driver::UsbPairSettingsConfig& config,
                                                uint32_t) { onReconfigure(config); });
        // Reconnects (DISCONNECTED/ERROR -> STREAMING) and hot-plug events happen here.
        poll_timer_ = nh.createWallTimer(ros::WallDuration(pnh.param("poll_period", 0.1)),
                                         [this](const ros::WallTimerEvent&) { pollDevice(); });
      } else {
        throw std::runtime_error("backend '" + backend + "' is unknown; use backend:=sim or usb");
      }
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
                device_->replaceScene(request.scene_yaml);
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

  // Parameters of backend:=usb (README "Setting up a real pair"). Throws on a malformed id.
  hw::UsbPairSettings usbSettings(ros::NodeHandle& pnh) const {
    hw::UsbPairSettings settings;
    settings.pair_id = pair_id_;
    settings.camera = hw::UsbDeviceMatch::parse(pnh.param<std::string>("camera_id", ""),
                                                pnh.param<std::string>("camera_serial", ""));
    const std::string projector_id = pnh.param<std::string>("projector_id", "");
    if (!projector_id.empty())
      settings.projector_usb =
          hw::UsbDeviceMatch::parse(projector_id, pnh.param<std::string>("projector_serial", ""));
    settings.projector_display = pnh.param<std::string>("projector_display", ":0");
    settings.projector_screen = pnh.param("projector_screen", -1);
    hw::UvcSettings& camera = settings.camera_settings;
    camera.format = pnh.param<std::string>("camera_format", camera.format);
    camera.width = pnh.param("camera_width", camera.width);
    camera.height = pnh.param("camera_height", camera.height);
    camera.fps = pnh.param("camera_fps", camera.fps);
    camera.exposure_ms = pnh.param("exposure_ms", camera.exposure_ms);
    camera.gain = pnh.param("gain", camera.gain);
    settings.sequencer.settle_frames = pnh.param("settle_frames", 2);
    settings.sequencer.frame_timeout_s = pnh.param("frame_timeout", 1.0);
    const std::string stripes = pnh.param<std::string>("stripes_along", "rows");
    if (stripes != "rows" && stripes != "columns")
      throw std::invalid_argument("stripes_along must be rows (vertical baseline) or columns");
    settings.sequencer.direction =
        stripes == "rows" ? hw::StripeDirection::kAlongRows : hw::StripeDirection::kAlongColumns;
    settings.bits = pnh.param("bits", 8);
    settings.inverse_frames = pnh.param("inverse_frames", true);
    settings.calibration_file = pnh.param<std::string>("calibration_file", "");
    settings.retry.initial_interval_s = pnh.param("retry_initial_interval", 0.5);
    settings.retry.max_interval_s = pnh.param("retry_max_interval", 10.0);
    return settings;
  }

  // Reconnects; logs each change of the connection state once (details on /diagnostics).
  void pollDevice() {
    device_->poll();
    const DeviceStatus status = device_->status();
    if (status.state == last_logged_state_) return;
    last_logged_state_ = status.state;
    if (status.level == DeviceStatus::Level::kError)
      NODELET_ERROR("[%s] %s: %s", pair_id_.c_str(), status.state.c_str(), status.message.c_str());
    else
      NODELET_INFO("[%s] %s: %s", pair_id_.c_str(), status.state.c_str(), status.message.c_str());
  }

  void onReconfigure(const body_scan_driver::UsbPairSettingsConfig& config) {
    hw::UvcSettings camera = usb_camera_settings_;
    camera.exposure_ms = config.exposure_ms;
    camera.gain = config.gain;
    try {
      usb_device_->applySettings(camera, config.settle_frames);
      usb_camera_settings_ = camera;
    } catch (const std::exception& e) {
      NODELET_ERROR("[%s] settings not applied: %s", pair_id_.c_str(), e.what());
    }
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
    if (auto calibration = device_->factoryCalibration();
        calibration && !calibration_file.empty()) {
      try {
        saveCalibration(calibration_file, *calibration);
        NODELET_INFO("[%s] factory calibration written to %s", pair_id_.c_str(),
                     calibration_file.c_str());
      } catch (const std::exception& e) {
        NODELET_ERROR("[%s] %s", pair_id_.c_str(), e.what());
      }
    }
    if (auto pose = device_->factoryPose(); pose && publish_tf) {
      geometry_msgs::TransformStamped transform;
      transform.header.stamp = ros::Time::now();
      transform.header.frame_id = world_frame_;
      transform.child_frame_id = frame_id_;
      const Eigen::Quaterniond q(pose->linear());
      transform.transform.translation.x = pose->translation().x();
      transform.transform.translation.y = pose->translation().y();
      transform.transform.translation.z = pose->translation().z();
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
    response.success = captureAndPublish(request.scan_id, response.message, &request.active_pairs);
    response.scan_id = last_scan_id_;
    return true;
  }

  void onTrigger(const std_msgs::UInt32::ConstPtr& scan_id) {
    std::string message;
    if (!captureAndPublish(scan_id->data, message))
      NODELET_ERROR_THROTTLE(5.0, "[%s] %s", pair_id_.c_str(), message.c_str());
  }

  // active_pairs: the other pairs projecting during this capture (nullptr: this pair alone).
  bool captureAndPublish(uint32_t scan_id, std::string& message,
                         const std::vector<std::string>* active_pairs = nullptr) {
    std::lock_guard<std::mutex> lock(capture_mutex_);  // one pattern sequence at a time
    if (!device_) {
      message = "pair not available: " + device_error_;
      return false;
    }
    try {
      device_->setActivePairs(active_pairs ? *active_pairs : std::vector<std::string>{});
    } catch (const std::exception& e) {
      message = std::string("capture refused: ") + e.what();
      return false;
    }
    last_scan_id_ = scan_id != 0 ? scan_id : last_scan_id_ + 1;
    PatternCapture capture;
    try {
      capture = device_->capture(last_scan_id_);
    } catch (const std::exception& e) {
      message = std::string("capture failed: ") + e.what();
      return false;
    }
    std_msgs::Header header;
    header.stamp = ros::Time::now();
    header.frame_id = frame_id_;
    const body_scan_msgs::PatternSetPtr set = toPatternSet(
        capture, device_->layout(), device_->camera(), header, pair_id_, last_scan_id_);
    pattern_pub_.publish(set);  // shared pointer: zero copy to nodelets in this manager
    ++published_sets_;
    if (image_pub_.getNumSubscribers() > 0) image_pub_.publish(set->texture);
    info_pub_.publish(set->camera_info);
    message = "captured scan " + std::to_string(last_scan_id_);
    return true;
  }

  std::unique_ptr<PairDevice> device_;
  hw::UsbPairDevice* usb_device_ = nullptr;  // device_ when backend:=usb
  hw::UvcSettings usb_camera_settings_;
  std::unique_ptr<dynamic_reconfigure::Server<body_scan_driver::UsbPairSettingsConfig>>
      reconfigure_server_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  ros::WallTimer diagnostics_timer_, poll_timer_;
  std::atomic<uint64_t> published_sets_{0};
  std::string last_logged_state_;
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
