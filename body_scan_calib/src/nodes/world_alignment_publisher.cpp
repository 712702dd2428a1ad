// world_alignment_publisher: static tf2 transforms world -> <pair_id>_camera_optical_frame from
// the rigid part of each pair's world alignment (thesis eq 4.1; the residual linear part is
// applied by Triangulate). Watches the calibration files: a pair aligned while the node runs
// (align_world rewrites its file) is published without a restart; a missing or unaligned file
// is reported and the other pairs keep being published.
#include <body_scan_driver/calibration_file.h>
#include <geometry_msgs/TransformStamped.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>

namespace fs = std::filesystem;

namespace {

struct WatchedPair {
  std::string pair_id, path, frame;
  std::optional<fs::file_time_type> loaded_version;
  std::optional<geometry_msgs::TransformStamped> transform;
};

std::string fileStem(std::string pair_id) {
  for (char& c : pair_id)
    if (c == '/') c = '_';
  return pair_id;
}

geometry_msgs::TransformStamped toMessage(const Eigen::Isometry3d& pose, const std::string& parent,
                                          const std::string& child) {
  geometry_msgs::TransformStamped transform;
  transform.header.stamp = ros::Time::now();
  transform.header.frame_id = parent;
  transform.child_frame_id = child;
  const Eigen::Quaterniond q(pose.linear());
  transform.transform.translation.x = pose.translation().x();
  transform.transform.translation.y = pose.translation().y();
  transform.transform.translation.z = pose.translation().z();
  transform.transform.rotation.x = q.x();
  transform.transform.rotation.y = q.y();
  transform.transform.rotation.z = q.z();
  transform.transform.rotation.w = q.w();
  return transform;
}

class WorldAlignmentPublisher {
 public:
  WorldAlignmentPublisher() {
    ros::NodeHandle pnh("~");
    const char* home = std::getenv("HOME");
    const std::string directory = pnh.param<std::string>(
        "calibration_dir", std::string(home ? home : ".") + "/.ros/body_scan/calibration");
    world_frame_ = pnh.param<std::string>("world_frame", "world");
    std::vector<std::string> pairs;
    pnh.param("pairs", pairs, std::vector<std::string>{});
    if (pairs.empty())
      ROS_ERROR(
          "~pairs is empty: list the pair ids to publish, e.g. [pole_a/pair_1, "
          "pole_b/pair_1]");
    for (const std::string& pair_id : pairs)
      pairs_.push_back({pair_id, directory + "/" + fileStem(pair_id) + ".yaml",
                        pair_id + "_camera_optical_frame", std::nullopt, std::nullopt});
    timer_ = pnh.createWallTimer(ros::WallDuration(pnh.param("check_period", 1.0)),
                                 [this](const ros::WallTimerEvent&) { refresh(); });
    refresh();
  }

 private:
  // Reloads every file that changed since it was last read; republishes if any transform did.
  void refresh() {
    bool changed = false;
    for (WatchedPair& pair : pairs_) {
      std::error_code error;
      const fs::file_time_type version = fs::last_write_time(pair.path, error);
      if (error) {
        ROS_ERROR_THROTTLE(10.0,
                           "[%s] calibration file %s not found: align the pairs with "
                           "`rosrun body_scan_calib align_world --images DIR` (simulator: "
                           "align_simulated_rig); it writes this file",
                           pair.pair_id.c_str(), pair.path.c_str());
        continue;
      }
      if (pair.loaded_version == version) continue;
      pair.loaded_version = version;
      try {
        const body_scan_driver::PairCalibration calibration =
            body_scan_driver::loadCalibration(pair.path);
        if (!calibration.alignment) {
          ROS_ERROR("[%s] %s has no world_alignment section: run align_world for this pair",
                    pair.pair_id.c_str(), pair.path.c_str());
          continue;
        }
        pair.transform =
            toMessage(calibration.alignment->world_from_camera, world_frame_, pair.frame);
        changed = true;
        ROS_INFO("[%s] world alignment loaded from %s: %s -> %s", pair.pair_id.c_str(),
                 pair.path.c_str(), world_frame_.c_str(), pair.frame.c_str());
      } catch (const std::exception& e) {
        ROS_ERROR("[%s] %s", pair.pair_id.c_str(), e.what());
      }
    }
    if (!changed) return;
    std::vector<geometry_msgs::TransformStamped> transforms;
    for (const WatchedPair& pair : pairs_)
      if (pair.transform) transforms.push_back(*pair.transform);
    broadcaster_.sendTransform(transforms);
  }

  std::string world_frame_;
  std::vector<WatchedPair> pairs_;
  tf2_ros::StaticTransformBroadcaster broadcaster_;
  ros::WallTimer timer_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "world_alignment_publisher");
  WorldAlignmentPublisher publisher;
  ros::spin();
  return 0;
}
