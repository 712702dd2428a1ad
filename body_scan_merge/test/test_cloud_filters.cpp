#include <body_scan_merge/cloud_filters.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <tuple>

using namespace body_scan;

namespace {

float rgb(uint32_t packed) {
  float value;
  std::memcpy(&value, &packed, sizeof value);
  return value;
}

// Points on a sphere of radius r about c (a body-sized surface), random but reproducible.
std::vector<ColouredPoint> sphere(const Eigen::Vector3f& c, float r, size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal;
  std::vector<ColouredPoint> points;
  for (size_t i = 0; i < n; ++i) {
    Eigen::Vector3f d(normal(rng), normal(rng), normal(rng));
    const Eigen::Vector3f p = c + r * d.normalized();
    points.push_back({p.x(), p.y(), p.z(), rgb(0x00ff8040)});
  }
  return points;
}

}  // namespace

TEST(CloudFilters, TransformAndCropMatchesAnalyticTransform) {
  // Camera 1.5 m in front of the axis, at 1 m height, looking back at it (optical z -> -x).
  Eigen::Isometry3f world_from_cloud = Eigen::Isometry3f::Identity();
  world_from_cloud.linear() << 0, 0, -1,  //
      -1, 0, 0,                           //
      0, -1, 0;
  world_from_cloud.translation() << 1.5f, 0.f, 1.f;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Each point: x, y, z, rgb (stride 4, as Triangulate's cloud).
  const std::vector<float> cloud = {
      0.1f,  0.2f,  1.5f, rgb(0x112233),  // world (1.5-1.5, -0.1, 1-0.2) = (0, -0.1, 0.8): kept
      nan,   nan,   nan,  rgb(0),         // invalid: skipped, not counted
      0.0f,  0.0f,  0.5f, rgb(0x445566),  // world (1.0, 0, 1): outside r 0.6
      0.0f,  0.99f, 1.5f, rgb(0x778899),  // world (0, 0, 0.01): above z_min 0.005, kept
      0.0f,  1.0f,  1.5f, rgb(0xaabbcc),  // world z = 0: the floor, cropped
      -0.3f, -1.3f, 1.2f, rgb(0xddeeff),  // world (0.3, 0.3, 2.3): above z_max
  };
  std::vector<ColouredPoint> out;
  const size_t valid =
      transformAndCrop(cloud.data(), cloud.size() / 4, 4, world_from_cloud, ScanVolume(), out);
  EXPECT_EQ(valid, 5u);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0].x, 0.0, 1e-6);
  EXPECT_NEAR(out[0].y, -0.1, 1e-6);
  EXPECT_NEAR(out[0].z, 0.8, 1e-6);
  EXPECT_EQ(std::memcmp(&out[0].rgb, &cloud[3], 4), 0);  // colour carried unchanged
  EXPECT_NEAR(out[1].x, 0.0, 1e-6);
  EXPECT_NEAR(out[1].z, 0.01, 1e-6);
  // Random points: the same against Eigen's analytic transform.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<float> random;
  for (int i = 0; i < 1000; ++i) random.insert(random.end(), {u(rng), u(rng), 1.5f + u(rng), 0});
  out.clear();
  ScanVolume everything;
  everything.radius = 100;
  everything.z_min = -100;
  everything.z_max = 100;
  ASSERT_EQ(transformAndCrop(random.data(), 1000, 4, world_from_cloud, everything, out), 1000u);
  ASSERT_EQ(out.size(), 1000u);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3f expected =
        world_from_cloud.linear() *
            Eigen::Vector3f(random[4 * i], random[4 * i + 1], random[4 * i + 2]) +
        world_from_cloud.translation();
    EXPECT_LT((Eigen::Vector3f(out[i].x, out[i].y, out[i].z) - expected).norm(), 1e-6);
  }
}

TEST(CloudFilters, VoxelGridKeepsOnePointPerOccupiedVoxel) {
  auto points = sphere({0.1f, -0.2f, 1.0f}, 0.15f, 200000, 1);
  const double leaf = 0.004;
  // Independent count: the distinct integer cells floor(p / leaf) that hold a point.
  std::set<std::tuple<int, int, int>> cells;
  const float inverse = 1.f / static_cast<float>(leaf);  // in float, as PCL
  for (const auto& p : points)
    cells.emplace(static_cast<int>(std::floor(p.x * inverse)),
                  static_cast<int>(std::floor(p.y * inverse)),
                  static_cast<int>(std::floor(p.z * inverse)));
  voxelGrid(points, leaf);
  EXPECT_EQ(points.size(), cells.size());
  // Every output point is a centroid of surface points: within a voxel diagonal of the sphere.
  for (const auto& p : points) {
    const float r = (Eigen::Vector3f(p.x, p.y, p.z) - Eigen::Vector3f(0.1f, -0.2f, 1.0f)).norm();
    EXPECT_NEAR(r, 0.15, leaf * std::sqrt(3.0));
  }
}

TEST(CloudFilters, OutlierRemovalRemovesInjectedOutliersKeepsSurface) {
  const Eigen::Vector3f centre(0, 0, 1);
  auto points = sphere(centre, 0.2f, 20000, 2);
  const size_t surface = points.size();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  size_t injected = 0;
  while (injected < 200) {  // isolated points at least 5 cm off the surface
    const Eigen::Vector3f p = centre + Eigen::Vector3f(u(rng), u(rng), u(rng));
    if (std::abs((p - centre).norm() - 0.2f) < 0.05f) continue;
    points.push_back({p.x(), p.y(), p.z(), 0});
    ++injected;
  }
  removeOutliers(points, 20, 1.0);
  size_t outliers_left = 0, surface_left = 0;
  for (const auto& p : points) {
    if (std::abs((Eigen::Vector3f(p.x, p.y, p.z) - centre).norm() - 0.2f) < 1e-4f)
      ++surface_left;
    else
      ++outliers_left;
  }
  EXPECT_EQ(outliers_left, 0u);
  EXPECT_GT(surface_left, surface * 0.95);  // the surface stays
}
