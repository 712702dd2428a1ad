// Merge stages of a whole-body scan (ROS- and PCL-agnostic interface; PCL only in the .cpp):
// each pair's valid points to the world frame, crop to the scan volume, voxel grid,
// statistical outlier removal.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

namespace body_scan {

// x, y, z (m) and PCL's packed-float rgb: the layout of Triangulate's cloud (point_step 16).
struct ColouredPoint {
  float x, y, z, rgb;
};

// The scan volume: a vertical cylinder about the world z axis (the subject's standing axis).
// Defaults: the thesis rig's subject volume; z_min above 0 removes the floor.
struct ScanVolume {
  double radius = 0.6;
  double z_min = 0.005;
  double z_max = 2.2;
  bool contains(const Eigen::Vector3f& p) const {
    return p.z() >= z_min && p.z() <= z_max && p.x() * p.x() + p.y() * p.y() <= radius * radius;
  }
};

struct MergeParams {
  ScanVolume volume;
  double voxel_leaf = 0.002;    // m; 0 = no voxel grid
  int outlier_neighbours = 0;   // k of the statistical outlier removal; 0 = off
  double outlier_stddev = 1.0;  // points with mean k-NN distance > mean + this * stddev go
};

// Appends the finite points of `points` (count points, `stride` floats apart, xyz + rgb at the
// first four floats) transformed by `world_from_cloud` and inside `volume` to `out`. Returns the
// number of finite points read (the pair's valid points, before cropping).
size_t transformAndCrop(const float* points, size_t count, size_t stride,
                        const Eigen::Isometry3f& world_from_cloud, const ScanVolume& volume,
                        std::vector<ColouredPoint>& out);

// pcl::VoxelGrid: one point (centroid, mean colour) per occupied cube of edge `leaf`.
void voxelGrid(std::vector<ColouredPoint>& points, double leaf);

// pcl::StatisticalOutlierRemoval with k neighbours and the stddev multiplier.
void removeOutliers(std::vector<ColouredPoint>& points, int neighbours, double stddev);

// One pair's cloud as Triangulate publishes it, with its pose in the world.
struct PairPoints {
  const float* points = nullptr;  // xyz + rgb at the first four floats of each point
  size_t count = 0;
  size_t stride = 4;  // floats between points
  Eigen::Isometry3f world_from_cloud = Eigen::Isometry3f::Identity();
};

struct MergeResult {
  std::vector<ColouredPoint> points;   // world frame, cropped and filtered
  std::vector<size_t> valid_per_pair;  // finite points of each input pair
  double transform_seconds = 0, voxel_seconds = 0, outlier_seconds = 0;
};

// The whole merge: transformAndCrop of every pair, then voxelGrid and removeOutliers as
// configured, with the wall time of each stage.
MergeResult mergeClouds(const std::vector<PairPoints>& pairs, const MergeParams& params);

}  // namespace body_scan
