// PCA body axes (thesis 5.5.1, eq 5.4) and front/back disambiguation from the feet.
#include <body_gait_model/body_axes.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "order_statistics.h"

namespace body_gait_model {
namespace {

constexpr size_t kMinimumPoints = 1000;

struct Moments {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  size_t count = 0;
  void add(const Eigen::Vector3d& point) {
    sum += point;
    outer += point * point.transpose();
    ++count;
  }
  Eigen::Vector3d mean() const { return sum / double(count); }
  Eigen::Matrix3d covariance() const {
    const Eigen::Vector3d m = mean();
    return outer / double(count) - m * m.transpose();
  }
};

// Height above the lowest point of the highest horizontal slice (1 cm) at least
// options.shoulder_width * body_height wide in some direction (2nd to 98th percentile of the
// points' projections on eight horizontal directions), searched from the top down to
// shoulder_band_low: the top of the shoulders, below the narrower head and neck. Returns
// options.shoulder_top * body_height if no slice is that wide.
double shoulderTop(const Cloud& cloud, const Eigen::Vector3d& centroid, const Eigen::Vector3d& up,
                   const Eigen::Vector3d& u, double lowest, double body_height,
                   const BodyAxesOptions& options) {
  constexpr double kSlice = 0.01;
  constexpr int kDirections = 8;
  const Eigen::Vector3d v = up.cross(u);
  const double floor_of_search = options.shoulder_band_low * body_height;
  const int slices = int(std::ceil((body_height - floor_of_search) / kSlice)) + 1;
  std::vector<std::vector<Eigen::Vector2d>> planar(std::max(slices, 1));
  for (const auto& point : cloud) {
    const Eigen::Vector3d offset = point - centroid;
    const double above_floor = offset.dot(up) - lowest;
    if (above_floor < floor_of_search) continue;
    const int slice = std::min(int((body_height - above_floor) / kSlice), slices - 1);
    planar[slice].emplace_back(offset.dot(u), offset.dot(v));
  }
  std::vector<double> projections;
  for (int slice = 0; slice < slices; ++slice) {
    if (planar[slice].size() < 20) continue;
    double widest = 0;
    for (int k = 0; k < kDirections; ++k) {
      const double angle = k * 3.141592653589793 / kDirections;
      const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
      projections.clear();
      for (const auto& p : planar[slice]) projections.push_back(p.dot(direction));
      const size_t low = projections.size() / 50, high = projections.size() - 1 - low;
      std::nth_element(projections.begin(), projections.begin() + low, projections.end());
      const double low_value = projections[low];
      std::nth_element(projections.begin(), projections.begin() + high, projections.end());
      widest = std::max(widest, projections[high] - low_value);
    }
    if (widest >= options.shoulder_width * body_height) return body_height - (slice + 0.5) * kSlice;
  }
  return options.shoulder_top * body_height;
}

}  // namespace

BodyAxes estimateBodyAxes(const Cloud& cloud, const BodyAxesOptions& options) {
  if (cloud.size() < kMinimumPoints)
    throw std::invalid_argument(
        "body axes: the cloud has " + std::to_string(cloud.size()) +
        " points; a whole-body scan needs >= " + std::to_string(kMinimumPoints) +
        " (check that every pair captured and the merge kept them)");
  // Step 1 (5.5.1): centroid e_0 and vertical axis e_1 from the whole body.
  Moments all;
  for (const auto& point : cloud) all.add(point);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> whole(all.covariance());
  BodyAxes result;
  result.centroid = all.mean();
  Eigen::Vector3d up = whole.eigenvectors().col(2);  // largest eigenvalue
  if (up.z() < 0) up = -up;
  if (up.z() < 0.5)
    throw std::invalid_argument(
        "body axes: the cloud's longest axis is not vertical (it leans by more than 60 "
        "degrees); the fitter expects a standing subject in the scanner's floor frame (z up)");
  result.pca_vertical = up;
  if (options.vertical_from_floor) up = Eigen::Vector3d::UnitZ();

  double lowest = 1e9, highest = -1e9;
  for (const auto& point : cloud) {
    const double height = (point - result.centroid).dot(up);
    lowest = std::min(lowest, height);
    highest = std::max(highest, height);
  }
  const double body_height = highest - lowest;

  // Step 2: coronal / sagittal axes from the horizontal spread of the torso's top, the shoulder
  // girdle: the widest, flattest cross-section of the torso, where swinging arms have not yet
  // moved away from it. Projected onto the
  // plane normal to e_1 so that the frame stays orthonormal.
  const Eigen::Vector3d seed =
      std::abs(up.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d u = up.cross(seed).normalized(), v = up.cross(u);
  // The band is placed below the shoulders' top, found from above as the first slice as wide as
  // shoulders: the cloud's top (a crown above the highest viewpoints may be missing) would move
  // a band at a fixed fraction of the measured height down onto the chest and the swinging arms.
  const double shoulder_shift =
      shoulderTop(cloud, result.centroid, up, u, lowest, body_height, options) -
      options.shoulder_top * body_height;
  result.shoulder_top = lowest + options.shoulder_top * body_height + shoulder_shift;
  // The torso's own points in the band: per radial sector around the band's centre, only those
  // within kSectorDepth of the sector's closest point (as the cross-sections of 5.5.2 do), so
  // that arms hanging outside the torso do not skew the axes.
  std::vector<Eigen::Vector2d> band;
  Eigen::Vector2d band_centre = Eigen::Vector2d::Zero();
  for (const auto& point : cloud) {
    const Eigen::Vector3d offset = point - result.centroid;
    const double above_floor = offset.dot(up) - lowest - shoulder_shift;
    if (above_floor < options.shoulder_band_low * body_height ||
        above_floor > options.shoulder_band_high * body_height)
      continue;
    band.emplace_back(offset.dot(u), offset.dot(v));
    band_centre += band.back();
  }
  if (band.size() < 100)
    throw std::invalid_argument(
        "body axes: only " + std::to_string(band.size()) +
        " points at shoulder height; the upper torso is missing from the cloud");
  band_centre /= double(band.size());
  constexpr int kSectors = 36;
  constexpr double kSectorDepth = 0.03;
  constexpr double kTwoPi = 6.283185307179586;
  auto sectorOf = [&](const Eigen::Vector2d& planar) {
    const Eigen::Vector2d d = planar - band_centre;
    const int sector = int((std::atan2(d.y(), d.x()) + kTwoPi / 2) / kTwoPi * kSectors);
    return std::clamp(sector, 0, kSectors - 1);
  };
  std::vector<double> closest(kSectors, 1e9);
  for (const auto& planar : band)
    closest[sectorOf(planar)] = std::min(closest[sectorOf(planar)], (planar - band_centre).norm());
  // Each sector's kept points stand for the outline by their mean, one vertex per sector: the
  // moments of the outline, not of the points, whose density varies over the surface with the
  // viewpoints (the full scanner sees a turned subject's shoulders obliquely from some poles).
  std::vector<Eigen::Vector2d> sector_sum(kSectors, Eigen::Vector2d::Zero());
  std::vector<int> sector_count(kSectors, 0);
  for (const auto& planar : band) {
    const int sector = sectorOf(planar);
    if ((planar - band_centre).norm() > closest[sector] + kSectorDepth) continue;
    sector_sum[sector] += planar;
    ++sector_count[sector];
  }
  Eigen::Vector2d band_sum = Eigen::Vector2d::Zero();
  Eigen::Matrix2d band_outer = Eigen::Matrix2d::Zero();
  int band_count = 0;
  for (int sector = 0; sector < kSectors; ++sector) {
    if (sector_count[sector] == 0) continue;
    const Eigen::Vector2d vertex = sector_sum[sector] / sector_count[sector];
    band_sum += vertex;
    band_outer += vertex * vertex.transpose();
    ++band_count;
  }
  const Eigen::Vector2d band_mean = band_sum / band_count;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> torso(band_outer / band_count -
                                                       band_mean * band_mean.transpose());
  const Eigen::Vector2d coronal = torso.eigenvectors().col(1);  // widest: shoulder to shoulder
  Eigen::Vector3d left = (coronal.x() * u + coronal.y() * v).normalized();
  Eigen::Vector3d front = left.cross(up);  // so that left = up x front

  // Front/back: per leg (split by the tentative coronal axis), extrapolate the lower shank's
  // centre line down to the foot and measure how far the foot's points lie ahead of it along
  // `front`. Heights count from each leg's own lowest point (a leg may be lifted off the floor),
  // a few stray points below it ignored; the shank's centre is the band's median, so that the
  // other leg's foot swinging close by does not pull it; only foot points within foot_radius of
  // the line count; each leg weighs the same (a leg's point count varies with its tilt).
  std::vector<double> side_heights[2];
  for (const auto& point : cloud) {
    const Eigen::Vector3d offset = point - result.centroid;
    const double height = offset.dot(up);
    if (height - lowest < options.shank_band_high * body_height)
      side_heights[offset.dot(left) > 0 ? 1 : 0].push_back(height);
  }
  double side_lowest[2] = {lowest, lowest};
  for (int side = 0; side < 2; ++side) {
    std::vector<double>& heights = side_heights[side];
    if (heights.empty()) continue;
    // The lowest but a few stray points.
    const size_t index = heights.size() / 1000;
    std::nth_element(heights.begin(), heights.begin() + index, heights.end());
    side_lowest[side] = heights[index];
  }
  const double mid = (options.shank_band_low + options.shank_band_high) / 2 * body_height;
  std::vector<Eigen::Vector3d> shank_band[2][2];  // [side][lower, upper half]
  for (const auto& point : cloud) {
    const Eigen::Vector3d offset = point - result.centroid;
    const int side = offset.dot(left) > 0 ? 1 : 0;
    const double above_floor = offset.dot(up) - side_lowest[side];
    if (above_floor < options.shank_band_low * body_height ||
        above_floor >= options.shank_band_high * body_height)
      continue;
    shank_band[side][above_floor >= mid ? 1 : 0].emplace_back(offset.dot(left), above_floor,
                                                              offset.dot(front));
  }
  bool has_line[2] = {false, false};
  Eigen::Vector3d line_low[2], line_high[2];
  for (int side = 0; side < 2; ++side) {
    if (shank_band[side][0].size() < 20 || shank_band[side][1].size() < 20) continue;
    line_low[side] = componentMedian(shank_band[side][0]);
    line_high[side] = componentMedian(shank_band[side][1]);
    has_line[side] = std::abs(line_high[side].y() - line_low[side].y()) > 1e-6;
  }
  double reach_sum[2] = {0, 0};
  int reach_count[2] = {0, 0};
  for (const auto& point : cloud) {
    const Eigen::Vector3d offset = point - result.centroid;
    const int side = offset.dot(left) > 0 ? 1 : 0;
    if (!has_line[side]) continue;
    const double above_floor = offset.dot(up) - side_lowest[side];
    if (above_floor >= options.foot_band * body_height) continue;
    const Eigen::Vector3d &a = line_low[side], &b = line_high[side];
    const double t = (above_floor - a.y()) / (b.y() - a.y());
    const Eigen::Vector2d on_line(a.x() + (b.x() - a.x()) * t, a.z() + (b.z() - a.z()) * t);
    const Eigen::Vector2d planar(offset.dot(left), offset.dot(front));
    if ((planar - on_line).norm() > options.foot_radius * body_height) continue;
    reach_sum[side] += planar.y() - on_line.y();
    ++reach_count[side];
  }
  double reach = 0;
  int legs = 0;
  for (int side = 0; side < 2; ++side)
    if (reach_count[side] >= 20) {
      reach += reach_sum[side] / reach_count[side];
      ++legs;
    }
  result.foot_reach = legs > 0 ? reach / legs : 0.0;
  if (result.foot_reach < 0) {
    front = -front;
    left = -left;
    result.foot_reach = -result.foot_reach;
  }
  result.axes.col(0) = left;
  result.axes.col(1) = up;
  result.axes.col(2) = front;
  result.lowest = lowest;
  result.highest = highest;
  result.stature = std::max(body_height, (result.shoulder_top - lowest) / options.shoulder_top);
  return result;
}

}  // namespace body_gait_model
