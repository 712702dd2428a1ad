// BodyFitter: /body_scan/cloud (PointCloud2, world) -> /body_gait/model (BodyModel),
// /body_gait/markers (MarkerArray), /body_gait/joint_states, TF of the model's links and the
// URDF on robot_description (thesis 5.5). The fit is body_gait_model::fitBody; this is the ROS
// wrapper. robot_state_publisher is not installed here, so the nodelet publishes the links' TF
// itself (modelTransforms: the same frames robot_state_publisher would derive from joint_states).
#include <body_gait_model/body_fitter.h>
#include <body_gait_model/fit_options_file.h>
#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/urdf.h>
#include <malloc.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <chrono>
#include <memory>
#include <pluginlib/class_list_macros.hpp>

namespace body_gait_model {

class BodyFitterNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    world_frame_ = pnh.param<std::string>("world_frame", "world");
    link_prefix_ = pnh.param<std::string>("link_prefix", "body_gait/");
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
    model_pub_ = nh.advertise<body_scan_msgs::BodyModel>("body_gait/model", 2, true);
    marker_pub_ = nh.advertise<visualization_msgs::MarkerArray>("body_gait/markers", 2, true);
    joint_pub_ = nh.advertise<sensor_msgs::JointState>("body_gait/joint_states", 2, true);
    tf_ = std::make_unique<tf2_ros::TransformBroadcaster>();
    // Queue of 1: a fit takes up to ~0.5 s; a newer cloud replaces one still waiting.
    cloud_sub_ = nh.subscribe("body_scan/cloud", 1, &BodyFitterNodelet::onCloud, this);
  }

  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
    if (msg->header.frame_id != world_frame_) {
      NODELET_ERROR_THROTTLE(5.0,
                             "cloud in frame '%s' not fitted: the body fitter needs clouds in "
                             "'%s' (floor, z up); publish the merged world cloud",
                             msg->header.frame_id.c_str(), world_frame_.c_str());
      return;
    }
    try {
      const Cloud cloud = cloudFromMsg(*msg);
      if (cloud.empty()) {
        NODELET_ERROR_THROTTLE(5.0, "cloud has no finite points: nothing to fit; check the scan");
        return;
      }
      const auto start = std::chrono::steady_clock::now();
      const BodyFit fit = fitBody(cloud, options_);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std_msgs::Header header = msg->header;
      model_pub_.publish(toMsg(fit, header, seconds));
      marker_pub_.publish(modelMarkers(fit.model, fit.quality.low_quality, header));
      joint_pub_.publish(jointStates(fit.model, header));
      tf_->sendTransform(modelTransforms(fit.model, header, link_prefix_));
      getNodeHandle().setParam("robot_description",
                               modelUrdf(fit.model, "body_gait", link_prefix_));
      // A fit's temporaries (tens of MB), once freed, stay with glibc's per-thread arenas (soak:
      // RSS +28 % over 300 scans with 2.5 MB in use); hand them back to the system.
      malloc_trim(0);
      if (fit.quality.low_quality)
        NODELET_WARN("%zu points fitted in %.0f ms: LOW QUALITY (%s)", cloud.size(), 1000 * seconds,
                     fit.quality.reason.c_str());
      else
        NODELET_INFO("%zu points fitted in %.0f ms: RMS %.1f mm, %.0f %% explained", cloud.size(),
                     1000 * seconds, 1000 * fit.quality.rms_distance,
                     100 * fit.quality.explained_fraction);
    } catch (const std::exception& e) {
      NODELET_ERROR_THROTTLE(5.0, "cloud not fitted: %s", e.what());
    }
  }

  std::string world_frame_, link_prefix_;
  FitOptions options_;
  ros::Publisher model_pub_, marker_pub_, joint_pub_;
  ros::Subscriber cloud_sub_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_;
};

}  // namespace body_gait_model

PLUGINLIB_EXPORT_CLASS(body_gait_model::BodyFitterNodelet, nodelet::Nodelet)
