#include <body_scan_merge/cloud_filters.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace body_scan {
namespace {

pcl::PointCloud<pcl::PointXYZRGB>::Ptr toPcl(const std::vector<ColouredPoint>& points) {
  pcl::PointCloud<pcl::PointXYZRGB>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZRGB>);
  cloud->resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    pcl::PointXYZRGB& p = (*cloud)[i];
    p.x = points[i].x;
    p.y = points[i].y;
    p.z = points[i].z;
    p.rgb = points[i].rgb;
  }
  cloud->width = static_cast<uint32_t>(points.size());
  cloud->height = 1;
  cloud->is_dense = true;
  return cloud;
}

void fromPcl(const pcl::PointCloud<pcl::PointXYZRGB>& cloud, std::vector<ColouredPoint>& points) {
  points.resize(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i)
    points[i] = {cloud[i].x, cloud[i].y, cloud[i].z, cloud[i].rgb};
}

}  // namespace

size_t transformAndCrop(const float* points, size_t count, size_t stride,
                        const Eigen::Isometry3f& world_from_cloud, const ScanVolume& volume,
                        std::vector<ColouredPoint>& out) {
  size_t valid = 0;
  for (size_t i = 0; i < count; ++i) {
    const float* p = points + i * stride;
    if (!std::isfinite(p[2])) continue;  // NaN = no depth (Triangulate)
    ++valid;
    const Eigen::Vector3f world = world_from_cloud * Eigen::Vector3f(p[0], p[1], p[2]);
    if (volume.contains(world)) out.push_back({world.x(), world.y(), world.z(), p[3]});
  }
  return valid;
}

void voxelGrid(std::vector<ColouredPoint>& points, double leaf) {
  if (leaf <= 0 || points.empty()) return;
  const auto cloud = toPcl(points);
  pcl::VoxelGrid<pcl::PointXYZRGB> grid;
  grid.setInputCloud(cloud);
  const float l = static_cast<float>(leaf);
  grid.setLeafSize(l, l, l);
  pcl::PointCloud<pcl::PointXYZRGB> filtered;
  grid.filter(filtered);
  fromPcl(filtered, points);
}

void removeOutliers(std::vector<ColouredPoint>& points, int neighbours, double stddev) {
  if (neighbours <= 0 || points.size() <= static_cast<size_t>(neighbours)) return;
  const auto cloud = toPcl(points);
  pcl::StatisticalOutlierRemoval<pcl::PointXYZRGB> sor;
  sor.setInputCloud(cloud);
  sor.setMeanK(neighbours);
  sor.setStddevMulThresh(stddev);
  pcl::PointCloud<pcl::PointXYZRGB> filtered;
  sor.filter(filtered);
  fromPcl(filtered, points);
}

MergeResult mergeClouds(const std::vector<PairPoints>& pairs, const MergeParams& params) {
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  };
  MergeResult result;
  const auto t0 = Clock::now();
  size_t total = 0;
  for (const PairPoints& pair : pairs) total += pair.count;
  result.points.reserve(total / 2);
  for (const PairPoints& pair : pairs)
    result.valid_per_pair.push_back(transformAndCrop(
        pair.points, pair.count, pair.stride, pair.world_from_cloud, params.volume, result.points));
  const auto t1 = Clock::now();
  voxelGrid(result.points, params.voxel_leaf);
  const auto t2 = Clock::now();
  removeOutliers(result.points, params.outlier_neighbours, params.outlier_stddev);
  const auto t3 = Clock::now();
  result.transform_seconds = seconds(t0, t1);
  result.voxel_seconds = seconds(t1, t2);
  result.outlier_seconds = seconds(t2, t3);
  return result;
}

}  // namespace body_scan
