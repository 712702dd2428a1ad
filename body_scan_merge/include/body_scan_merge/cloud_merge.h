// Merging the pair clouds of one scan into one world-frame cloud (Merge nodelet): transform,
// crop to the scan volume, then the optional voxel grid and statistical outlier removal (PCL,
// only in cloud_merge.cpp). ROS-agnostic.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace body_scan {

struct MergeOptions {
  // Scan volume: a vertical cylinder about the world z axis (the subject's place). Points
  // outside (the floor, the poles, the room) are dropped.
  double crop_radius = 0.6;   // m
  double crop_min_z = 0.005;  // m: just above the floor
  double crop_max_z = 2.3;    // m
  // Voxel grid leaf (m); 0 = off. Neighbouring pairs overlap, doubling the density there; one
  // point per voxel evens it out (the centroid of the voxel's points and colours).
  double voxel_leaf = 0.0015;
  // Statistical outlier removal: drop points whose mean distance to their k nearest neighbours
  // exceeds the cloud's mean by std_ratio standard deviations.
  bool outlier_removal = false;
  int outlier_neighbours = 12;
  double outlier_std_ratio = 3.0;
};

// One pair's cloud as stored (e.g. a PointCloud2's buffer): x y z at offsets 0..2 floats of each
// point, stride floats per point, PCL packed rgb at rgb_offset (< 0: none); NaN = no point.
struct CloudView {
  const float* points = nullptr;
  size_t count = 0;
  size_t stride = 4;
  int rgb_offset = 3;
  Eigen::Isometry3d world_from_cloud = Eigen::Isometry3d::Identity();
};

struct MergedCloud {
  std::vector<float> xyzrgb;               // 4 floats per point: x y z (world) and packed rgb
  std::vector<size_t> valid_per_part;      // finite points of each part (before cropping)
  std::vector<size_t> in_volume_per_part;  // of those, inside the scan volume
  std::vector<std::pair<std::string, double>> stage_seconds;  // wall time per stage

  size_t size() const { return xyzrgb.size() / 4; }
};

// Deterministic: the same parts in the same order give the same cloud, bit for bit.
MergedCloud mergeClouds(const std::vector<CloudView>& parts, const MergeOptions& options);

}  // namespace body_scan
