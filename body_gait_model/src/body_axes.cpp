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
  // At least this many points left out at each end: a sparse slice's 2nd percentile is its
  // extreme point, and a few stray points of undecoded dark hair made the head's top slice as
  // wide as shoulders (the frame turned 60 deg, the fit 277 mm off).
  constexpr size_t kMinTrimmed = 3;
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
      const size_t low = std::max<size_t>(projections.size() / 50, kMinTrimmed);
      const size_t high = projections.size() - 1 - low;
      std::nth_element(projections.begin(), projections.begin() + low, projections.end());
      const double low_value = projections[low];
      std::nth_element(projections.begin(), projections.begin() + high, projections.end());
      widest = std::max(widest, projections[high] - low_value);
    }
    if (widest >= options.shoulder_width * body_height) return body_height - (slice + 0.5) * kSlice;
  }
  return options.shoulder_top * body_height;
}

// Step 1 (5.5.1): centroid e_0 and vertical axis e_1 from the whole body; sets result.centroid
// and result.pca_vertical, returns the vertical axis the later steps use.
Eigen::Vector3d verticalAxis(const Cloud& cloud, const BodyAxesOptions& options, BodyAxes& result) {
  Moments all;
  for (const auto& point : cloud) all.add(point);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> whole(all.covariance());
  result.centroid = all.mean();
  Eigen::Vector3d up = whole.eigenvectors().col(2);  // largest eigenvalue
  if (up.z() < 0) up = -up;
  if (up.z() < 0.5)
    throw std::invalid_argument(
        "body axes: the cloud's longest axis is not vertical (it leans by more than 60 "
        "degrees); the fitter expects a standing subject in the scanner's floor frame (z up)");
  result.pca_vertical = up;
  if (options.vertical_from_floor) up = Eigen::Vector3d::UnitZ();
  return up;
}

// Points of the shoulder band (its heights shifted by shoulder_shift to the measured shoulders'
// top), projected on the horizontal plane (u, v), and their mean.
struct ShoulderBand {
  std::vector<Eigen::Vector2d> points;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
};

ShoulderBand shoulderBand(const Cloud& cloud, const Eigen::Vector3d& centroid,
                          const Eigen::Vector3d& up, const Eigen::Vector3d& u,
                          const Eigen::Vector3d& v, double lowest, double shoulder_shift,
                          double body_height, const BodyAxesOptions& options) {
  ShoulderBand band;
  for (const auto& point : cloud) {
    const Eigen::Vector3d offset = point - centroid;
    const double above_floor = offset.dot(up) - lowest - shoulder_shift;
    if (above_floor < options.shoulder_band_low * body_height ||
        above_floor > options.shoulder_band_high * body_height)
      continue;
    band.points.emplace_back(offset.dot(u), offset.dot(v));
    band.centre += band.points.back();
  }
  if (band.points.size() < 100)
    throw std::invalid_argument(
        "body axes: only " + std::to_string(band.points.size()) +
        " points at shoulder height; the upper torso is missing from the cloud");
  band.centre /= double(band.points.size());
  return band;
}

// The widest horizontal direction of the torso's outline in the band, in (u, v) coordinates.
// Only the torso's own points count: per radial sector around the band's centre, those within
// kSectorDepth of the sector's closest point (as the cross-sections of 5.5.2 do), so that arms
// hanging outside the torso do not skew the axes.
Eigen::Vector2d torsoCoronalAxis(const ShoulderBand& band) {
  constexpr int kSectors = 36;
  constexpr double kSectorDepth = 0.03;
  constexpr double kTwoPi = 6.283185307179586;
  const Eigen::Vector2d& band_centre = band.centre;
  auto sectorOf = [&](const Eigen::Vector2d& planar) {
    const Eigen::Vector2d d = planar - band_centre;
    const int sector = int((std::atan2(d.y(), d.x()) + kTwoPi / 2) / kTwoPi * kSectors);
    return std::clamp(sector, 0, kSectors - 1);
  };
  std::vector<double> closest(kSectors, 1e9);
  for (const auto& planar : band.points)
    closest[sectorOf(planar)] = std::min(closest[sectorOf(planar)], (planar - band_centre).norm());
  // Each sector's kept points stand for the outline by their mean, one vertex per sector: the
  // moments of the outline, not of the points, whose density varies over the surface with the
  // viewpoints (the full scanner sees a turned subject's shoulders obliquely from some poles).
  std::vector<Eigen::Vector2d> sector_sum(kSectors, Eigen::Vector2d::Zero());
  std::vector<int> sector_count(kSectors, 0);
  for (const auto& planar : band.points) {
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
  return torso.eigenvectors().col(1);  // widest: shoulder to shoulder
}

// The tentative body frame that the front/back step tests, and the cloud's extent along up.
struct TentativeFrame {
  Eigen::Vector3d centroid, up, left, front;
  double lowest, body_height;
};

// Side of the tentative coronal plane a point lies on: 1 left, 0 right.
int legSide(const Eigen::Vector3d& offset, const TentativeFrame& frame) {
  return offset.dot(frame.left) > 0 ? 1 : 0;
}

// Each leg's lowest height but a few stray points (a leg may be lifted off the floor).
void legLowest(const Cloud& cloud, const TentativeFrame& frame, const BodyAxesOptions& options,
               double (&side_lowest)[2]) {
  std::vector<double> side_heights[2];
  for (const auto& point : cloud) {
    const Eigen::Vector3d offset = point - frame.centroid;
    const double height = offset.dot(frame.up);
    if (height - frame.lowest < options.shank_band_high * frame.body_height)
      side_heights[legSide(offset, frame)].push_back(height);
  }
  side_lowest[0] = side_lowest[1] = frame.lowest;
  for (int side = 0; side < 2; ++side) {
    std::vector<double>& heights = side_heights[side];
    if (heights.empty()) continue;
    const size_t index = heights.size() / 1000;
    std::nth_element(heights.begin(), heights.begin() + index, heights.end());
    side_lowest[side] = heights[index];
  }
}

// Per leg, the lower shank's centre line through the medians of the shank band's lower and upper
// halves, as (left, height above the leg's lowest point, front) points; the median, so that the
// other leg's foot swinging close by does not pull it.
struct ShankLine {
  bool valid = false;
  Eigen::Vector3d low, high;
};

void shankLines(const Cloud& cloud, const TentativeFrame& frame, const double (&side_lowest)[2],
                const BodyAxesOptions& options, ShankLine (&lines)[2]) {
  const double body_height = frame.body_height;
  const double mid = (options.shank_band_low + options.shank_band_high) / 2 * body_height;
  std::vector<Eigen::Vector3d> shank_band[2][2];  // [side][lower, upper half]
  for (const auto& point : cloud) {
    const Eigen::Vector3d offset = point - frame.centroid;
    const int side = legSide(offset, frame);
    const double above_floor = offset.dot(frame.up) - side_lowest[side];
    if (above_floor < options.shank_band_low * body_height ||
        above_floor >= options.shank_band_high * body_height)
      continue;
    shank_band[side][above_floor >= mid ? 1 : 0].emplace_back(offset.dot(frame.left), above_floor,
                                                              offset.dot(frame.front));
  }
  for (int side = 0; side < 2; ++side) {
    if (shank_band[side][0].size() < 20 || shank_band[side][1].size() < 20) continue;
    lines[side].low = componentMedian(shank_band[side][0]);
    lines[side].high = componentMedian(shank_band[side][1]);
    lines[side].valid = std::abs(lines[side].high.y() - lines[side].low.y()) > 1e-6;
  }
}

// How far the feet's points lie ahead of their shank lines along the tentative front, the mean
// over the legs that have enough foot points (each leg weighs the same: a leg's point count
// varies with its tilt); only foot points within foot_radius of the line count. 0 if no leg.
double footReach(const Cloud& cloud, const TentativeFrame& frame, const BodyAxesOptions& options) {
  double side_lowest[2];
  legLowest(cloud, frame, options, side_lowest);
  ShankLine lines[2];
  shankLines(cloud, frame, side_lowest, options, lines);
  double reach_sum[2] = {0, 0};
  int reach_count[2] = {0, 0};
  for (const auto& point : cloud) {
    const Eigen::Vector3d offset = point - frame.centroid;
    const int side = legSide(offset, frame);
    if (!lines[side].valid) continue;
    const double above_floor = offset.dot(frame.up) - side_lowest[side];
    if (above_floor >= options.foot_band * frame.body_height) continue;
    const Eigen::Vector3d &a = lines[side].low, &b = lines[side].high;
    const double t = (above_floor - a.y()) / (b.y() - a.y());
    const Eigen::Vector2d on_line(a.x() + (b.x() - a.x()) * t, a.z() + (b.z() - a.z()) * t);
    const Eigen::Vector2d planar(offset.dot(frame.left), offset.dot(frame.front));
    if ((planar - on_line).norm() > options.foot_radius * frame.body_height) continue;
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
  return legs > 0 ? reach / legs : 0.0;
}

}  // namespace

BodyAxes estimateBodyAxes(const Cloud& cloud, const BodyAxesOptions& options) {
  if (cloud.size() < kMinimumPoints)
    throw std::invalid_argument(
        "body axes: the cloud has " + std::to_string(cloud.size()) +
        " points; a whole-body scan needs >= " + std::to_string(kMinimumPoints) +
        " (check that every pair captured and the merge kept them)");
  BodyAxes result;
  const Eigen::Vector3d up = verticalAxis(cloud, options, result);
  double lowest = 1e9, highest = -1e9;
  for (const auto& point : cloud) {
    const double height = (point - result.centroid).dot(up);
    lowest = std::min(lowest, height);
    highest = std::max(highest, height);
  }
  const double body_height = highest - lowest;

  // Step 2: coronal / sagittal axes from the horizontal spread of the torso's top, the shoulder
  // girdle: the widest, flattest cross-section of the torso, where swinging arms have not yet
  // moved away from it. Projected onto the plane normal to e_1 so that the frame stays
  // orthonormal.
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
  const Eigen::Vector2d coronal = torsoCoronalAxis(
      shoulderBand(cloud, result.centroid, up, u, v, lowest, shoulder_shift, body_height, options));
  Eigen::Vector3d left = (coronal.x() * u + coronal.y() * v).normalized();
  Eigen::Vector3d front = left.cross(up);  // so that left = up x front

  // Step 3, front/back: per leg (split by the tentative coronal axis), extrapolate the lower
  // shank's centre line down to the foot; the feet reach ahead of it along the true front.
  result.foot_reach =
      footReach(cloud, {result.centroid, up, left, front, lowest, body_height}, options);
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
