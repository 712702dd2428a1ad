// Merge: the pair clouds of one scan (`/<pair_id>/scan_points`, PairCloud) -> one whole-body
// cloud in the world frame (/body_scan/cloud) + a ScanReport (/body_scan/scan_report).
// Collection by scan id: ScanAssembler; transform, crop and filters: mergeClouds (core).
#include <body_scan_merge/cloud_filters.h>
#include <body_scan_merge/scan_assembler.h>
#include <body_scan_msgs/PairCloud.h>
#include <body_scan_msgs/ScanReport.h>
#include <body_scan_msgs/TimingGroups.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <memory>
#include <mutex>
#include <pluginlib/class_list_macros.hpp>

namespace body_scan {
namespace {

std::vector<std::string> thesisPairs() {
  std::vector<std::string> pairs;
  for (const char* pole : {"pole_a", "pole_b", "pole_c"})
    for (int i = 1; i <= 4; ++i) pairs.push_back(std::string(pole) + "/pair_" + std::to_string(i));
  return pairs;
}

// Triangulate's layout: float32 x, y, z, rgb at offsets 0, 4, 8, 12, little endian.
bool hasTriangulateLayout(const sensor_msgs::PointCloud2& cloud) {
  const char* names[] = {"x", "y", "z", "rgb"};
  if (cloud.fields.size() < 4 || cloud.point_step < 16 || cloud.point_step % 4 != 0 ||
      cloud.is_bigendian ||
      cloud.data.size() < static_cast<size_t>(cloud.row_step) * cloud.height ||
      cloud.row_step != cloud.point_step * cloud.width)
    return false;
  for (uint32_t i = 0; i < 4; ++i)
    if (cloud.fields[i].name != names[i] || cloud.fields[i].offset != 4 * i ||
        cloud.fields[i].datatype != sensor_msgs::PointField::FLOAT32)
      return false;
  return true;
}

double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

class MergeNodelet : public nodelet::Nodelet {
  using Assembler = ScanAssembler<body_scan_msgs::PairCloud::ConstPtr>;

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    std::vector<std::string> pairs;
    if (!pnh.getParam("pairs", pairs) || pairs.empty()) pairs = thesisPairs();
    world_frame_ = pnh.param<std::string>("world_frame", "world");
    const double timeout = pnh.param("timeout", 2.0);
    params_.volume.radius = pnh.param("crop_radius", params_.volume.radius);
    params_.volume.z_min = pnh.param("crop_z_min", params_.volume.z_min);
    params_.volume.z_max = pnh.param("crop_z_max", params_.volume.z_max);
    params_.voxel_leaf = pnh.param("voxel_leaf", params_.voxel_leaf);
    params_.outlier_neighbours = pnh.param("outlier_neighbours", params_.outlier_neighbours);
    params_.outlier_stddev = pnh.param("outlier_stddev", params_.outlier_stddev);
    tf_wait_ = pnh.param("tf_wait", 0.5);
    assembler_ = std::make_unique<Assembler>(pairs, timeout);

    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
    cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>("/body_scan/cloud", 2);
    report_pub_ = nh.advertise<body_scan_msgs::ScanReport>("/body_scan/scan_report", 10);
    groups_sub_ = nh.subscribe<body_scan_msgs::TimingGroups>(
        "/body_scan/timing_groups", 1, [this](const body_scan_msgs::TimingGroups::ConstPtr& g) {
          std::lock_guard<std::mutex> lock(mutex_);
          timing_groups_ = g;
        });
    for (const std::string& pair : pairs)
      pair_subs_.push_back(
          nh.subscribe("/" + pair + "/scan_points", 4, &MergeNodelet::onPairCloud, this));
    poll_timer_ =
        nh.createWallTimer(ros::WallDuration(0.05), [this](const ros::WallTimerEvent&) { poll(); });
    NODELET_INFO(
        "merging %zu pairs into /body_scan/cloud (%s frame, timeout %.1f s, voxel %.1f mm, "
        "crop r %.2f m z %.3f..%.2f m)",
        pairs.size(), world_frame_.c_str(), timeout, params_.voxel_leaf * 1e3,
        params_.volume.radius, params_.volume.z_min, params_.volume.z_max);
  }

  void onPairCloud(const body_scan_msgs::PairCloud::ConstPtr& cloud) {
    Assembler::AddResult result;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      result = assembler_->add(cloud->pair_id, cloud->scan_id, cloud, steadySeconds());
    }
    switch (result) {
      case Assembler::AddResult::kLate:
        NODELET_WARN(
            "[%s] cloud of scan %u arrived after the scan was published (timeout %.1f "
            "s); dropped. Raise ~timeout if this pair is regularly this slow",
            cloud->pair_id.c_str(), cloud->scan_id, assembler_->timeout());
        break;
      case Assembler::AddResult::kDuplicate:
        NODELET_WARN("[%s] second cloud for scan %u; dropped", cloud->pair_id.c_str(),
                     cloud->scan_id);
        break;
      case Assembler::AddResult::kUnexpectedPair:
        NODELET_WARN_THROTTLE(5.0,
                              "cloud with pair_id '%s' is not in ~pairs; dropped (check the "
                              "pair's driver pair_id or add it to ~pairs)",
                              cloud->pair_id.c_str());
        break;
      case Assembler::AddResult::kAccepted:
        poll();
        break;
    }
  }

  void poll() {
    std::vector<Assembler::Scan> ready;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready = assembler_->poll(steadySeconds());
    }
    for (Assembler::Scan& scan : ready) {
      try {
        process(scan);
      } catch (const std::exception& e) {  // never take the manager down
        NODELET_ERROR("scan %u not merged: %s", scan.scan_id, e.what());
      }
    }
  }

  std::optional<Eigen::Isometry3f> worldFrom(const std::string& frame, const std::string& pair) {
    try {
      const auto t =
          tf_buffer_->lookupTransform(world_frame_, frame, ros::Time(0), ros::Duration(tf_wait_));
      const auto& q = t.transform.rotation;
      const auto& p = t.transform.translation;
      Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
      pose.linear() = Eigen::Quaternionf(q.w, q.x, q.y, q.z).normalized().toRotationMatrix();
      pose.translation() << p.x, p.y, p.z;
      return pose;
    } catch (const std::exception& e) {
      NODELET_ERROR_THROTTLE(5.0,
                             "[%s] no transform %s <- %s (%s); the pair is left out of the scan. "
                             "Start the drivers with publish_factory_tf (simulator) or run the "
                             "world_alignment_publisher (calibrated rig)",
                             pair.c_str(), world_frame_.c_str(), frame.c_str(), e.what());
      return std::nullopt;
    }
  }

  void process(Assembler::Scan& scan) {
    const auto start = std::chrono::steady_clock::now();
    body_scan_msgs::ScanReport report;
    report.scan_id = scan.scan_id;
    report.pairs_expected = assembler_->expectedPairs();
    report.pairs_missing = scan.missing;
    std::vector<PairPoints> inputs;
    std::vector<std::string> present;
    double slowest = 0;
    ros::Time stamp;
    for (const auto& [pair, cloud] : scan.clouds) {
      if (!hasTriangulateLayout(cloud->cloud)) {
        NODELET_ERROR_THROTTLE(5.0,
                               "[%s] scan_points cloud is not Triangulate's layout (float32 x y z "
                               "rgb, complete data); the pair is left out",
                               pair.c_str());
        report.pairs_missing.push_back(pair);
        continue;
      }
      const auto pose = worldFrom(cloud->header.frame_id, pair);
      if (!pose) {
        report.pairs_missing.push_back(pair);
        continue;
      }
      PairPoints input;
      input.points = reinterpret_cast<const float*>(cloud->cloud.data.data());
      input.count = static_cast<size_t>(cloud->cloud.width) * cloud->cloud.height;
      input.stride = cloud->cloud.point_step / 4;
      input.world_from_cloud = *pose;
      inputs.push_back(input);
      present.push_back(pair);
      slowest = std::max(slowest, cloud->processing_seconds);
      stamp = std::max(stamp, cloud->header.stamp);
    }
    const MergeResult merged = mergeClouds(inputs, params_);
    report.pairs_present = present;
    for (size_t n : merged.valid_per_pair) report.points_per_pair.push_back(n);
    report.points_merged = static_cast<uint32_t>(merged.points.size());

    sensor_msgs::PointCloud2Ptr cloud(new sensor_msgs::PointCloud2);
    cloud->header.stamp = stamp;
    cloud->header.frame_id = world_frame_;
    cloud->height = 1;
    cloud->width = static_cast<uint32_t>(merged.points.size());
    const char* names[] = {"x", "y", "z", "rgb"};
    for (uint32_t i = 0; i < 4; ++i) {
      sensor_msgs::PointField field;
      field.name = names[i];
      field.offset = 4 * i;
      field.datatype = sensor_msgs::PointField::FLOAT32;
      field.count = 1;
      cloud->fields.push_back(field);
    }
    cloud->point_step = sizeof(ColouredPoint);
    cloud->row_step = cloud->point_step * cloud->width;
    cloud->is_dense = true;
    cloud->data.resize(static_cast<size_t>(cloud->row_step));
    if (!merged.points.empty())
      std::memcpy(cloud->data.data(), merged.points.data(), cloud->data.size());
    cloud_pub_.publish(cloud);

    const double total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report.header = cloud->header;
    report.stage_names = {"decode+triangulate (slowest pair)", "transform+crop", "voxel",
                          "outliers", "merge total"};
    report.stage_seconds = {slowest, merged.transform_seconds, merged.voxel_seconds,
                            merged.outlier_seconds, total};
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (timing_groups_) {
        report.timing_groups = static_cast<uint32_t>(timing_groups_->groups.size());
        report.simulated_capture_seconds = report.timing_groups * timing_groups_->group_seconds;
      }
    }
    char line[256];
    std::snprintf(line, sizeof line,
                  "scan %u: %zu/%zu pairs, %u points (decode+triangulate %.0f ms slowest pair, "
                  "merge %.0f ms)",
                  scan.scan_id, present.size(), report.pairs_expected.size(), report.points_merged,
                  slowest * 1e3, total * 1e3);
    std::string message = line;
    if (!report.pairs_missing.empty()) {
      message += "; missing:";
      for (const auto& pair : report.pairs_missing) message += " " + pair;
    }
    report.message = message;
    report_pub_.publish(report);
    NODELET_INFO("%s", message.c_str());
  }

  std::string world_frame_;
  MergeParams params_;
  double tf_wait_ = 0.5;
  std::mutex mutex_;
  std::unique_ptr<Assembler> assembler_;
  body_scan_msgs::TimingGroups::ConstPtr timing_groups_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Publisher cloud_pub_, report_pub_;
  ros::Subscriber groups_sub_;
  std::vector<ros::Subscriber> pair_subs_;
  ros::WallTimer poll_timer_;
};

}  // namespace body_scan

PLUGINLIB_EXPORT_CLASS(body_scan::MergeNodelet, nodelet::Nodelet)
