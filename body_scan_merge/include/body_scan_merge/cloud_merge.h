// Merging the pair clouds of one scan into one world-frame cloud (Merge nodelet): transform,
// crop to the scan volume, then the optional voxel grid and statistical outlier removal (PCL,
// only in cloud_merge.cpp). ROS-agnostic.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace body_scan_merge {

struct MergeOptions {
  // Scan volume: a vertical cylinder about the world z axis (the subject's place). Points
  // outside (the floor, the poles, the room) are dropped.
  double crop_radius = 0.6;   // m
  double crop_min_z = 0.005;  // m: just above the floor
  double crop_max_z = 2.3;    // m
  // Voxel grid leaf (m); 0 = off. Neighbouring pairs overlap, doubling the density there; one
  // point per voxel evens it out (the centroid of the voxel's points and colours).
  double voxel_leaf = 0.0015;
  // Our voxel grid (bucketed sort of the voxel keys, the same grid and centroids as PCL's
  // VoxelGrid, several times faster) or PCL's own (the peer in tests and benchmarks).
  enum class VoxelGrid { kOurs, kPcl };
  VoxelGrid voxel_grid = VoxelGrid::kOurs;
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

// Allocator of the merge's big working buffers. Elements are not value-initialized (each is
// written before it is read), and blocks of 2 MB or more are aligned to and advised as
// transparent huge pages: a first scan touches tens of MB, and 4 kB pages would cost it tens of
// thousands of page faults.
void* allocateWorkBuffer(size_t bytes);
void freeWorkBuffer(void* block);
template <typename T>
struct WorkBufferAllocator {
  using value_type = T;
  WorkBufferAllocator() = default;
  template <typename U>
  WorkBufferAllocator(const WorkBufferAllocator<U>&) {}
  T* allocate(size_t n) { return static_cast<T*>(allocateWorkBuffer(n * sizeof(T))); }
  void deallocate(T* block, size_t) { freeWorkBuffer(block); }
  template <typename U, typename... Args>
  void construct(U* at, Args&&... args) {
    if constexpr (sizeof...(Args) == 0)
      ::new (static_cast<void*>(at)) U;  // default-initialized: no zeroing pass
    else
      ::new (static_cast<void*>(at)) U(std::forward<Args>(args)...);
  }
  template <typename U>
  bool operator==(const WorkBufferAllocator<U>&) const {
    return true;
  }
  template <typename U>
  bool operator!=(const WorkBufferAllocator<U>&) const {
    return false;
  }
};
template <typename T>
using WorkBuffer = std::vector<T, WorkBufferAllocator<T>>;

// The merge with its working buffers kept from one scan to the next (the Merge nodelet keeps
// one): a scan's tens of megabytes are not allocated and page-faulted in again every time.
// Deterministic: the same parts in the same order give the same cloud, bit for bit, on 2
// threads. Not thread-safe: one merge at a time per CloudMerger.
class CloudMerger {
 public:
  // All parts at once: transform and crop on 2 threads, then the filters.
  MergedCloud merge(const std::vector<CloudView>& parts, const MergeOptions& options);

  // Or part by part as they are made (transformed while still in cache): begin(), then
  // addPart(i) once for every i < parts, from any threads (distinct i may run concurrently),
  // then finish(). The same cloud as merge() of the same parts.
  void begin(size_t parts, const MergeOptions& options);
  void addPart(size_t index, const CloudView& part);
  // transform_seconds: the wall time of the addPart calls if known (< 0: their sum).
  MergedCloud finish(double transform_seconds = -1);

  // One point per occupied voxel of a grid of `leaf` anchored like PCL's VoxelGrid (at
  // floor(min / leaf)): the centroid of its points and the mean of their colours, ordered by
  // voxel index (x fastest). `parts`: finite points, 4 floats each (x y z rgb), taken in order
  // as one cloud. The output replaces `xyzrgb`.
  struct Points {
    const float* xyzrgb;
    size_t count;
  };
  void voxelGrid(const std::vector<Points>& parts, double leaf, std::vector<float>& xyzrgb);

 private:
  struct Bounds {  // of a set of points
    Eigen::Array3f min = Eigen::Array3f::Constant(std::numeric_limits<float>::max());
    Eigen::Array3f max = Eigen::Array3f::Constant(std::numeric_limits<float>::lowest());
    void add(const Eigen::Array3f& p) { min = min.min(p), max = max.max(p); }
    void add(const Bounds& other) { min = min.min(other.min), max = max.max(other.max); }
  };
  void voxelGrid(const std::vector<Points>& parts, double leaf, const Bounds& bounds,
                 std::vector<float>& xyzrgb);

  struct Record {  // a point in the voxel sort: its voxel key, then the point itself
    uint32_t key;
    float xyzrgb[4];
  };
  MergeOptions options_;
  std::vector<WorkBuffer<float>> kept_;  // per part: its points in the scan volume
  std::vector<Points> in_volume_;        // per part: the part of kept_ in use
  std::vector<Bounds> bounds_;           // per part: of its points in the scan volume
  std::vector<size_t> valid_;            // per part: its finite points
  std::vector<double> part_seconds_;     // per part: addPart's time
  WorkBuffer<Record> records_;           // every point, grouped by bucket of keys
  WorkBuffer<uint32_t> keys_;            // per point: its voxel key
  std::vector<size_t> bucket_offsets_;   // per chunk of input and bucket: where it goes
  std::vector<float> upper_half_;        // the upper buckets' voxels, before they are appended
};

// A merge with buffers of its own (tests, tools).
MergedCloud mergeClouds(const std::vector<CloudView>& parts, const MergeOptions& options);

// CloudMerger::voxelGrid of one cloud, in place.
void voxelGrid(std::vector<float>& xyzrgb, double leaf);

}  // namespace body_scan_merge
