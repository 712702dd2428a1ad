#include <body_scan_merge/cloud_merge.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <chrono>
#include <cmath>
#include <cstring>

namespace body_scan {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

pcl::PointCloud<pcl::PointXYZRGB>::Ptr toPcl(const std::vector<float>& xyzrgb) {
  pcl::PointCloud<pcl::PointXYZRGB>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZRGB>);
  cloud->resize(xyzrgb.size() / 4);
  for (size_t i = 0; i < cloud->size(); ++i) {
    pcl::PointXYZRGB& p = (*cloud)[i];
    p.x = xyzrgb[4 * i], p.y = xyzrgb[4 * i + 1], p.z = xyzrgb[4 * i + 2];
    std::memcpy(&p.rgba, &xyzrgb[4 * i + 3], sizeof p.rgba);
  }
  return cloud;
}

void fromPcl(const pcl::PointCloud<pcl::PointXYZRGB>& cloud, std::vector<float>& xyzrgb) {
  xyzrgb.resize(4 * cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    const pcl::PointXYZRGB& p = cloud[i];
    xyzrgb[4 * i] = p.x, xyzrgb[4 * i + 1] = p.y, xyzrgb[4 * i + 2] = p.z;
    const uint32_t rgb = p.rgba & 0xFFFFFFu;
    std::memcpy(&xyzrgb[4 * i + 3], &rgb, sizeof rgb);
  }
}

}  // namespace

MergedCloud mergeClouds(const std::vector<CloudView>& parts, const MergeOptions& options) {
  MergedCloud merged;
  auto start = Clock::now();
  const float radius2 = static_cast<float>(options.crop_radius * options.crop_radius);
  const float white = [] {
    const uint32_t rgb = 0xFFFFFF;
    float value;
    std::memcpy(&value, &rgb, sizeof value);
    return value;
  }();
  for (const CloudView& part : parts) {
    const Eigen::Matrix3f rotation = part.world_from_cloud.linear().cast<float>();
    const Eigen::Vector3f translation = part.world_from_cloud.translation().cast<float>();
    size_t valid = 0, kept = 0;
    for (size_t i = 0; i < part.count; ++i) {
      const float* p = part.points + i * part.stride;
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
      ++valid;
      const Eigen::Vector3f w = rotation * Eigen::Vector3f(p[0], p[1], p[2]) + translation;
      if (w.x() * w.x() + w.y() * w.y() > radius2 || w.z() < options.crop_min_z ||
          w.z() > options.crop_max_z)
        continue;
      ++kept;
      merged.xyzrgb.insert(
          merged.xyzrgb.end(),
          {w.x(), w.y(), w.z(), part.rgb_offset >= 0 ? p[part.rgb_offset] : white});
    }
    merged.valid_per_part.push_back(valid);
    merged.in_volume_per_part.push_back(kept);
  }
  merged.stage_seconds.emplace_back("transform+crop", secondsSince(start));

  if (options.voxel_leaf > 0 && merged.size() > 0) {
    start = Clock::now();
    pcl::VoxelGrid<pcl::PointXYZRGB> grid;
    grid.setInputCloud(toPcl(merged.xyzrgb));
    const auto leaf = static_cast<float>(options.voxel_leaf);
    grid.setLeafSize(leaf, leaf, leaf);
    pcl::PointCloud<pcl::PointXYZRGB> filtered;
    grid.filter(filtered);
    fromPcl(filtered, merged.xyzrgb);
    merged.stage_seconds.emplace_back("voxel", secondsSince(start));
  }
  if (options.outlier_removal && merged.size() > static_cast<size_t>(options.outlier_neighbours)) {
    start = Clock::now();
    pcl::StatisticalOutlierRemoval<pcl::PointXYZRGB> removal;
    removal.setInputCloud(toPcl(merged.xyzrgb));
    removal.setMeanK(options.outlier_neighbours);
    removal.setStddevMulThresh(options.outlier_std_ratio);
    pcl::PointCloud<pcl::PointXYZRGB> filtered;
    removal.filter(filtered);
    fromPcl(filtered, merged.xyzrgb);
    merged.stage_seconds.emplace_back("outliers", secondsSince(start));
  }
  return merged;
}

}  // namespace body_scan
