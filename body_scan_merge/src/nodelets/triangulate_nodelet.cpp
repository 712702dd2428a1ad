// Triangulate: pattern_set -> scan_points (PairCloud: the organized xyz + rgb cloud with its
// scan id, for Merge), points (the same PointCloud2 for rviz, when subscribed) + stripe_image.
// Decoding and triangulation are body_scan_driver's core functions; this is the ROS wrapper.
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/robust_decoding.h>
#include <body_scan_driver/ros/message_checks.h>
#include <body_scan_driver/ros/pattern_set_cloud.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>
#include <body_scan_msgs/PairCloud.h>
#include <body_scan_msgs/PatternSet.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>

#include <filesystem>
#include <memory>
#include <pluginlib/class_list_macros.hpp>

#include "master_watch.h"

namespace body_scan_merge {
class TriangulateNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    calibration_file_ = pnh.param<std::string>("calibration_file", "");
    body_scan_driver::DecoderParams params;
    params.subpixel = pnh.param("subpixel", true);
    params.min_contrast = pnh.param("min_contrast", params.min_contrast);
    params.edge_contrast_ratio = pnh.param("edge_contrast_ratio", params.edge_contrast_ratio);
    body_scan_driver::RobustDecoding robust;
    robust.enabled = pnh.param("robust_decoding", false);
    cloud_maker_ = body_scan_driver::PatternSetCloud(params, robust);
    min_range_ = pnh.param("min_range", 0.2);
    max_range_ = pnh.param("max_range", 5.0);
    points_pub_ = nh.advertise<sensor_msgs::PointCloud2>("points", 2);
    scan_points_pub_ = nh.advertise<body_scan_msgs::PairCloud>("scan_points", 2);
    stripe_pub_ = nh.advertise<sensor_msgs::Image>("stripe_image", 2);
    pattern_sub_ = nh.subscribe("pattern_set", 2, &TriangulateNodelet::onPatternSet, this);
    master_watch_ = MasterWatch::acquire();  // registers again with a restarted master
    if (calibration_file_.empty())
      NODELET_ERROR("~calibration_file is not set: point it at the pair's calibration YAML");
  }

  // Loads the calibration on first use, so a driver that writes its factory calibration at
  // start-up may come up after this nodelet, and again whenever the file changes. A changed file
  // that does not load is reported once and the last good calibration stays in use.
  bool ensureCalibration(const std::string& pair_id) {
    std::error_code error;
    const auto modified = std::filesystem::last_write_time(calibration_file_, error);
    const FileStamp stamp{error ? decltype(modified)() : modified,
                          error ? 0 : std::filesystem::file_size(calibration_file_, error)};
    if (triangulator_ && (stamp == loaded_stamp_ || stamp == rejected_stamp_)) return true;
    try {
      auto triangulator = std::make_unique<body_scan_driver::Triangulator>(
          body_scan_driver::loadCalibration(calibration_file_), min_range_, max_range_);
      NODELET_INFO("[%s] calibration %sloaded from %s (%s)%s", pair_id.c_str(),
                   triangulator_ ? "re" : "", calibration_file_.c_str(),
                   triangulator->calibration().source.c_str(),
                   triangulator->calibration().alignment
                       ? ", world alignment: applying its residual linear part"
                       : "");
      triangulator_ = std::move(triangulator);
      loaded_stamp_ = stamp;
      rejected_stamp_.reset();
      return true;
    } catch (const std::exception& e) {
      if (!triangulator_) {
        NODELET_ERROR_THROTTLE(5.0, "[%s] %s", pair_id.c_str(), e.what());
        return false;
      }
      rejected_stamp_ = stamp;
      NODELET_ERROR(
          "[%s] calibration file changed but does not load, keeping the last good "
          "calibration (%s): %s; fix or restore the file (it is re-read when it changes)",
          pair_id.c_str(), triangulator_->calibration().source.c_str(), e.what());
      return true;
    }
  }

  // Nothing of a set that fails checkPatternSet is used; no exception leaves the callback
  // (it would terminate the whole nodelet manager).
  void onPatternSet(const body_scan_msgs::PatternSet::ConstPtr& set) {
    if (const auto problem = body_scan_driver::checkPatternSet(*set)) {
      if (throttle_.shouldReport(set->pair_id + *problem, ros::WallTime::now().toSec()))
        NODELET_ERROR("pattern set of '%s' (scan %u) rejected: %s", set->pair_id.c_str(),
                      set->scan_id, problem->c_str());
      return;
    }
    const std::string& pair = set->pair_id;
    try {
      if (!ensureCalibration(pair)) return;
      publish(*set);
    } catch (const std::exception& e) {
      NODELET_ERROR_THROTTLE(5.0, "[%s] scan %u not triangulated: %s", pair.c_str(), set->scan_id,
                             e.what());
    } catch (...) {
      NODELET_ERROR_THROTTLE(5.0, "[%s] scan %u not triangulated: unknown error", pair.c_str(),
                             set->scan_id);
    }
  }

  void publish(const body_scan_msgs::PatternSet& set) {
    const ros::WallTime start = ros::WallTime::now();
    body_scan_msgs::PairCloudPtr pair_cloud(new body_scan_msgs::PairCloud);
    pair_cloud->header = set.header;
    pair_cloud->pair_id = set.pair_id;
    pair_cloud->scan_id = set.scan_id;
    pair_cloud->walk_id = set.walk_id;
    pair_cloud->pose_index = set.pose_index;
    sensor_msgs::PointCloud2* cloud = &pair_cloud->cloud;
    cloud->header = set.header;
    const size_t valid = cloud_maker_.triangulate(set, *triangulator_, *cloud);
    pair_cloud->processing_seconds = (ros::WallTime::now() - start).toSec();
    // Shared pointers: no copy to subscribers in this manager; rviz's copy only when watched.
    if (points_pub_.getNumSubscribers() > 0)
      points_pub_.publish(sensor_msgs::PointCloud2Ptr(new sensor_msgs::PointCloud2(*cloud)));
    scan_points_pub_.publish(pair_cloud);
    NODELET_DEBUG("[%s] scan %u: %zu points", set.pair_id.c_str(), set.scan_id, valid);

    if (stripe_pub_.getNumSubscribers() > 0) {
      const cv::Mat1f& coordinate = cloud_maker_.stripes().coordinate;
      const cv::Size size = coordinate.size();
      sensor_msgs::ImagePtr image(new sensor_msgs::Image);
      image->header = set.header;
      image->height = size.height;
      image->width = size.width;
      image->encoding = sensor_msgs::image_encodings::TYPE_32FC1;
      image->step = static_cast<uint32_t>(size.width * sizeof(float));
      image->data.resize(static_cast<size_t>(image->step) * size.height);
      cv::Mat(size, CV_32FC1, image->data.data()) = coordinate * 1.f;
      stripe_pub_.publish(image);
    }
  }

  std::string calibration_file_;
  double min_range_ = 0.2, max_range_ = 5.0;
  std::unique_ptr<body_scan_driver::Triangulator> triangulator_;
  // The calibration file's modification time and size when loaded / when it failed to load.
  using FileStamp = std::pair<std::filesystem::file_time_type, std::uintmax_t>;
  FileStamp loaded_stamp_;
  std::optional<FileStamp> rejected_stamp_;
  body_scan_driver::PatternSetCloud cloud_maker_;  // decode, triangulate, colour
  body_scan_driver::ProblemThrottle throttle_;
  ros::Publisher points_pub_, scan_points_pub_, stripe_pub_;
  ros::Subscriber pattern_sub_;
  std::shared_ptr<MasterWatch> master_watch_;
};

}  // namespace body_scan_merge

PLUGINLIB_EXPORT_CLASS(body_scan_merge::TriangulateNodelet, nodelet::Nodelet)
