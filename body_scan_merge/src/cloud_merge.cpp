#include <body_scan_merge/cloud_merge.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <sys/mman.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <thread>

namespace body_scan_merge {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Runs work(0) on a second thread and work(1) on this one.
template <typename Work>
void onTwoThreads(Work work) {
  std::thread second([&] { work(0); });
  work(1);
  second.join();
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

void pclVoxelGrid(std::vector<float>& xyzrgb, double leaf) {
  pcl::VoxelGrid<pcl::PointXYZRGB> grid;
  grid.setInputCloud(toPcl(xyzrgb));
  const auto size = static_cast<float>(leaf);
  grid.setLeafSize(size, size, size);
  pcl::PointCloud<pcl::PointXYZRGB> filtered;
  grid.filter(filtered);
  fromPcl(filtered, xyzrgb);
}

void concatenate(const std::vector<CloudMerger::Points>& parts, std::vector<float>& xyzrgb) {
  size_t total = 0;
  for (const auto& part : parts) total += part.count;
  xyzrgb.resize(4 * total);
  float* out = xyzrgb.data();
  for (const auto& part : parts) out = std::copy(part.xyzrgb, part.xyzrgb + 4 * part.count, out);
}

// The mean of n packed rgb colours summed per channel (floats, as PCL).
float meanColour(float r, float g, float b, float n) {
  const uint32_t rgb = (static_cast<uint32_t>(r / n) << 16) | (static_cast<uint32_t>(g / n) << 8) |
                       static_cast<uint32_t>(b / n);
  float packed;
  std::memcpy(&packed, &rgb, sizeof packed);
  return packed;
}

}  // namespace

void* allocateWorkBuffer(size_t bytes) {
  constexpr size_t kHugePage = size_t{2} << 20;
  void* block = nullptr;
  if (bytes >= kHugePage) {
    const size_t size = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    block = std::aligned_alloc(kHugePage, size);
    if (block) ::madvise(block, size, MADV_HUGEPAGE);  // a hint: without it, 4 kB pages
  } else {
    block = std::malloc(bytes > 0 ? bytes : 1);
  }
  if (!block) throw std::bad_alloc();
  return block;
}

void freeWorkBuffer(void* block) { std::free(block); }

// The voxel keys are PCL's (z-major, 32 bits). Sorting them all at once would scatter the whole
// cloud through memory several times, and the centroids would then gather points at random; a
// scan's points are instead bucketed once by the upper bits of their key (a few hundred points
// per bucket, in input order), and each bucket is sorted and reduced in cache. The buckets are
// ranges of keys, so their outputs concatenate in key order.
void CloudMerger::voxelGrid(const std::vector<Points>& parts, double leaf,
                            std::vector<float>& xyzrgb) {
  Bounds bounds[2];
  onTwoThreads([&](int t) {
    for (size_t part = t; part < parts.size(); part += 2)
      for (size_t i = 0; i < parts[part].count; ++i)
        bounds[t].add(Eigen::Map<const Eigen::Array3f>(parts[part].xyzrgb + 4 * i));
  });
  bounds[0].add(bounds[1]);
  voxelGrid(parts, leaf, bounds[0], xyzrgb);
}

void CloudMerger::voxelGrid(const std::vector<Points>& parts, double leaf, const Bounds& bounds,
                            std::vector<float>& xyzrgb) {
  constexpr size_t kChunk = size_t{1} << 16;  // points per unit of work
  struct Chunk {
    const float* xyzrgb;
    size_t count, first;  // first: index of its first point in the whole cloud
  };
  std::vector<Chunk> chunks;
  size_t n = 0;
  for (const Points& part : parts)
    for (size_t begin = 0; begin < part.count; begin += kChunk) {
      chunks.push_back({part.xyzrgb + 4 * begin, std::min(kChunk, part.count - begin), n});
      n += chunks.back().count;
    }
  if (n == 0) {
    xyzrgb.clear();
    return;
  }
  const float inverse = static_cast<float>(1.0 / leaf);  // PCL works in float, so do we
  const Eigen::Array3i min_b = (bounds.min * inverse).floor().cast<int>();
  const Eigen::Array3i max_b = (bounds.max * inverse).floor().cast<int>();
  const Eigen::Array3i divisions = max_b - min_b + 1;
  if (static_cast<double>(divisions.x()) * divisions.y() * divisions.z() > 4.2e9) {
    concatenate(parts, xyzrgb);
    pclVoxelGrid(xyzrgb, leaf);  // a key would not fit 32 bits: PCL warns and copies
    return;
  }
  const uint32_t stride_y = static_cast<uint32_t>(divisions.x());
  const uint32_t stride_z = stride_y * static_cast<uint32_t>(divisions.y());
  const uint32_t max_key = static_cast<uint32_t>(divisions.x() - 1) +
                           static_cast<uint32_t>(divisions.y() - 1) * stride_y +
                           static_cast<uint32_t>(divisions.z() - 1) * stride_z;
  // About 256 points per bucket if they were spread evenly over the key range.
  const size_t wanted_buckets = std::clamp<size_t>(n / 256, 1, size_t{1} << 16);
  int shift = 0;
  while ((static_cast<size_t>(max_key) >> shift) + 1 > wanted_buckets) ++shift;
  const size_t buckets = (static_cast<size_t>(max_key) >> shift) + 1;

  // Keys and, per chunk, how many of its points fall in each bucket.
  keys_.resize(n);
  bucket_offsets_.assign(chunks.size() * buckets, 0);
  onTwoThreads([&](int t) {
    for (size_t c = t; c < chunks.size(); c += 2) {
      size_t* count = &bucket_offsets_[c * buckets];
      uint32_t* key = &keys_[chunks[c].first];
      for (size_t i = 0; i < chunks[c].count; ++i) {
        const Eigen::Array3i b =
            (Eigen::Map<const Eigen::Array3f>(chunks[c].xyzrgb + 4 * i) * inverse)
                .floor()
                .cast<int>() -
            min_b;
        key[i] = static_cast<uint32_t>(b.x()) + static_cast<uint32_t>(b.y()) * stride_y +
                 static_cast<uint32_t>(b.z()) * stride_z;
        ++count[key[i] >> shift];
      }
    }
  });
  // Where each chunk's points of each bucket go: buckets in key order, within a bucket the
  // chunks in input order (so a voxel's points keep their input order, as in PCL's stable sort).
  std::vector<size_t> bucket_start(buckets + 1);
  size_t position = 0;
  for (size_t b = 0; b < buckets; ++b) {
    bucket_start[b] = position;
    for (size_t c = 0; c < chunks.size(); ++c) {
      const size_t count = bucket_offsets_[c * buckets + b];
      bucket_offsets_[c * buckets + b] = position;
      position += count;
    }
  }
  bucket_start[buckets] = position;
  records_.resize(n);
  onTwoThreads([&](int t) {
    for (size_t c = t; c < chunks.size(); c += 2) {
      size_t* next = &bucket_offsets_[c * buckets];
      const uint32_t* key = &keys_[chunks[c].first];
      for (size_t i = 0; i < chunks[c].count; ++i) {
        Record& record = records_[next[key[i] >> shift]++];
        record.key = key[i];
        std::memcpy(record.xyzrgb, chunks[c].xyzrgb + 4 * i, sizeof record.xyzrgb);
      }
    }
  });

  // Each thread sorts and reduces about half of the points: the buckets below / from `split`.
  const size_t split = static_cast<size_t>(
      std::lower_bound(bucket_start.begin(), bucket_start.end(), n / 2) - bucket_start.begin());
  onTwoThreads([&](int t) {
    std::vector<float>& out = t == 0 ? upper_half_ : xyzrgb;
    out.clear();
    // key << 32 | index in the bucket, sorted by a stable LSD radix sort of the key's bits
    // below `shift` (the bits above are the bucket's): ties keep input order.
    std::vector<uint64_t> order, scratch;
    const size_t first = t == 0 ? split : 0, last = t == 0 ? buckets : split;
    for (size_t b = first; b < last; ++b) {
      const Record* bucket = &records_[bucket_start[b]];
      const size_t size = bucket_start[b + 1] - bucket_start[b];
      order.resize(size), scratch.resize(size);
      for (size_t i = 0; i < size; ++i) order[i] = (uint64_t{bucket[i].key} << 32) | i;
      for (int digit = 32; digit < 32 + shift && size > 1; digit += 8) {
        uint32_t count[257] = {};
        for (const uint64_t v : order) ++count[((v >> digit) & 0xFF) + 1];
        for (int i = 0; i < 256; ++i) count[i + 1] += count[i];
        for (const uint64_t v : order) scratch[count[(v >> digit) & 0xFF]++] = v;
        order.swap(scratch);
      }
      for (size_t begin = 0; begin < size;) {
        const uint64_t voxel = order[begin] >> 32;
        Eigen::Vector3f sum = Eigen::Vector3f::Zero();
        float r = 0, g = 0, b = 0;
        size_t end = begin;
        for (; end < size && (order[end] >> 32) == voxel; ++end) {
          const float* p = bucket[order[end] & 0xFFFFFFFFu].xyzrgb;
          sum += Eigen::Vector3f(p[0], p[1], p[2]);
          uint32_t rgb;
          std::memcpy(&rgb, &p[3], sizeof rgb);
          r += (rgb >> 16) & 0xFF, g += (rgb >> 8) & 0xFF, b += rgb & 0xFF;
        }
        const float count = static_cast<float>(end - begin);
        out.insert(out.end(),
                   {sum.x() / count, sum.y() / count, sum.z() / count, meanColour(r, g, b, count)});
        begin = end;
      }
    }
  });
  xyzrgb.insert(xyzrgb.end(), upper_half_.begin(), upper_half_.end());
}

void voxelGrid(std::vector<float>& xyzrgb, double leaf) {
  const std::vector<float> input = std::move(xyzrgb);
  CloudMerger().voxelGrid({{input.data(), input.size() / 4}}, leaf, xyzrgb);
}

void CloudMerger::begin(size_t parts, const MergeOptions& options) {
  options_ = options;
  if (kept_.size() < parts) kept_.resize(parts);
  in_volume_.assign(parts, Points{nullptr, 0});
  bounds_.assign(parts, Bounds());
  valid_.assign(parts, 0);
  part_seconds_.assign(parts, 0.0);
}

void CloudMerger::addPart(size_t index, const CloudView& part) {
  const auto start = Clock::now();
  const float radius2 = static_cast<float>(options_.crop_radius * options_.crop_radius);
  const auto min_z = static_cast<float>(options_.crop_min_z);
  const auto max_z = static_cast<float>(options_.crop_max_z);
  const float white = meanColour(255, 255, 255, 1);
  const Eigen::Matrix3f rotation = part.world_from_cloud.linear().cast<float>();
  const Eigen::Vector3f translation = part.world_from_cloud.translation().cast<float>();
  // Sized to the points kept, not to the organized cloud: most of a pair's pixels are not in
  // the scan volume, and a buffer for all of them (tens of MB over 12 pairs) would cost the
  // first scan its page faults. Grows by doubling; kept from one scan to the next.
  WorkBuffer<float>& buffer = kept_[index];
  float* out = buffer.data();
  size_t valid = 0, kept = 0;
  for (size_t i = 0; i < part.count; ++i) {
    const float* p = part.points + i * part.stride;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    ++valid;
    const Eigen::Vector3f w = rotation * Eigen::Vector3f(p[0], p[1], p[2]) + translation;
    if (w.x() * w.x() + w.y() * w.y() > radius2 || w.z() < min_z || w.z() > max_z) continue;
    if (4 * (kept + 1) > buffer.size()) {
      buffer.resize(std::max<size_t>(4 * 16384, 2 * buffer.size()));
      out = buffer.data();
    }
    float* o = out + 4 * kept++;
    o[0] = w.x(), o[1] = w.y(), o[2] = w.z();
    o[3] = part.rgb_offset >= 0 ? p[part.rgb_offset] : white;
    bounds_[index].add(w.array());
  }
  valid_[index] = valid;
  in_volume_[index] = {out, kept};
  part_seconds_[index] = secondsSince(start);
}

MergedCloud CloudMerger::merge(const std::vector<CloudView>& parts, const MergeOptions& options) {
  const auto start = Clock::now();
  begin(parts.size(), options);
  onTwoThreads([&](int t) {
    for (size_t index = t; index < parts.size(); index += 2) addPart(index, parts[index]);
  });
  return finish(secondsSince(start));
}

MergedCloud CloudMerger::finish(double transform_seconds) {
  MergedCloud merged;
  merged.valid_per_part = valid_;
  for (const Points& part : in_volume_) merged.in_volume_per_part.push_back(part.count);
  auto start = Clock::now();
  const MergeOptions& options = options_;
  const bool ours = options.voxel_leaf > 0 && options.voxel_grid == MergeOptions::VoxelGrid::kOurs;
  if (!ours) concatenate(in_volume_, merged.xyzrgb);
  if (transform_seconds >= 0) {
    merged.stage_seconds.emplace_back("transform+crop", transform_seconds + secondsSince(start));
  } else {
    double sum = 0;
    for (double seconds : part_seconds_) sum += seconds;
    merged.stage_seconds.emplace_back("transform+crop (as the pairs came, summed)",
                                      sum + secondsSince(start));
  }
  if (options.voxel_leaf > 0) {
    start = Clock::now();
    if (ours) {
      Bounds all;
      for (const Bounds& part : bounds_) all.add(part);
      voxelGrid(in_volume_, options.voxel_leaf, all, merged.xyzrgb);
    } else {
      pclVoxelGrid(merged.xyzrgb, options.voxel_leaf);
    }
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

MergedCloud mergeClouds(const std::vector<CloudView>& parts, const MergeOptions& options) {
  return CloudMerger().merge(parts, options);
}

}  // namespace body_scan_merge
