#include <body_scan_merge/cloud_merge.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <thread>
#include <tuple>

using namespace body_scan_merge;

namespace {

float packed(uint32_t rgb) {
  float value;
  std::memcpy(&value, &rgb, sizeof value);
  return value;
}

// Points on a vertical cylinder of radius r about the z axis (a torso-like surface), stride 4.
std::vector<float> cylinderPoints(double r, int count, uint32_t seed, double noise = 0.0) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), height(0.5, 1.5);
  std::normal_distribution<double> jitter(0.0, noise > 0 ? noise : 1e-12);
  std::vector<float> points;
  for (int i = 0; i < count; ++i) {
    const double a = angle(generator), rr = r + (noise > 0 ? jitter(generator) : 0.0);
    points.insert(points.end(),
                  {static_cast<float>(rr * std::cos(a)), static_cast<float>(rr * std::sin(a)),
                   static_cast<float>(height(generator)), packed(0x804020)});
  }
  return points;
}

}  // namespace

TEST(CloudMerge, PointsAreTransformedToTheWorldAndCroppedToTheScanVolume) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Camera 1 m in front of the subject looking back along -x (optical z = world -x).
  Eigen::Isometry3d world_from_camera = Eigen::Isometry3d::Identity();
  world_from_camera.linear() << 0, 0, -1, 1, 0, 0, 0, -1, 0;  // columns: optical x, y, z
  world_from_camera.translation() << 1.0, 0.0, 1.0;
  const std::vector<float> points = {
      0.1f, 0.2f, 0.9f, packed(0x112233),  // in front of the camera: inside the volume
      nan,  nan,  nan,  packed(0),         // no point
      0.0f, 0.0f, 3.0f, packed(0),         // 2 m behind the subject: outside the radius
      0.0f, 1.2f, 1.0f, packed(0)};        // below the floor: cropped
  MergeOptions options;
  options.voxel_leaf = 0;
  const MergedCloud merged =
      mergeClouds({CloudView{points.data(), 4, 4, 3, world_from_camera}}, options);
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_EQ(merged.valid_per_part, std::vector<size_t>{3});
  EXPECT_EQ(merged.in_volume_per_part, std::vector<size_t>{1});
  const Eigen::Vector3d expected = world_from_camera * Eigen::Vector3d(0.1, 0.2, 0.9);
  EXPECT_NEAR(merged.xyzrgb[0], expected.x(), 1e-6);
  EXPECT_NEAR(merged.xyzrgb[1], expected.y(), 1e-6);
  EXPECT_NEAR(merged.xyzrgb[2], expected.z(), 1e-6);
  uint32_t rgb;
  std::memcpy(&rgb, &merged.xyzrgb[3], sizeof rgb);
  EXPECT_EQ(rgb, 0x112233u);
}

TEST(CloudMerge, TheVoxelGridKeepsOnePointPerOccupiedVoxel) {
  // Two overlapping clouds of one surface (as neighbouring pairs give) -> one point per voxel.
  const std::vector<float> a = cylinderPoints(0.15, 40000, 1), b = cylinderPoints(0.15, 40000, 2);
  MergeOptions options;
  options.voxel_leaf = 0.01;
  const MergedCloud merged =
      mergeClouds({CloudView{a.data(), 40000, 4, 3, Eigen::Isometry3d::Identity()},
                   CloudView{b.data(), 40000, 4, 3, Eigen::Isometry3d::Identity()}},
                  options);
  // Independent count of occupied voxels: the distinct integer cells floor(p / leaf), with
  // 1 / leaf in float as PCL computes it (its grid origin floor(min / leaf) is a whole number of
  // cells, so it does not change which points share a cell). Exact, not approximate.
  const float inverse = 1.f / 0.01f;
  std::set<std::tuple<int, int, int>> voxels;
  for (const auto* cloud : {&a, &b})
    for (size_t i = 0; i < cloud->size(); i += 4)
      voxels.emplace(static_cast<int>(std::floor((*cloud)[i] * inverse)),
                     static_cast<int>(std::floor((*cloud)[i + 1] * inverse)),
                     static_cast<int>(std::floor((*cloud)[i + 2] * inverse)));
  EXPECT_EQ(merged.size(), voxels.size());
  EXPECT_LT(merged.size(), 60000u);
  // Every output point stays on the surface (centroids of nearby surface points).
  for (size_t i = 0; i < merged.xyzrgb.size(); i += 4)
    ASSERT_NEAR(std::hypot(merged.xyzrgb[i], merged.xyzrgb[i + 1]), 0.15, 0.003);
}

TEST(CloudMerge, OurVoxelGridGivesPclsPointsAndColours) {
  // Two overlapping noisy clouds of different colours, as neighbouring pairs give.
  std::vector<float> cloud = cylinderPoints(0.15, 60000, 6, 0.001);
  std::vector<float> other = cylinderPoints(0.15, 60000, 7, 0.001);
  for (size_t i = 3; i < other.size(); i += 4) other[i] = packed(0x20C0FF);
  cloud.insert(cloud.end(), other.begin(), other.end());
  MergeOptions ours, pcl;
  ours.voxel_leaf = pcl.voxel_leaf = 0.0015;
  pcl.voxel_grid = MergeOptions::VoxelGrid::kPcl;
  const CloudView view{cloud.data(), cloud.size() / 4, 4, 3, Eigen::Isometry3d::Identity()};
  const MergedCloud a = mergeClouds({view}, ours), b = mergeClouds({view}, pcl);
  ASSERT_EQ(a.size(), b.size());
  double worst = 0;
  int colour_off = 0;
  for (size_t i = 0; i < a.xyzrgb.size(); i += 4) {
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, static_cast<double>(std::abs(a.xyzrgb[i + k] - b.xyzrgb[i + k])));
    uint32_t ca, cb;
    std::memcpy(&ca, &a.xyzrgb[i + 3], 4);
    std::memcpy(&cb, &b.xyzrgb[i + 3], 4);
    for (int shift : {0, 8, 16})  // float sums in another order: at most one level apart
      colour_off += std::abs(static_cast<int>((ca >> shift) & 0xFF) -
                             static_cast<int>((cb >> shift) & 0xFF)) > 1;
  }
  std::cout << "[ figure ] voxel grid of " << cloud.size() / 4 << " points: " << a.size()
            << " voxels, ours vs PCL largest coordinate difference " << worst << " m; "
            << a.stage_seconds.back().second * 1000 << " ms vs "
            << b.stage_seconds.back().second * 1000 << " ms\n";
  EXPECT_LT(worst, 1e-6);
  EXPECT_EQ(colour_off, 0);
}

TEST(CloudMerge, OutlierRemovalDropsIsolatedPointsAndKeepsTheSurface) {
  std::vector<float> points = cylinderPoints(0.15, 20000, 3, 0.0005);
  std::mt19937 generator(9);
  std::uniform_real_distribution<float> anywhere(-0.5f, 0.5f), height(0.2f, 2.0f);
  const int outliers = 200;
  for (int i = 0; i < outliers; ++i)  // stray points in the air around the subject
    points.insert(points.end(),
                  {anywhere(generator), anywhere(generator), height(generator), packed(0xFF0000)});
  MergeOptions options;
  options.voxel_leaf = 0;
  options.outlier_removal = true;
  const MergedCloud merged = mergeClouds(
      {CloudView{points.data(), points.size() / 4, 4, 3, Eigen::Isometry3d::Identity()}}, options);
  int kept_outliers = 0, kept_surface = 0;
  for (size_t i = 0; i < merged.xyzrgb.size(); i += 4) {
    const bool on_surface =
        std::abs(std::hypot(merged.xyzrgb[i], merged.xyzrgb[i + 1]) - 0.15) < 0.005;
    (on_surface ? kept_surface : kept_outliers)++;
  }
  std::cout << "[ figure ] outlier removal kept " << kept_outliers << " of " << outliers
            << " stray points and " << kept_surface << " of 20000 surface points\n";
  EXPECT_LE(kept_outliers, outliers / 20);
  EXPECT_GE(kept_surface, 19800);
}

TEST(CloudMerge, TheSamePartsGiveTheSameCloudBitForBit) {
  const std::vector<float> a = cylinderPoints(0.15, 30000, 4), b = cylinderPoints(0.16, 30000, 5);
  MergeOptions options;
  options.voxel_leaf = 0.004;
  options.outlier_removal = true;
  const std::vector<CloudView> parts = {
      CloudView{a.data(), 30000, 4, 3, Eigen::Isometry3d::Identity()},
      CloudView{b.data(), 30000, 4, 3, Eigen::Isometry3d::Identity()}};
  EXPECT_EQ(mergeClouds(parts, options).xyzrgb, mergeClouds(parts, options).xyzrgb);
}

TEST(CloudMerge, PartsAddedOneByOneFromTwoThreadsGiveTheSameCloud) {
  std::vector<std::vector<float>> clouds;
  std::vector<CloudView> parts;
  for (uint32_t seed = 1; seed <= 5; ++seed) clouds.push_back(cylinderPoints(0.15, 20000, seed));
  for (size_t i = 0; i < clouds.size(); ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(0.01 * i, 0, 0.1);  // distinct poses per part
    parts.push_back(CloudView{clouds[i].data(), 20000, 4, 3, pose});
  }
  MergeOptions options;
  options.voxel_leaf = 0.002;
  CloudMerger merger;
  const MergedCloud all_at_once = merger.merge(parts, options);
  merger.begin(parts.size(), options);
  std::thread odd([&] {  // in the opposite order to the part index
    for (size_t i = parts.size() - (parts.size() % 2 == 0 ? 1 : 2);; i -= 2) {
      merger.addPart(i, parts[i]);
      if (i < 2) break;
    }
  });
  for (size_t i = 0; i < parts.size(); i += 2) merger.addPart(i, parts[i]);
  odd.join();
  const MergedCloud one_by_one = merger.finish();
  EXPECT_GT(one_by_one.size(), 50000u);
  EXPECT_EQ(one_by_one.xyzrgb, all_at_once.xyzrgb);
  EXPECT_EQ(one_by_one.valid_per_part, all_at_once.valid_per_part);
  EXPECT_EQ(one_by_one.in_volume_per_part, all_at_once.in_volume_per_part);
}
