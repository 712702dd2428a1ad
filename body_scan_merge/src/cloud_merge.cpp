#include <body_scan_merge/cloud_merge.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <thread>

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

// Stable LSD radix sort of (key << 32 | index) values by their key (the upper 32 bits).
void sortByKey(std::vector<uint64_t>& values) {
  uint64_t largest = 0;
  for (uint64_t v : values) largest = std::max(largest, v >> 32);
  std::vector<uint64_t> scratch(values.size());
  for (int shift = 32; shift < 64 && (largest >> (shift - 32)) > 0; shift += 8) {
    size_t count[257] = {};
    for (uint64_t v : values) ++count[((v >> shift) & 0xFF) + 1];
    for (int i = 0; i < 256; ++i) count[i + 1] += count[i];
    for (uint64_t v : values) scratch[count[(v >> shift) & 0xFF]++] = v;
    values.swap(scratch);
  }
}

void pclVoxelGrid(std::vector<float>& xyzrgb, double leaf) {
  pcl::VoxelGrid<pcl::PointXYZRGB> grid;
  grid.setInputCloud(toPcl(xyzrgb));
  const auto size = static_cast<float>(leaf);
  grid.setLeafSize(size, size, size);
  pcl::PointCloud<pcl::PointXYZRGB> filtered;
  grid.filter(filtered);
  fromPcl(filtered, xyzrgb);
}

}  // namespace

void voxelGrid(std::vector<float>& xyzrgb, double leaf) {
  const size_t n = xyzrgb.size() / 4;
  if (n == 0) return;
  const float inverse = static_cast<float>(1.0 / leaf);  // PCL works in float, so do we
  Eigen::Array3f min_p = Eigen::Array3f::Constant(std::numeric_limits<float>::max());
  Eigen::Array3f max_p = -min_p;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Array3f p(xyzrgb[4 * i], xyzrgb[4 * i + 1], xyzrgb[4 * i + 2]);
    min_p = min_p.min(p), max_p = max_p.max(p);
  }
  const Eigen::Array3i min_b = (min_p * inverse).floor().cast<int>();
  const Eigen::Array3i max_b = (max_p * inverse).floor().cast<int>();
  const Eigen::Array3i divisions = max_b - min_b + 1;
  if (static_cast<double>(divisions.x()) * divisions.y() * divisions.z() > 4.2e9) {
    pclVoxelGrid(xyzrgb, leaf);  // a key would not fit 32 bits: PCL warns and copies
    return;
  }
  const uint64_t stride_y = static_cast<uint64_t>(divisions.x());
  const uint64_t stride_z = stride_y * static_cast<uint64_t>(divisions.y());
  // Keys are z-major: the lower and upper halves of the z range are independent, one per
  // thread, and their outputs concatenate in key order.
  const uint64_t split = stride_z * static_cast<uint64_t>(divisions.z() / 2);
  std::vector<uint64_t> halves[2];
  halves[0].reserve(n / 2 + n / 8), halves[1].reserve(n / 2 + n / 8);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Array3i b =
        (Eigen::Array3f(xyzrgb[4 * i], xyzrgb[4 * i + 1], xyzrgb[4 * i + 2]) * inverse)
            .floor()
            .cast<int>() -
        min_b;
    const uint64_t key = b.x() + b.y() * stride_y + b.z() * stride_z;
    halves[key >= split].push_back((key << 32) | i);
  }
  std::vector<float> out[2];
  auto reduce = [&](int half) {
    std::vector<uint64_t>& keyed = halves[half];
    sortByKey(keyed);
    out[half].reserve(4 * keyed.size());
    for (size_t first = 0; first < keyed.size();) {
      size_t last = first;
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      float r = 0, g = 0, b = 0;
      for (; last < keyed.size() && (keyed[last] >> 32) == (keyed[first] >> 32); ++last) {
        const size_t i = keyed[last] & 0xFFFFFFFFu;
        sum += Eigen::Vector3f(xyzrgb[4 * i], xyzrgb[4 * i + 1], xyzrgb[4 * i + 2]);
        uint32_t rgb;
        std::memcpy(&rgb, &xyzrgb[4 * i + 3], sizeof rgb);
        r += (rgb >> 16) & 0xFF, g += (rgb >> 8) & 0xFF, b += rgb & 0xFF;
      }
      const float count = static_cast<float>(last - first);
      const uint32_t rgb = (static_cast<uint32_t>(r / count) << 16) |
                           (static_cast<uint32_t>(g / count) << 8) |
                           static_cast<uint32_t>(b / count);
      float packed;
      std::memcpy(&packed, &rgb, sizeof packed);
      out[half].insert(out[half].end(),
                       {sum.x() / count, sum.y() / count, sum.z() / count, packed});
      first = last;
    }
  };
  std::thread upper(reduce, 1);
  reduce(0);
  upper.join();
  out[0].insert(out[0].end(), out[1].begin(), out[1].end());
  xyzrgb.swap(out[0]);
}

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
  // Each part into its own buffer (2 threads), then concatenated in part order.
  std::vector<std::vector<float>> kept(parts.size());
  merged.valid_per_part.assign(parts.size(), 0);
  merged.in_volume_per_part.assign(parts.size(), 0);
  auto transform = [&](size_t index) {
    const CloudView& part = parts[index];
    const Eigen::Matrix3f rotation = part.world_from_cloud.linear().cast<float>();
    const Eigen::Vector3f translation = part.world_from_cloud.translation().cast<float>();
    std::vector<float>& out = kept[index];
    out.reserve(4 * part.count / 2);
    size_t valid = 0;
    for (size_t i = 0; i < part.count; ++i) {
      const float* p = part.points + i * part.stride;
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
      ++valid;
      const Eigen::Vector3f w = rotation * Eigen::Vector3f(p[0], p[1], p[2]) + translation;
      if (w.x() * w.x() + w.y() * w.y() > radius2 || w.z() < options.crop_min_z ||
          w.z() > options.crop_max_z)
        continue;
      out.insert(out.end(),
                 {w.x(), w.y(), w.z(), part.rgb_offset >= 0 ? p[part.rgb_offset] : white});
    }
    merged.valid_per_part[index] = valid;
    merged.in_volume_per_part[index] = out.size() / 4;
  };
  std::thread second([&] {
    for (size_t i = 1; i < parts.size(); i += 2) transform(i);
  });
  for (size_t i = 0; i < parts.size(); i += 2) transform(i);
  second.join();
  size_t total = 0;
  for (const auto& part : kept) total += part.size();
  merged.xyzrgb.reserve(total);
  for (const auto& part : kept) merged.xyzrgb.insert(merged.xyzrgb.end(), part.begin(), part.end());
  merged.stage_seconds.emplace_back("transform+crop", secondsSince(start));

  if (options.voxel_leaf > 0 && merged.size() > 0) {
    start = Clock::now();
    if (options.voxel_grid == MergeOptions::VoxelGrid::kPcl)
      pclVoxelGrid(merged.xyzrgb, options.voxel_leaf);
    else
      voxelGrid(merged.xyzrgb, options.voxel_leaf);
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
