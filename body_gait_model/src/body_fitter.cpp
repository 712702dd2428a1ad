// Model fitting of thesis 5.5: axes, torso, arms and legs (eqs 5.9-5.10), head and neck.
#include <body_gait_model/body_fitter.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>

#include "order_statistics.h"

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Line {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitY();  // unit

  double distance(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d offset = p - point;
    return (offset - offset.dot(direction) * direction).norm();
  }
  // The line's point at model height y (the line must not be horizontal).
  Eigen::Vector3d atHeight(double y) const {
    if (std::abs(direction.y()) < 1e-6) return point;
    return point + (y - point.y()) / direction.y() * direction;
  }
};

// Running sums for least-squares line fits: the line through the mean along the principal
// axis minimizes the summed squared distances of eqs 5.9 / 5.10.
struct LineMoments {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  int count = 0;
  void add(const Eigen::Vector3d& p) {
    sum += p;
    outer += p * p.transpose();
    ++count;
  }
  LineMoments operator-(const LineMoments& other) const {
    return {sum - other.sum, outer - other.outer, count - other.count};
  }
  Line fit(const Eigen::Vector3d& orientation) const {
    Line line;
    if (count < 3) return line;
    line.point = sum / count;
    const Eigen::Matrix3d covariance = outer / count - line.point * line.point.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
    line.direction = solver.eigenvectors().col(2);
    if (line.direction.dot(orientation) < 0) line.direction = -line.direction;
    return line;
  }
};

// A limb of two parts (upper/lower arm or leg) fitted by two lines (eqs 5.9-5.10).
struct LimbFit {
  bool valid = false;
  Line upper, lower;
  Eigen::Vector3d middle_joint = Eigen::Vector3d::Zero();     // elbow or knee
  Eigen::Vector3d distal_end = Eigen::Vector3d::Zero();       // hand tip or sole
  double upper_radius[2] = {0, 0}, lower_radius[2] = {0, 0};  // proximal, distal
  int points = 0;
  // Legs: the centre of the shank's section just above the ankle (ankleCentre), if found.
  Eigen::Vector3d ankle = Eigen::Vector3d::Zero();
  bool ankle_found = false;
};

double mean(const std::vector<double>& values) {
  return values.empty() ? 0.0 : std::accumulate(values.begin(), values.end(), 0.0) / values.size();
}

// Splits the limb's points along their principal axis and fits a line to each part (eqs
// 5.9-5.10). The split is searched within +-window of the standard proportion (expected_fraction
// of the proximal-joint-to-tip length) and minimizes the spread of point-to-line distances about
// each part's own radius. The elbow is then placed by the bend: where the two lines meet when
// the arm bends clearly (the lines fitted without the points near the split, whose part is
// ambiguous), at the standard proportion along the limb when it is nearly straight (a straight
// limb's girth changes too smoothly to show the joint: the split alone put straight knees ~100
// mm off), blended in between. The knee (proximal_fixed: the hip) always at the proportion, on
// the shank line. tip_points give the limb's far end for the proportion (the legs' include the
// feet, left out of the line fits). proximalOf gives the proximal joint.
constexpr double kShortUpperPart = 0.2;  // m
constexpr double kJointGap = 0.04;       // m each side of the split left out of the joint lines
// A leg's points this close to the lowest point touch the floor (m), and its foot is planted
// when one of them lies this close (horizontally) to where the shank's line meets the floor.
constexpr double kContactHeight = 0.015, kPlantedReach = 0.07;
// A planted sole lies at most this far beyond the leg's farthest point along the shank (the
// scanner sees little of a foot's underside: 20-50 mm); a floor point farther along the line is
// the other foot's, met by a lifted shank's line.
constexpr double kPlantedBeyondSole = 0.06;
constexpr double kTipCap = 0.03;    // m: an arm's far-end points, before its reach
constexpr double kCrownCap = 0.02;  // m: the head's top points whose centroid is the vertex
// A crown seen closes as a dome: the head's sections in its top kCrownCap stay below this part
// of its largest (seen crowns: 0.01-0.32; heads cut off by the viewpoints' sight: 0.65-1.0).
constexpr double kCrownDome = 0.5;
constexpr double kMaxTipTurn = 30 * kPi / 180;  // the far end's direction from the lower line
// Bend between the two lines (rad) below which the joint comes from the proportion alone, and
// above which from the lines' meeting point alone. A line off the bone's axis by d (a muscle's
// bulge, a side the scanner sees less of) moves the meeting point along the other line by
// d / sin(bend): 3-4 d at a walking arm's 15-20 deg. Trusted alone from 14 deg on, the direct
// fits' elbows scattered 42-49 mm about their mean offset, 29-41 mm by the proportion (mesh
// people on the CMU walks and simulated walks, evaluate_body_fit --direct --per-joint).
constexpr double kStraightBend = 10 * kPi / 180, kClearBend = 30 * kPi / 180;

// Midpoint of the closest approach of two lines; false if they are (nearly) parallel.
bool closestApproach(const Line& a, const Line& b, Eigen::Vector3d* midpoint) {
  const Eigen::Vector3d w = a.point - b.point;
  const double ab = a.direction.dot(b.direction), denominator = 1 - ab * ab;
  if (denominator < 1e-6) return false;
  const double da = a.direction.dot(w), db = b.direction.dot(w);
  const double s = (ab * db - da) / denominator, t = (db - ab * da) / denominator;
  *midpoint = (a.point + s * a.direction + b.point + t * b.direction) / 2;
  return true;
}

template <typename ProximalOf>
LimbFit fitLimb(std::vector<Eigen::Vector3d> points, const std::vector<Eigen::Vector3d>& tip_points,
                double expected_fraction, double window, const ProximalOf& proximalOf,
                bool proximal_fixed) {
  LimbFit limb;
  limb.points = int(points.size());
  if (points.size() < 30) return limb;
  LineMoments all;
  for (const auto& p : points) all.add(p);
  const Line axis = all.fit(-Eigen::Vector3d::UnitY());  // limbs hang: orient downward
  std::sort(points.begin(), points.end(), [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return (a - axis.point).dot(axis.direction) < (b - axis.point).dot(axis.direction);
  });
  std::vector<double> along(points.size());
  std::vector<LineMoments> prefix(points.size() + 1);
  for (size_t i = 0; i < points.size(); ++i) {
    along[i] = (points[i] - axis.point).dot(axis.direction);
    prefix[i + 1] = prefix[i];
    prefix[i + 1].add(points[i]);
  }
  const double start = (proximalOf(axis) - axis.point).dot(axis.direction);
  std::vector<double> tip_along;
  for (const auto& p : tip_points) tip_along.push_back((p - axis.point).dot(axis.direction));
  if (tip_along.empty()) tip_along = along;
  const double end = quantile(tip_along, 0.995);
  const double length = end - start;
  double best_cost = std::numeric_limits<double>::infinity();
  size_t best_split = 0;
  for (double fraction = expected_fraction - window; fraction <= expected_fraction + window + 1e-9;
       fraction += 0.01) {
    const size_t split =
        std::lower_bound(along.begin(), along.end(), start + fraction * length) - along.begin();
    if (split < 10 || split + 10 > points.size()) continue;
    const Line upper = prefix[split].fit(axis.direction);
    const Line lower = (prefix[points.size()] - prefix[split]).fit(axis.direction);
    double cost = 0;
    for (const auto& [from, to, line] :
         {std::tuple<size_t, size_t, const Line&>{0, split, upper},
          std::tuple<size_t, size_t, const Line&>{split, points.size(), lower}}) {
      double sum = 0, sum_squares = 0;
      for (size_t i = from; i < to; ++i) {
        const double d = line.distance(points[i]);
        sum += d;
        sum_squares += d * d;
      }
      cost += sum_squares - sum * sum / double(to - from);
    }
    if (cost < best_cost) {
      best_cost = cost;
      best_split = split;
    }
  }
  if (best_split == 0) return limb;
  auto indexAt = [&](double position) {
    return size_t(std::lower_bound(along.begin(), along.end(), position) - along.begin());
  };
  // The lines without the points within kJointGap of the split (if enough remain).
  const size_t upper_end = indexAt(along[best_split] - kJointGap);
  const size_t lower_begin = indexAt(along[best_split] + kJointGap);
  limb.upper = upper_end >= 10 ? prefix[upper_end].fit(axis.direction)
                               : prefix[best_split].fit(axis.direction);
  limb.lower = points.size() - lower_begin >= 10
                   ? (prefix[points.size()] - prefix[lower_begin]).fit(axis.direction)
                   : (prefix[points.size()] - prefix[best_split]).fit(axis.direction);
  auto onLine = [](const Line& line, const Eigen::Vector3d& p) {
    return line.point + (p - line.point).dot(line.direction) * line.direction;
  };
  // Joint by proportion: where the plane across the axis at the standard fraction meets each
  // line, averaged.
  const Eigen::Vector3d proportion_plane =
      axis.point + (start + expected_fraction * length) * axis.direction;
  Eigen::Vector3d by_proportion =
      (onLine(limb.upper, proportion_plane) + onLine(limb.lower, proportion_plane)) / 2;
  Eigen::Vector3d by_bend = by_proportion;
  double weight = 0;
  if (proximal_fixed) {
    // Legs: the knee on the shank line at the proportion. The thigh below the crotch is too short
    // and mixed with the buttocks' surface for a line of its own, and a line from the hip (inside
    // the pelvis, estimated) turns the hip's error into a ~4x larger error along the shank:
    // measured on 10 subjects x 4 poses, both bend estimates put the knee 38-45 mm off, the
    // proportion 21-22 mm (evaluate_body_fit --direct).
    by_proportion = onLine(limb.lower, proportion_plane);
  } else {
    // Arms: where the two lines meet, if that lies within the search window.
    const double bend =
        std::acos(std::clamp(limb.upper.direction.dot(limb.lower.direction), -1.0, 1.0));
    weight = std::clamp((bend - kStraightBend) / (kClearBend - kStraightBend), 0.0, 1.0);
    if (weight > 0 && closestApproach(limb.upper, limb.lower, &by_bend)) {
      const double fraction = ((by_bend - axis.point).dot(axis.direction) - start) / length;
      if (std::abs(fraction - expected_fraction) > window) by_bend = by_proportion;
    }
  }
  limb.middle_joint = weight * by_bend + (1 - weight) * by_proportion;
  const double split_along = (limb.middle_joint - axis.point).dot(axis.direction);
  const size_t split_index = std::clamp<size_t>(indexAt(split_along), 1, points.size() - 1);
  // A short upper part (a thigh seen only below a low crotch) leaves its line's direction
  // undetermined: take the line from the joint through the fixed proximal joint (hips) or the
  // upper part's centroid.
  const double upper_extent = split_along - along.front();
  if (proximal_fixed || upper_extent < kShortUpperPart) {
    const Eigen::Vector3d from =
        proximal_fixed ? proximalOf(axis)
                       : Eigen::Vector3d(prefix[split_index].sum / prefix[split_index].count);
    limb.upper.point = from;
    limb.upper.direction = (limb.middle_joint - from).normalized();
  }
  best_split = split_index;
  // Far end: the 99.5th percentile of the lower part along a direction from the middle joint
  // (robust to stray points). The hand bends at the wrist away from the forearm's line (CMU
  // walks: 20-40 deg, its tip 60-90 mm off the line), so an arm's direction is turned toward
  // the centroid of its far end's points (twice: the cap then lies across the new direction).
  auto farEnd = [&](const Eigen::Vector3d& direction, double* far_reach) {
    std::vector<double> reach;
    for (size_t i = best_split; i < points.size(); ++i)
      reach.push_back((points[i] - limb.middle_joint).dot(direction));
    *far_reach = quantile(reach, 0.995);
    Eigen::Vector3d cap = Eigen::Vector3d::Zero();
    int count = 0;
    for (size_t i = best_split; i < points.size(); ++i)
      if (reach[i - best_split] > *far_reach - kTipCap && reach[i - best_split] <= *far_reach) {
        cap += points[i];
        ++count;
      }
    return count > 0 ? Eigen::Vector3d(cap / count) : limb.middle_joint + *far_reach * direction;
  };
  Eigen::Vector3d tip_direction = limb.lower.direction;
  double far_reach = 0;
  if (!proximal_fixed)
    for (int pass = 0; pass < 2; ++pass) {
      const Eigen::Vector3d towards = farEnd(tip_direction, &far_reach) - limb.middle_joint;
      // A cap far off the line holds stray points, no hand (a bent hand turns the elbow-to-tip
      // direction 10-20 deg).
      if (towards.norm() > kShortUpperPart / 2 &&
          towards.normalized().dot(limb.lower.direction) > std::cos(kMaxTipTurn))
        tip_direction = towards.normalized();
    }
  farEnd(tip_direction, &far_reach);
  limb.distal_end = limb.middle_joint + far_reach * tip_direction;
  // Radii: mean distance to the line over each half of each part.
  auto radii = [&](size_t from, size_t to, const Line& line, double* out) {
    const size_t middle = (from + to) / 2;
    std::vector<double> first, second;
    for (size_t i = from; i < to; ++i)
      (i < middle ? first : second).push_back(line.distance(points[i]));
    out[0] = mean(first);
    out[1] = mean(second);
  };
  radii(0, best_split, limb.upper, limb.upper_radius);
  radii(best_split, points.size(), limb.lower, limb.lower_radius);
  limb.valid = true;
  return limb;
}

// Radius of a cross-section polygon in the direction of a point (its sector's vertex).
double polygonRadius(const CrossSection& section, double phi, int sectors) {
  if (section.polygon.empty()) return 0;
  const int sector = std::clamp(int((phi + kPi) / (2 * kPi) * sectors), 0, sectors - 1);
  return section.polygon[sector].norm();
}

// Kasa's algebraic circle fit of points (a, b) in a plane: a^2 + b^2 + D a + E b + F = 0, least
// squares in (D, E, F), accumulated point by point.
struct CircleFit {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d right_side = Eigen::Vector3d::Zero();
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int count = 0;

  void add(double a, double b) {
    const Eigen::Vector3d row(a, b, 1.0);
    normal += row * row.transpose();
    right_side -= row * (a * a + b * b);
    sum += Eigen::Vector2d(a, b);
    ++count;
  }
  Eigen::Vector2d centroid() const { return sum / count; }
  // The centre; none from fewer than 20 points or a singular system. A degenerate arc (a straight
  // wall, stray points) leaves it far from the centroid: callers bound that distance.
  std::optional<Eigen::Vector2d> centre() const {
    constexpr int kMinPoints = 20;
    if (count < kMinPoints) return std::nullopt;
    const Eigen::Vector3d circle = normal.ldlt().solve(right_side);
    const Eigen::Vector2d centre(-circle[0] / 2, -circle[1] / 2);
    if (!centre.allFinite()) return std::nullopt;
    return centre;
  }
};

// The centre of a leg's shank just above the ankle: a circle fitted (CircleFit) to the
// leg's points between kAnkleBand[0] and kAnkleBand[1] of the body height below the knee along
// the knee-to-sole line (Drillis & Contini: knee 0.285, ankle 0.039 of the stature high, so the
// band lies 0.045-0.085 above the ankle), within kAnkleReach of the line (a foot reaches across
// it: with a heel-off foot's points some ellipsoid bodies' soles came out 30-70 mm off), and no
// lower than kAnkleAboveSole above the sole. There the shank is tibia, fibula and tendons, centred
// on the ankle joint; higher up the calf bulges behind the tibia: on the mesh human the shank's
// surface centre lies 20-25 mm behind the knee-to-ankle line over its upper half and 0-8 mm in this
// band (the ellipsoid body: 0-1 mm all along), so a line fitted to the shank's surface misses the
// ankle. False when the band holds too few points or no arc.
constexpr double kAnkleBand[2] = {0.18, 0.22};  // * body height below the knee
constexpr double kAnkleReach = 0.07;            // m from the knee-to-sole line
constexpr double kAnkleAboveSole = 0.04;        // * body height
bool ankleCentre(const std::vector<Eigen::Vector3d>& leg_points, const Eigen::Vector3d& knee,
                 const Eigen::Vector3d& sole, double body_height, Eigen::Vector3d* centre) {
  const Eigen::Vector3d axis = (sole - knee).normalized();
  const double sole_along = (sole - knee).dot(axis);
  const double from = kAnkleBand[0] * body_height,
               to = std::min(kAnkleBand[1] * body_height,
                             sole_along - kAnkleAboveSole * body_height);
  // A frame across the axis.
  const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
  CircleFit section;
  for (const auto& p : leg_points) {
    const Eigen::Vector3d r = p - knee;
    const double along = r.dot(axis);
    if (along < from || along > to) continue;
    const double a = r.dot(u), b = r.dot(v);
    if (std::hypot(a, b) <= kAnkleReach) section.add(a, b);
  }
  const auto middle = section.centre();
  if (!middle || (*middle - section.centroid()).norm() > 0.05) return false;
  *centre = knee + (from + to) / 2 * axis + middle->x() * u + middle->y() * v;
  return true;
}

enum Part { kTorsoPart, kHeadPart, kRightArm, kLeftArm, kRightLeg, kLeftLeg, kUnassigned };

// Standard proportions (Drillis & Contini): elbow at 0.186 / 0.44 of shoulder to finger tip,
// knee at 0.245 / 0.53 of hip to sole.
constexpr double kElbowFraction = 0.186 / 0.44, kKneeFraction = 0.245 / 0.53;

}  // namespace

FitQuality evaluateFit(const BodyModel& model, const Cloud& cloud,
                       const FitQualityOptions& options) {
  FitQuality quality;
  const SegmentSurfaces surfaces = segmentSurfaces(forwardKinematics(model));
  double sum_squares = 0;
  int explained = 0, evaluated = 0;
  const size_t stride = std::max<size_t>(1, cloud.size() / size_t(std::max(options.max_points, 1)));
  std::array<int, kSegmentCount> nearest{};
  for (size_t index = 0; index < cloud.size(); index += stride) {
    const Eigen::Vector3d& point = cloud[index];
    const auto [best_segment, best] = nearestSegment(surfaces, point);
    sum_squares += best * best;
    explained += best <= options.explained_distance;
    ++nearest[best_segment];
    ++evaluated;
  }
  for (int s = 0; s < kSegmentCount; ++s)
    quality.points_per_segment[s] =
        evaluated > 0 ? int(std::lround(double(nearest[s]) * cloud.size() / evaluated)) : 0;
  quality.rms_distance = evaluated > 0 ? std::sqrt(sum_squares / evaluated) : 0.0;
  quality.explained_fraction = evaluated > 0 ? double(explained) / evaluated : 0.0;
  std::string reason;
  if (quality.explained_fraction < options.min_explained_fraction)
    reason += "only " + std::to_string(int(100 * quality.explained_fraction)) +
              " % of the points lie within " +
              std::to_string(int(1000 * options.explained_distance)) + " mm of the model; ";
  if (quality.rms_distance > options.max_rms)
    reason += "RMS point-to-model distance " + std::to_string(int(1000 * quality.rms_distance)) +
              " mm > " + std::to_string(int(1000 * options.max_rms)) + " mm; ";
  for (int s : {kRightUpperArm, kRightLowerArm, kLeftUpperArm, kLeftLowerArm, kRightUpperLeg,
                kRightLowerLeg, kLeftUpperLeg, kLeftLowerLeg})
    if (quality.points_per_segment[s] < options.min_points_per_limb_segment)
      reason += std::string(segmentInfo(s).name) + " explains only " +
                std::to_string(quality.points_per_segment[s]) + " points; ";
  // Limb proportions (FitQualityOptions::max_*_share_deviation).
  for (const auto& [upper, standard, tolerance] :
       {std::tuple{kRightUpperArm, kElbowFraction, options.max_arm_share_deviation},
        std::tuple{kLeftUpperArm, kElbowFraction, options.max_arm_share_deviation},
        std::tuple{kRightUpperLeg, kKneeFraction, options.max_leg_share_deviation},
        std::tuple{kLeftUpperLeg, kKneeFraction, options.max_leg_share_deviation}}) {
    const double limb_length = model.r[upper] + model.r[upper + 1];
    const double share = limb_length > 0 ? model.r[upper] / limb_length : 0.0;
    if (std::abs(share - standard) > tolerance)
      reason += std::string(segmentInfo(upper).name) + " is " +
                std::to_string(int(std::lround(100 * share))) + " % of its limb (standard " +
                std::to_string(int(std::lround(100 * standard))) + " %); ";
  }
  quality.low_quality = !reason.empty();
  if (quality.low_quality)
    quality.reason = reason +
                     "check that the whole subject was scanned (arms away from the "
                     "torso, every pair captured)";
  return quality;
}

namespace {

// Right and left leg from the points below the lower torso's base, in slices of slice_step top
// down (model coordinates). Just below the crotch the legs lie either side of the hips' centre
// (x), and the top slices are split there. Further down a split at that x fails in mid-stance,
// where a foot crosses the midline and the leg of that side takes in the other foot (CMU walks:
// knee 64 mm, thigh 56-60 % of its leg). So each leg's centre is tracked down in x-z from slice
// to slice, as the arms are: a slice's points go to the nearer of the two centres carried down
// from the slice above, re-centred on the points taken (a few 2-means steps), which follows legs
// that pass each other in z or cross the midline in x.
void splitLegs(const std::vector<Eigen::Vector3d>& model_points,
               const std::vector<std::vector<size_t>>& slices, double centre_x,
               std::vector<Part>& part) {
  // The tracking starts from kSeedSlices slices split at the hips' centre with both thighs in
  // them (each side at least kSeedShare of the slice): under dark trunks the top slices hold
  // only stray points of the hands, and a centre seeded there never finds its thigh.
  constexpr int kSeedSlices = 3;
  constexpr double kSeedShare = 0.25;
  constexpr int kSteps = 3;      // 2-means steps per slice
  constexpr int kMinPoints = 3;  // a leg with fewer in a slice keeps its centre
  // A leg left with less than this share of the points has been lost (the other centre took
  // both): then the split at the hips' centre.
  constexpr double kMinLegShare = 0.25;
  const Part kLegs[2] = {kRightLeg, kLeftLeg};
  Eigen::Vector2d centre[2] = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  int seed_slices = 0;
  size_t total[2] = {0, 0};
  auto xzOf = [&](size_t i) { return Eigen::Vector2d(model_points[i].x(), model_points[i].z()); };
  std::vector<std::vector<int>> legs_of(slices.size());
  for (size_t slice = 0; slice < slices.size(); ++slice) {
    const auto& points = slices[slice];
    std::vector<int>& leg_of = legs_of[slice];
    leg_of.resize(points.size());
    const bool seed = seed_slices < kSeedSlices;
    for (int step = 0; step < (seed ? 1 : kSteps); ++step) {
      Eigen::Vector2d sum[2] = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
      int count[2] = {0, 0};
      for (size_t k = 0; k < points.size(); ++k) {
        const Eigen::Vector2d xz = xzOf(points[k]);
        leg_of[k] = seed
                        ? (xz.x() > centre_x ? 1 : 0)
                        : ((xz - centre[1]).squaredNorm() < (xz - centre[0]).squaredNorm() ? 1 : 0);
        sum[leg_of[k]] += xz;
        ++count[leg_of[k]];
      }
      const int min_count =
          seed ? std::max(kMinPoints, int(kSeedShare * double(points.size()))) : kMinPoints;
      if (seed && (count[0] < min_count || count[1] < min_count)) continue;
      seed_slices += seed;
      for (int leg = 0; leg < 2; ++leg)
        if (count[leg] >= min_count) centre[leg] = sum[leg] / count[leg];
    }
    for (int leg : leg_of) ++total[leg];
  }
  const double all = double(total[0] + total[1]);
  const bool lost = all > 0 && std::min(total[0], total[1]) < kMinLegShare * all;
  for (size_t slice = 0; slice < slices.size(); ++slice)
    for (size_t k = 0; k < slices[slice].size(); ++k) {
      const size_t i = slices[slice][k];
      part[i] = kLegs[lost ? (model_points[i].x() > centre_x ? 1 : 0) : legs_of[slice][k]];
    }
}

// The parts of the body (5.5.2-5.5.4) each point (model coordinates) belongs to.
std::vector<Part> segmentBody(const std::vector<Eigen::Vector3d>& model_points,
                              const TorsoFit& torso, const Line& upper_axis, double body_height,
                              const FitOptions& options) {
  const int sectors = options.torso.sectors;
  // Segmentation (5.5.2-5.5.4). Above the torso: head and neck near the axis. Between the
  // centroid and the torso's top: points outside the cross-section polygon are arms (the chest
  // sections are closed). Below the centroid the polygon around the axis no longer separates
  // arms from hips and thighs, so each arm is tracked down slice by slice from its centre; what
  // remains below the lower torso's base is legs.
  std::vector<Part> part(model_points.size(), kUnassigned);
  const double step = options.torso.slice_step;
  std::vector<std::vector<size_t>> low_slices;  // below g, top down
  for (size_t i = 0; i < model_points.size(); ++i) {
    const Eigen::Vector3d& p = model_points[i];
    if (p.y() > torso.top) {
      const Eigen::Vector3d on_axis = upper_axis.atHeight(p.y());
      if (std::hypot(p.x() - on_axis.x(), p.z() - on_axis.z()) < 0.09 * body_height)
        part[i] = kHeadPart;
    } else if (p.y() >= 0) {
      const CrossSection& section = torso.sectionAt(p.y());
      const double r = std::hypot(p.x(), p.z());
      const double phi = std::atan2(p.z(), p.x());
      if (r <= polygonRadius(section, phi, sectors) + 0.03)
        part[i] = kTorsoPart;
      else
        part[i] = p.x() - section.centre.x() > 0 ? kLeftArm : kRightArm;
    } else {
      const size_t slice = size_t(std::floor(-p.y() / step));
      if (slice >= low_slices.size()) low_slices.resize(slice + 1);
      low_slices[slice].push_back(i);
    }
  }
  constexpr double kArmReach = 0.5;  // finger tips lie < 0.5 * height below the torso's top
  for (Part arm : {kRightArm, kLeftArm}) {
    // Start: the arm's points in the lowest 5 cm above the centroid.
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    int count = 0;
    for (size_t i = 0; i < model_points.size(); ++i)
      if (part[i] == arm && model_points[i].y() < 0.05) {
        centre += Eigen::Vector2d(model_points[i].x(), model_points[i].z());
        ++count;
      }
    if (count < 5) continue;
    centre /= count;
    int empty_run = 0;
    for (const auto& slice : low_slices) {
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      int taken = 0;
      for (size_t i : slice) {
        const Eigen::Vector2d xz(model_points[i].x(), model_points[i].z());
        const Eigen::Vector3d& p = model_points[i];
        if (p.y() < torso.top - kArmReach * body_height) continue;
        // Down to the crotch the arm may touch the hips: points on the hips' cross-section
        // polygon belong to the torso.
        if (p.y() >= torso.base &&
            std::hypot(p.x(), p.z()) <=
                polygonRadius(torso.sectionAt(p.y()), std::atan2(p.z(), p.x()), sectors) + 0.02)
          continue;
        if (part[i] == kUnassigned && (xz - centre).norm() < options.limb_track_radius) {
          part[i] = arm;
          sum += xz;
          ++taken;
        }
      }
      if (taken >= 3) {
        centre = sum / taken;
        empty_run = 0;
      } else if (++empty_run > 3) {
        break;
      }
    }
  }
  const Eigen::Vector3d hip_line_centre =
      Line{torso.waist, torso.lower_direction}.atHeight(torso.base);
  std::vector<std::vector<size_t>> leg_slices;  // below the base, top down
  for (const auto& slice : low_slices) {
    std::vector<size_t> legs;
    for (size_t i : slice)
      if (part[i] == kUnassigned && model_points[i].y() < torso.base) legs.push_back(i);
    if (!legs.empty() || !leg_slices.empty()) leg_slices.push_back(std::move(legs));
  }
  splitLegs(model_points, leg_slices, hip_line_centre.x(), part);
  return part;
}

// Neck, chin and head (5.5.4) and the stature they imply.
struct HeadFit {
  double neck_area = 0;  // m^2; infinite when no section qualified
  double chin = 0;       // height in the model frame
  double head_area = 0;  // largest section of the head, m^2
  Eigen::Vector3d head_direction;
  double stature = 0;
  // The vertex seen: the centroid of the head's top kCrownCap at the highest point's height
  // (not when the hair is unseen or the crown lies above the viewpoints' sight).
  Eigen::Vector3d crown = Eigen::Vector3d::Zero();
  bool crown_seen = false;
  // Dark hair: the head's upper half returned no light, the vertex was placed from the chin.
  bool hair_unseen = false;
};

HeadFit fitHead(const std::vector<Eigen::Vector3d>& model_points, const std::vector<Part>& part,
                const TorsoFit& torso, const BodyAxes& axes, int sectors) {
  // Head and neck (5.5.4): the neck is the narrowest section above the torso, the chin where the
  // sections widen again; the head runs from there to its highest point.
  double head_top = torso.top;
  std::vector<Eigen::Vector3d> head_points;
  for (size_t i = 0; i < model_points.size(); ++i)
    if (part[i] == kHeadPart) {
      head_points.push_back(model_points[i]);
      head_top = std::max(head_top, model_points[i].y());
    }
  if (head_points.size() < 30)
    throw std::invalid_argument("body fit: no head above the torso (" +
                                std::to_string(head_points.size()) +
                                " points); the top viewpoints must see the subject's head");
  // Sections of the head and neck, each about its own slice's centroid: the torso's are taken
  // about the body's vertical axis, which a head held forward of the trunk leaves at the neck's
  // edge (CMU walk 07_02: neck sections of ~0 area, the chin found 30 mm low, the neck 30 % short).
  const double step =
      torso.sections.size() > 1 ? torso.sections[1].height - torso.sections[0].height : 0.01;
  std::vector<std::vector<Eigen::Vector2d>> head_slices(
      size_t(std::max(1.0, std::ceil((head_top - torso.top) / step))));
  for (const auto& p : head_points)
    head_slices[std::min(head_slices.size() - 1, size_t((p.y() - torso.top) / step))].emplace_back(
        p.x(), p.z());
  std::vector<CrossSection> head_sections;
  for (size_t k = 0; k < head_slices.size(); ++k) {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const auto& xz : head_slices[k]) centre += xz;
    if (!head_slices[k].empty()) centre /= double(head_slices[k].size());
    std::vector<Eigen::Vector2d> around;
    for (const auto& xz : head_slices[k]) around.push_back(xz - centre);
    CrossSection section = crossSection(around, torso.top + (double(k) + 0.5) * step, sectors);
    section.centre += centre;
    head_sections.push_back(section);
  }
  // The neck: the smallest well-sampled section in the lower half of the head-and-neck range;
  // the chin where the sections widen past 1.6x it.
  struct NeckAndChin {
    double neck_area = std::numeric_limits<double>::infinity(), neck_height = 0;
    double chin = 0, head_area = 0;
    bool chin_found = false;
    Eigen::Vector2d chin_centre = Eigen::Vector2d::Zero();
  };
  auto neckAndChin = [&](const std::vector<CrossSection>& sections) {
    NeckAndChin found;
    found.neck_height = torso.top;
    for (const auto& section : sections)
      if (section.height > torso.top && section.height < (torso.top + head_top) / 2 &&
          section.filled_sectors >= sectors / 2 && section.area < found.neck_area) {
        found.neck_area = section.area;
        found.neck_height = section.height;
      }
    if (!std::isfinite(found.neck_area)) found.neck_area = torso.sectionAt(torso.top).area;
    found.chin = torso.top + 0.3 * (head_top - torso.top);  // if the sections never widen
    for (const auto& section : sections)
      if (section.height > found.neck_height && section.height < head_top) {
        if (section.filled_sectors < sectors / 2) continue;
        if (!found.chin_found && section.area > 1.6 * found.neck_area) {
          found.chin = section.height;
          found.chin_found = true;
          found.chin_centre = section.centre;
        }
        found.head_area = std::max(found.head_area, section.area);
      }
    if (!found.chin_found) {
      const double at = found.chin;
      const auto nearest = std::min_element(
          sections.begin(), sections.end(),
          [&](auto& a, auto& b) { return std::abs(a.height - at) < std::abs(b.height - at); });
      if (nearest != sections.end()) found.chin_centre = nearest->centre;
    }
    return found;
  };
  // Dark hair returns no light: the head's upper half is then open (its sections about the axis
  // have points in a few sectors only, the face's; a seen head fills nearly all). A slice's own
  // centroid then lies on the face, not inside the head, so such a head keeps the sections about
  // the axis (the chin-to-vertex proportion below was measured on them).
  const NeckAndChin about_axis = neckAndChin(torso.sections);
  int upper_head_sections = 0, upper_head_filled = 0;
  for (const auto& section : torso.sections)
    if (section.height > (about_axis.chin + head_top) / 2 && section.height < head_top) {
      ++upper_head_sections;
      upper_head_filled += section.filled_sectors;
    }
  const bool open_about_axis = about_axis.chin_found && upper_head_sections > 0 &&
                               upper_head_filled < upper_head_sections * sectors / 2;
  // Unseen hair leaves the upper head open about its own centroid too (the face's half shell: 21-25
  // of 36 sectors on 10 subjects x 4 poses with dark hair); a head held forward of the trunk's
  // axis is open about the axis only (35-36 sectors about its own centroid).
  int own_sections = 0, own_filled = 0;
  for (const auto& section : head_sections)
    if (section.height > (about_axis.chin + head_top) / 2 && section.height < head_top) {
      ++own_sections;
      own_filled += section.filled_sectors;
    }
  // Only a head open about both is unseen on top: one open about the axis only is seen whole
  // and takes its own sections, like a head over the axis (the mesh people switched between the
  // two from scan to scan: their chin moved 10-90 mm, neck and head lengths 12 mm SD between two
  // walks of one person, 7 and 6 mm when both take their own sections).
  const bool hair_unseen = open_about_axis && own_filled < own_sections * sectors * 3 / 4;
  const NeckAndChin found = hair_unseen ? about_axis : neckAndChin(head_sections);
  const double neck_area = found.neck_area, chin = found.chin, head_area = found.head_area;
  Eigen::Vector3d head_centroid = Eigen::Vector3d::Zero();
  int head_count = 0;
  for (const auto& p : head_points)
    if (p.y() > chin) {
      head_centroid += p;
      ++head_count;
    }
  const Eigen::Vector3d chin_centre(found.chin_centre.x(), chin, found.chin_centre.y());
  Eigen::Vector3d head_direction = torso.upper_direction;
  // An open head's visible top lies 40-53 mm below the vertex and the face alone pulls the
  // head's centroid forward. Then the vertex comes
  // from the chin by proportion: in fits of simulated subjects with their hair seen, the chin
  // found above lies 0.103 (0.096-0.116) of the stature below the vertex (10 subjects x 4 poses;
  // Drillis & Contini's chin-to-vertex is 0.130, the sections widen past 1.6x the neck's ~0.03
  // higher). Measured on the same subjects with dark hair: vertex -3 mm (8 mm RMS) instead of
  // -46 mm. The stature from it sets the hips' height.
  constexpr double kChinToVertex = 0.103;  // * stature
  // The crown is seen when the head closes as a dome below its highest point. The gap between
  // that point and the stature the shoulders' top implies does not tell: on real proportions it
  // is 0-56 mm with the crown seen (CMU walks on mesh bodies), 32 mm on a tall subject whose
  // crown lies above the highest viewpoints' sight.
  double top_area = 0;
  for (const auto& section : head_sections)
    if (section.height > head_top - kCrownCap) top_area = std::max(top_area, section.area);
  const bool crown_domed = top_area < kCrownDome * head_area;
  // A head cut off by the highest viewpoints' sight (tall subjects under the full scanner's top
  // pairs) keeps the trunk's direction: its visible band's centroid lies on the face, and the
  // refinement turned a head started there toward the horizontal (mesh human of 1.95 m: vertex
  // 270 mm forward, 80-120 mm with the trunk's direction).
  const bool head_cut_off = !hair_unseen && !crown_domed;
  if (hair_unseen)
    head_top = std::max(head_top, (chin - kChinToVertex * axes.lowest) / (1 - kChinToVertex));
  else if (head_count > 10 && !head_cut_off)
    head_direction = (head_centroid / head_count - chin_centre).normalized();
  // The stature: up to the vertex found (placed from the chin when the hair is unseen), or the
  // axes' estimate from the shoulders' top when the crown lies above the highest viewpoints'
  // sight (tall subjects under the full scanner's top pairs).
  const double stature = std::max(head_top - axes.lowest, axes.stature);

  HeadFit fit{neck_area, chin, head_area, head_direction, stature};
  fit.hair_unseen = hair_unseen;
  if (!hair_unseen && crown_domed) {
    Eigen::Vector2d cap = Eigen::Vector2d::Zero();
    int count = 0;
    for (const auto& p : head_points)
      if (p.y() > head_top - kCrownCap) {
        cap += Eigen::Vector2d(p.x(), p.z());
        ++count;
      }
    if (count >= 10) {
      fit.crown = Eigen::Vector3d(cap.x() / count, head_top, cap.y() / count);
      fit.crown_seen = true;
    }
  }
  return fit;
}

// The four limbs' lines, middle joints and far ends, and the shoulders and hips they hang from
// (model coordinates; index 0 right, 1 left).
struct LimbJoints {
  LimbFit limbs[6];
  Eigen::Vector3d shoulder[2], hip[2];
};

LimbJoints fitLimbs(const std::vector<Eigen::Vector3d>& model_points, const std::vector<Part>& part,
                    const TorsoFit& torso, const BodyAxes& axes, double stature,
                    const FitOptions& options) {
  const double body_height = axes.height();
  std::vector<Eigen::Vector3d> limb_points[6];
  for (size_t i = 0; i < model_points.size(); ++i)
    if (part[i] != kUnassigned) limb_points[part[i]].push_back(model_points[i]);
  // Proximal joints. Shoulder: below the top of the shoulder above the upper-arm line by
  // shoulder_depth of the arm's radii (FitOptions). Hip: on the thigh line at hip_height * body
  // height above the lowest point. The top of the shoulder is no higher than the shoulders' top the
  // body axes found (the highest slice as wide as shoulders: the acromia): above it, a column
  // reaching in toward the neck meets the trapezius sloping up (the mesh human on the CMU walks:
  // shoulders 37-51 mm high, 27-41 mm with this bound; the ellipsoid bodies' shoulders 1-2 mm
  // nearer). It is searched within 0.1 of the body height of the torso's top: the line of an arm
  // swung forward across the body, extended up, passes behind the shoulder and met the buttocks
  // (mesh human, sampler: an arm not fitted at all).
  auto shoulderOn = [&](const Line& line, double radius, double depth_in_radii) {
    const Eigen::Vector3d column = line.atHeight(torso.top);
    double shoulder_top = -std::numeric_limits<double>::infinity();
    for (const auto& p : model_points)
      if (std::hypot(p.x() - column.x(), p.z() - column.z()) < radius &&
          std::abs(p.y() - torso.top) < 0.1 * body_height)
        shoulder_top = std::max(shoulder_top, p.y());
    if (!std::isfinite(shoulder_top)) shoulder_top = torso.top;
    return line.atHeight(std::min(shoulder_top, axes.shoulder_top) - depth_in_radii * radius);
  };
  // Hips: inside the pelvis, unseen. Height by proportion; depth a fraction of the body's depth
  // there from the back (the lower torso's axis, centred on belly and buttocks, lies 35-40 mm
  // in front of real hips); each hip above the centre of its thigh's top 10 cm (a thigh line
  // extrapolated up from a low crotch swings wildly when the knee is bent).
  const double hip_y = axes.lowest + options.hip_height * stature;
  Eigen::Vector3d pelvis_centre = Line{torso.waist, torso.lower_direction}.atHeight(hip_y);
  {
    // The midline's front and back at hip height (|x| < 4 cm: between the thighs, clear of the
    // hands).
    std::vector<double> depths;
    for (const auto& p : model_points)
      if (std::abs(p.y() - hip_y) < 0.02 && std::abs(p.x() - pelvis_centre.x()) < 0.04)
        depths.push_back(p.z());
    constexpr size_t kMinDepthPoints = 20;
    if (depths.size() >= kMinDepthPoints) {
      const double back = quantile(depths, 0.01), front = quantile(depths, 0.99);
      pelvis_centre.z() = back + options.hip_depth_fraction * (front - back);
    }
  }
  // Each thigh's axis at its top: the centre of a circle fitted to its top 10 cm (CircleFit in
  // x, z). The points' centroid lay ~16 mm outward: the inner thigh, hidden by the other leg,
  // returns fewer points than the outer.
  auto thighTopX = [&](Part leg) {
    double top = -1e9;
    for (const auto& p : limb_points[leg]) top = std::max(top, p.y());
    CircleFit band;
    for (const auto& p : limb_points[leg])
      if (p.y() > top - 0.1) band.add(p.x(), p.z());
    if (band.count == 0) return pelvis_centre.x();
    const double centroid_x = band.centroid().x();
    // A degenerate band (too few points, a straight wall) keeps the centroid.
    const auto centre = band.centre();
    return centre && std::abs(centre->x() - centroid_x) < 0.05 ? centre->x() : centroid_x;
  };
  const double hip_half_width = std::clamp((thighTopX(kLeftLeg) - thighTopX(kRightLeg)) / 2,
                                           0.02 * body_height, 0.08 * body_height);
  const Eigen::Vector3d hip_of_side[2] = {pelvis_centre - Eigen::Vector3d(hip_half_width, 0, 0),
                                          pelvis_centre + Eigen::Vector3d(hip_half_width, 0, 0)};
  constexpr double kArmRadius = 0.045;
  constexpr double kFootHeight = 0.06;  // * body height: the foot's points above the sole
  LimbJoints joints;
  auto& limbs = joints.limbs;
  auto& shoulder = joints.shoulder;
  auto& hip = joints.hip;
  for (Part limb : {kRightArm, kLeftArm, kRightLeg, kLeftLeg}) {
    const bool arm = limb == kRightArm || limb == kLeftArm;
    const int side = limb == kLeftArm || limb == kLeftLeg ? 1 : 0;
    // The arm's split (kElbowFraction) is searched from one radius below the shoulder's top,
    // where its proportion was measured.
    if (arm)
      limbs[limb] = fitLimb(
          limb_points[limb], limb_points[limb], kElbowFraction, options.arm_split_window,
          [&](const Line& line) { return shoulderOn(line, kArmRadius, 1.0); }, false);
    else {
      // The foot sticks out forward from the shank: leave it out of the line fits.
      double lowest = std::numeric_limits<double>::infinity();
      for (const auto& p : limb_points[limb]) lowest = std::min(lowest, p.y());
      std::vector<Eigen::Vector3d> without_foot;
      for (const auto& p : limb_points[limb])
        if (p.y() > lowest + kFootHeight * body_height) without_foot.push_back(p);
      limbs[limb] = fitLimb(
          without_foot, limb_points[limb], kKneeFraction, options.leg_split_window,
          [&](const Line&) { return hip_of_side[side]; }, true);
      if (limbs[limb].valid) {
        // The sole: as far along the shank line as the leg's points (the foot included) reach.
        std::vector<double> reach;
        for (const auto& p : limb_points[limb])
          reach.push_back((p - limbs[limb].middle_joint).dot(limbs[limb].lower.direction));
        limbs[limb].distal_end =
            limbs[limb].middle_joint + quantile(reach, 0.995) * limbs[limb].lower.direction;
        limbs[limb].ankle_found =
            ankleCentre(limb_points[limb], limbs[limb].middle_joint, limbs[limb].distal_end,
                        body_height, &limbs[limb].ankle);
      }
    }
    if (!limbs[limb].valid)
      throw std::invalid_argument(
          std::string("body fit: too few points on the ") +
          (limb == kRightArm   ? "right arm"
           : limb == kLeftArm  ? "left arm"
           : limb == kRightLeg ? "right leg"
                               : "left leg") +
          " (" + std::to_string(limb_points[limb].size()) +
          "); the subject must stand with arms and legs apart and in view of every pole");
    if (arm)
      shoulder[side] = shoulderOn(limbs[limb].upper, std::max(limbs[limb].upper_radius[0], 0.02),
                                  options.shoulder_depth);
    else
      hip[side] = hip_of_side[side];
  }

  return joints;
}

// The body model in the world from the torso, head and limbs found (segment lengths, joint
// angles, shape) and the joints' points.
void assembleModel(const Line& upper_axis, const HeadFit& head, const LimbJoints& joints,
                   const JointLimitSet& limits, BodyFit& fit) {
  const BodyAxes& axes = fit.axes;
  const TorsoFit& torso = fit.torso;
  const double chin = head.chin, stature = head.stature, neck_area = head.neck_area,
               head_area = head.head_area;
  const Eigen::Vector3d& head_direction = head.head_direction;
  const auto& limbs = joints.limbs;
  const auto& shoulder = joints.shoulder;
  const auto& hip = joints.hip;
  // Assemble the model in the world (eq 5.4 inverse): root at w_g with the body axes.
  BodyModel& model = fit.model;
  model.p = poseVectorFromFrame(axes.toWorld(torso.waist), axes.axes);
  auto toWorldDirection = [&](const Eigen::Vector3d& d) { return axes.axes * d; };
  auto setSegment = [&](int segment, const Eigen::Vector3d& world_direction) {
    const PosedModel posed = forwardKinematics(model);
    const int parent = segmentInfo(segment).parent;
    const Eigen::Matrix3d parent_rotation =
        parent == kWholeBody ? posed.whole_body.linear() : posed.segments[parent].frame.linear();
    const Eigen::Vector2d angles = jointAnglesForDirection(
        parent_rotation.transpose() * world_direction, segmentInfo(segment).points_up);
    model.setJointAngles(segment, angles[0], angles[1]);
    model = clampToJointLimits(model, limits);
  };
  model.r[kUpperTorso] = torso.top / std::max(torso.upper_direction.y(), 0.5);
  model.r[kLowerTorso] = -torso.base / std::max(-torso.lower_direction.y(), 0.5);
  model.r[kNeck] = std::max(chin - torso.top, 0.01) / std::max(torso.upper_direction.y(), 0.5);
  const double crown = axes.lowest + stature;
  model.r[kHead] = std::max(crown - chin, 0.05) / std::max(head_direction.y(), 0.5);
  setSegment(kUpperTorso, toWorldDirection(torso.upper_direction));
  setSegment(kLowerTorso, toWorldDirection(torso.lower_direction));
  setSegment(kHead, toWorldDirection(head_direction));

  BodyShape& shape = model.shape;
  {
    const PosedModel posed = forwardKinematics(model);
    const Eigen::Isometry3d upper_frame_inverse = posed.segments[kUpperTorso].frame.inverse();
    const Eigen::Isometry3d lower_frame_inverse = posed.segments[kLowerTorso].frame.inverse();
    double shoulder_x = 0, shoulder_y = 0, hip_x = 0, hip_y = 0, hip_z = 0;
    for (int side = 0; side < 2; ++side) {
      const Eigen::Vector3d s = upper_frame_inverse * axes.toWorld(shoulder[side]);
      const Eigen::Vector3d h = lower_frame_inverse * axes.toWorld(hip[side]);
      shoulder_x += std::abs(s.x()) / 2;
      shoulder_y += s.y() / 2;
      hip_x += std::abs(h.x()) / 2;
      hip_y += h.y() / 2;
      hip_z += h.z() / 2;
    }
    shape.shoulder_half_width = shoulder_x;
    shape.shoulder_drop = model.r[kUpperTorso] - shoulder_y;
    shape.hip_half_width = hip_x;
    shape.hip_rise = model.r[kLowerTorso] + hip_y;  // hip_y is negative (below the waist)
    shape.hip_back = -hip_z;
  }
  shape.proximal_radius[kUpperTorso] = shape.proximal_radius[kLowerTorso] = torso.waist_radius;
  shape.distal_radius[kUpperTorso] = torso.upper_radius_top;
  shape.distal_radius[kLowerTorso] = torso.lower_radius_base;
  shape.proximal_radius[kNeck] = shape.distal_radius[kNeck] =
      std::isfinite(neck_area) ? std::sqrt(neck_area / kPi) : 0.05;
  shape.proximal_radius[kHead] = shape.distal_radius[kHead] = std::sqrt(head_area / kPi);

  const struct {
    Part part;
    int upper_segment;
    int side;
    const char* middle;
    const char* distal;
    const char* proximal;
  } kLimbs[] = {{kRightArm, kRightUpperArm, 0, "right_elbow", "right_hand_tip", "right_shoulder"},
                {kLeftArm, kLeftUpperArm, 1, "left_elbow", "left_hand_tip", "left_shoulder"},
                {kRightLeg, kRightUpperLeg, 0, "right_knee", "right_sole", "right_hip"},
                {kLeftLeg, kLeftUpperLeg, 1, "left_knee", "left_sole", "left_hip"}};
  for (const auto& limb_info : kLimbs) {
    const LimbFit& limb = limbs[limb_info.part];
    const bool arm = limb_info.part == kRightArm || limb_info.part == kLeftArm;
    const Eigen::Vector3d proximal =
        axes.toWorld(arm ? shoulder[limb_info.side] : hip[limb_info.side]);
    const Eigen::Vector3d middle = axes.toWorld(limb.middle_joint);
    const Eigen::Vector3d distal = axes.toWorld(limb.distal_end);
    const int upper = limb_info.upper_segment, lower = upper + 1;
    model.r[upper] = (middle - proximal).norm();
    model.r[lower] = (distal - middle).norm();
    setSegment(upper, (middle - proximal).normalized());
    setSegment(lower, (distal - middle).normalized());
    shape.proximal_radius[upper] = limb.upper_radius[0];
    shape.distal_radius[upper] = limb.upper_radius[1];
    shape.proximal_radius[lower] = limb.lower_radius[0];
    shape.distal_radius[lower] = limb.lower_radius[1];
    fit.joint_points.push_back({limb_info.proximal, proximal});
    fit.joint_points.push_back({limb_info.middle, middle});
    fit.joint_points.push_back({limb_info.distal, distal});
  }
  fit.joint_points.push_back({"head_top", axes.toWorld(upper_axis.atHeight(crown))});
}

// A scan's direct fit (5.5) and what refinement needs of it.
struct DirectFit {
  BodyFit fit;
  bool fitted = false;  // false: no body shape found, fit holds a flagged standing template
  std::string failure;  // why not
  Cloud without_feet;   // the fitting cloud above the feet (the model has none): refinement's
  Eigen::Vector3d soles[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};      // world
  Eigen::Vector3d hand_tips[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};  // world
  // Each shank's centre just above the ankle (world; ankleCentre), when found.
  Eigen::Vector3d ankles[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  bool ankle_found[2] = {false, false};
  // The vertex (world) when crown_known: seen, or under dark hair placed from the chin on the
  // trunk's axis (the refinement has only the face to turn that head to: on 10 subjects x 4 poses
  // with dark hair the head top came out 37 mm forward, 5 mm aimed at the placed vertex).
  Eigen::Vector3d crown = Eigen::Vector3d::Zero();
  bool crown_known = false;
  // Each leg's points within kContactHeight of the lowest point (world), and the floor's height
  // (world z of the lowest point).
  std::vector<Eigen::Vector3d> contacts[2];
  double floor = 0;
  // False when the pelvis returned too little light to be seen (pelvisSeen).
  bool pelvis_seen = true;
};

// Whether the pelvis was seen: most torso sections from the hips' height up to kPelvisBand of
// the stature above them closed (points in at least 3/4 of the sectors, as fitTorso's reference
// section). The iliac crest lies about 0.6 of the stature high (C. C. Gordon et al., "2012
// Anthropometric Survey of U.S. Army Personnel", 2014: iliocristale height), the hip joints at
// 0.53 (Drillis & Contini). Dark trunks leave that band open, and a walk's refinement then has
// nothing to hold the hips where the direct fit put them: the thighs' lengths wander (10
// subjects x 4 poses with dark trunks: hips 80-110 mm high or low in 3 walks, 51 mm off on
// average; with the thighs held 24 mm).
constexpr double kPelvisBand = 0.06;  // * stature
bool pelvisSeen(const TorsoFit& torso, double hip_height, double stature, int sectors) {
  int sections = 0, closed = 0;
  for (const CrossSection& section : torso.sections)
    if (section.height >= hip_height && section.height <= hip_height + kPelvisBand * stature) {
      ++sections;
      closed += section.filled_sectors >= sectors * 3 / 4;
    }
  return 2 * closed >= sections;
}

// Steps 5.5.1-5.5.4 on an even subsample of the cloud. Throws std::invalid_argument when the
// cloud is no standing body at all (estimateBodyAxes).
DirectFit fitDirectly(const Cloud& full_cloud, const FitOptions& options) {
  DirectFit direct;
  BodyFit& fit = direct.fit;
  // An even subsample (every k-th point keeps every viewpoint's share) for the fitting stages.
  Cloud subsample;
  if (options.max_fit_points > 0 && full_cloud.size() > size_t(options.max_fit_points)) {
    subsample.reserve(size_t(options.max_fit_points));
    for (size_t i = 0; i < size_t(options.max_fit_points); ++i)
      subsample.push_back(full_cloud[i * full_cloud.size() / size_t(options.max_fit_points)]);
  }
  const Cloud& cloud = subsample.empty() ? full_cloud : subsample;
  fit.axes = estimateBodyAxes(cloud, options.axes);  // refuses clouds that are no body at all
  try {
    const BodyAxes& axes = fit.axes;
    std::vector<Eigen::Vector3d> model_points;
    model_points.reserve(cloud.size());
    for (const auto& p : cloud) model_points.push_back(axes.toModel(p));
    fit.torso = fitTorso(model_points, axes, options.torso);
    const TorsoFit& torso = fit.torso;
    const Line upper_axis{torso.waist, torso.upper_direction};
    const std::vector<Part> part =
        segmentBody(model_points, torso, upper_axis, axes.height(), options);
    const HeadFit head = fitHead(model_points, part, torso, axes, options.torso.sectors);
    const LimbJoints joints = fitLimbs(model_points, part, torso, axes, head.stature, options);
    assembleModel(upper_axis, head, joints, options.joint_limits, fit);
    // The feet: everything up to foot_height above the lowest point, and each leg's points
    // within foot_height of its sole along its shank (a lifted foot, whose points would pull
    // the shank's cylinder toward the toes: CMU swing-leg soles 30-50 mm low).
    const double foot_height = options.foot_height * axes.height();
    const double foot_top = axes.lowest + foot_height;
    double foot_from[2];
    for (int side = 0; side < 2; ++side) {
      const LimbFit& leg = joints.limbs[side == 0 ? kRightLeg : kLeftLeg];
      foot_from[side] = (leg.distal_end - leg.middle_joint).dot(leg.lower.direction) - foot_height;
    }
    direct.without_feet.reserve(cloud.size());
    for (size_t i = 0; i < cloud.size(); ++i) {
      if (model_points[i].y() <= foot_top) continue;
      if (part[i] == kRightLeg || part[i] == kLeftLeg) {
        const int side = part[i] == kLeftLeg ? 1 : 0;
        const LimbFit& leg = joints.limbs[side == 0 ? kRightLeg : kLeftLeg];
        if ((model_points[i] - leg.middle_joint).dot(leg.lower.direction) > foot_from[side])
          continue;
      }
      direct.without_feet.push_back(cloud[i]);
    }
    direct.soles[0] = axes.toWorld(joints.limbs[kRightLeg].distal_end);
    direct.soles[1] = axes.toWorld(joints.limbs[kLeftLeg].distal_end);
    direct.floor = axes.toWorld(Eigen::Vector3d(0, axes.lowest, 0)).z();
    for (size_t i = 0; i < cloud.size(); ++i)
      if ((part[i] == kRightLeg || part[i] == kLeftLeg) &&
          model_points[i].y() < axes.lowest + kContactHeight)
        direct.contacts[part[i] == kLeftLeg ? 1 : 0].push_back(cloud[i]);
    direct.crown = axes.toWorld(head.hair_unseen ? upper_axis.atHeight(axes.lowest + head.stature)
                                                 : head.crown);
    direct.crown_known = head.crown_seen || head.hair_unseen;
    direct.pelvis_seen = pelvisSeen(torso, axes.lowest + options.hip_height * head.stature,
                                    head.stature, options.torso.sectors);
    for (int side = 0; side < 2; ++side) {
      const LimbFit& leg = joints.limbs[side == 0 ? kRightLeg : kLeftLeg];
      direct.ankles[side] = axes.toWorld(leg.ankle);
      direct.ankle_found[side] = leg.ankle_found;
    }
    direct.hand_tips[0] = axes.toWorld(joints.limbs[kRightArm].distal_end);
    direct.hand_tips[1] = axes.toWorld(joints.limbs[kLeftArm].distal_end);
    direct.fitted = true;
  } catch (const std::invalid_argument& not_a_body) {
    // Shaped unlike a body (or parts missing): a standing template at the centroid, flagged.
    fit.model = standingModel(std::max(fit.axes.height(), 0.5));
    fit.model.p = poseVectorFromFrame(fit.axes.centroid, fit.axes.axes);
    direct.failure = std::string("not fitted: ") + not_a_body.what();
  }
  return direct;
}

// The refinement turns the shanks without the feet (the model has none) and holds their
// lengths, so their far ends swing away from the soles the direct fit found: the length of
// each lower leg that ends it where its sole projects onto the refined line. Measured on 10
// subjects x 4 poses: soles 34 -> 25 mm. That sole is the leg's farthest point along the line
// but a few, and the scanner sees little of a foot's underside (none within ~1 cm of the
// floor): on CMU walks planted soles came out 20-50 mm short. A planted foot (flat or on its
// heel: a point at floor level within kPlantedReach of where the shank's line meets the floor;
// a toe-off foot touches it 10-15 cm ahead) has its sole on the floor: there the length is the
// refined knee's distance to the floor along the line.
struct ShankLengths {
  std::array<double, 2> length{};
  std::array<bool, 2> planted{};
};

ShankLengths shankLengthsToSoles(const BodyModel& model, const DirectFit& direct,
                                 double min_length) {
  const PosedModel posed = forwardKinematics(model);
  ShankLengths shanks;
  for (int side = 0; side < 2; ++side) {
    const PosedSegment& shank = posed.segments[side == 0 ? kRightLowerLeg : kLeftLowerLeg];
    const Eigen::Vector3d direction = (shank.distal - shank.proximal).normalized();
    shanks.length[side] =
        std::max((direct.soles[side] - shank.proximal).dot(direction), min_length);
    if (direction.z() > -0.5) continue;  // a leg this far from upright: no floor point
    const double along = (direct.floor - shank.proximal.z()) / direction.z();
    if (along > shanks.length[side] + kPlantedBeyondSole) continue;
    const Eigen::Vector3d on_floor = shank.proximal + along * direction;
    for (const Eigen::Vector3d& contact : direct.contacts[side])
      if (std::hypot(contact.x() - on_floor.x(), contact.y() - on_floor.y()) < kPlantedReach) {
        shanks.planted[side] = true;
        shanks.length[side] = std::max(along, min_length);
        break;
      }
  }
  return shanks;
}

// The refinement turns each lower arm to its forearm's surface, and a hand bent at the wrist
// (real walks: 20-40 deg) leaves its tip 40-60 mm off that line: each lower arm is aimed from its
// refined elbow at the tip the direct fit found. A tip the refined arm does not point at (beyond
// kMaxTipTurn of its line, or its distance beyond max_length_change of the arm's length) comes
// from a failed direct fit of the arm, which the refinement corrected: that arm stays.
struct HandTips {
  std::array<double, 2> length{};  // elbow to tip
  std::array<bool, 2> found{};     // the tip agrees with the refined arm
};

// The distance from `segment`'s proximal joint to `target` when the segment points at it within
// max_turn and that distance is within max_length_change of its length; 0 otherwise.
double agreeingReach(const BodyModel& model, const PosedModel& posed, int segment,
                     const Eigen::Vector3d& target, double max_length_change,
                     double max_turn = kMaxTipTurn) {
  const PosedSegment& posed_segment = posed.segments[segment];
  const Eigen::Vector3d to_target = target - posed_segment.proximal;
  const double length = to_target.norm();
  const bool agrees =
      length > 1e-3 && model.r[segment] > 0 &&
      to_target.normalized().dot((posed_segment.distal - posed_segment.proximal).normalized()) >
          std::cos(max_turn) &&
      std::abs(length / model.r[segment] - 1) < max_length_change;
  return agrees ? length : 0;
}

// Turns `segment` about its proximal joint to point at `target`.
void aimSegmentAt(BodyModel& model, int segment, const Eigen::Vector3d& target) {
  const PosedModel posed = forwardKinematics(model);
  const SegmentInfo& info = segmentInfo(segment);
  const Eigen::Vector3d direction = (target - posed.segments[segment].proximal).normalized();
  const Eigen::Vector2d angles = jointAnglesForDirection(
      posed.segments[info.parent].frame.linear().transpose() * direction, info.points_up);
  model.setJointAngles(segment, angles[0], angles[1]);
}

// The refinement turns each shank to its surface, whose calf bulges behind the tibia (mesh human
// on the full scanner: soles 30 mm behind and 30 mm lateral of the true ones, the shank turned
// 3-5 deg off its bone): each lower leg is aimed from its refined knee at the shank's centre
// above the ankle (ankleCentre) when that lies within kMaxShankTurn of the refined line (beyond,
// the band held something else than the shank).
constexpr double kMaxShankTurn = 8 * kPi / 180;
void aimLowerLegsAtAnkles(BodyModel& model, const DirectFit& direct, const JointLimitSet& limits) {
  for (int side = 0; side < 2; ++side) {
    if (!direct.ankle_found[side]) continue;
    const int segment = side == 0 ? kRightLowerLeg : kLeftLowerLeg;
    const PosedModel posed = forwardKinematics(model);
    const PosedSegment& shank = posed.segments[segment];
    const Eigen::Vector3d to_ankle = direct.ankles[side] - shank.proximal;
    if (to_ankle.normalized().dot((shank.distal - shank.proximal).normalized()) >
        std::cos(kMaxShankTurn))
      aimSegmentAt(model, segment, direct.ankles[side]);
  }
  model = clampToJointLimits(model, limits);
}

HandTips elbowToHandTips(const BodyModel& model, const DirectFit& direct,
                         double max_length_change) {
  const PosedModel posed = forwardKinematics(model);
  HandTips tips;
  for (int side = 0; side < 2; ++side) {
    const int segment = side == 0 ? kRightLowerArm : kLeftLowerArm;
    tips.length[side] = (direct.hand_tips[side] - posed.segments[segment].proximal).norm();
    tips.found[side] =
        agreeingReach(model, posed, segment, direct.hand_tips[side], max_length_change) > 0;
  }
  return tips;
}

// Aims each lower arm whose tip was found at it; `lengths` (the walk's shared ones, or the
// tips' distances) go to every arm with a length.
void aimLowerArmsAtHandTips(BodyModel& model, const DirectFit& direct, const HandTips& tips,
                            const std::array<double, 2>& lengths, const JointLimitSet& limits) {
  for (int side = 0; side < 2; ++side) {
    const int segment = side == 0 ? kRightLowerArm : kLeftLowerArm;
    if (lengths[side] > 0) model.r[segment] = lengths[side];
    if (tips.found[side]) aimSegmentAt(model, segment, direct.hand_tips[side]);
  }
  model = clampToJointLimits(model, limits);
}

// The refinement turns the head to the surface of its points, face and hair, whose axis runs
// behind the vertex (simulated and CMU walks: head top 15-18 mm behind; a mesh person of CMU
// walk 35: the head pitched 30-50 deg forward of its vertex): the head is aimed from its refined
// base at the vertex the direct fit found when that distance agrees with the head's length. A
// vertex is the seen crown's top, not a far end that a failed direct fit can misplace as a
// hand's, so the turn is bounded by kMaxCrownTurn only (a vertex behind or below the base).
// Returns the base-to-vertex distance, 0 when no vertex was found or it disagrees.
constexpr double kMaxCrownTurn = kPi / 2;
double headBaseToCrown(const BodyModel& model, const DirectFit& direct, double max_length_change) {
  if (!direct.crown_known) return 0;
  return agreeingReach(model, forwardKinematics(model), kHead, direct.crown, max_length_change,
                       kMaxCrownTurn);
}

// Aims the head at the vertex when `found`; `length` > 0 becomes the head's length.
void aimHeadAtCrown(BodyModel& model, const DirectFit& direct, bool found, double length,
                    const JointLimitSet& limits) {
  if (length > 0) model.r[kHead] = length;
  if (!found) return;
  aimSegmentAt(model, kHead, direct.crown);
  model = clampToJointLimits(model, limits);
}

// The fit quality against the whole cloud, the direct fit's failure and the limits reached.
void finishFit(const Cloud& full_cloud, const FitOptions& options, DirectFit& direct) {
  BodyFit& fit = direct.fit;
  fit.quality = evaluateFit(fit.model, full_cloud, options.quality);
  if (!direct.fitted) {
    fit.quality.low_quality = true;
    fit.quality.reason = direct.failure;
  }
  fit.quality.limits_reached = jointLimitsReached(fit.model, options.joint_limits);
}

// Whether the knee of one leg (0 right, 1 left) bends beyond kClearKneeBend in any of the walk's
// direct fits. Only a bent knee shows where it lies along the leg: on a straight one the thigh's
// and shank's cylinders fit the surface about as well with the knee anywhere along the line, and
// a walk's refinement moved such knees by the legs' radius profiles, not by the bend: the mesh
// people's straighter walks (knees bent at most 19 deg in the direct fits) had their knees
// raised 25 mm, 13 mm with their thighs held; walks whose knees bend 40-60 deg (CMU) place them
// better refined (knees 16-17 mm, 20-22 mm held).
constexpr double kClearKneeBend = 20 * kPi / 180;  // beyond loading response's 15-20 deg
bool kneeBentInWalk(const std::vector<BodyModel>& models, int side) {
  const int thigh = side == 0 ? kRightUpperLeg : kLeftUpperLeg, shank = thigh + 1;
  for (const BodyModel& model : models) {
    const PosedModel posed = forwardKinematics(model);
    const Eigen::Vector3d thigh_direction =
        (posed.segments[thigh].distal - posed.segments[thigh].proximal).normalized();
    const Eigen::Vector3d shank_direction =
        (posed.segments[shank].distal - posed.segments[shank].proximal).normalized();
    if (thigh_direction.dot(shank_direction) < std::cos(kClearKneeBend)) return true;
  }
  return false;
}

template <typename Values>
double median(Values values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n == 0 ? 0.0 : n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

}  // namespace

BodyFit fitBody(const Cloud& full_cloud, const FitOptions& options) {
  DirectFit direct = fitDirectly(full_cloud, options);
  if (direct.fitted && options.refine) {
    BodyModel& model = direct.fit.model;
    direct.fit.refinement =
        refineModel(model, direct.without_feet, options.refinement, options.joint_limits);
    aimLowerLegsAtAnkles(model, direct, options.joint_limits);
    const auto shanks = shankLengthsToSoles(model, direct, options.refinement.min_length);
    model.r[kRightLowerLeg] = shanks.length[0];
    model.r[kLeftLowerLeg] = shanks.length[1];
    const HandTips tips = elbowToHandTips(model, direct, options.refinement.max_length_change);
    std::array<double, 2> lengths{};
    for (int side = 0; side < 2; ++side)
      if (tips.found[side]) lengths[side] = tips.length[side];
    aimLowerArmsAtHandTips(model, direct, tips, lengths, options.joint_limits);
    const double crown = headBaseToCrown(model, direct, options.refinement.max_length_change);
    aimHeadAtCrown(model, direct, crown > 0, crown, options.joint_limits);
  }
  finishFit(full_cloud, options, direct);
  return direct.fit;
}

WalkFit fitWalk(const std::vector<Cloud>& walk, const FitOptions& options) {
  WalkFit result;
  std::vector<DirectFit> directs;
  directs.reserve(walk.size());
  for (const Cloud& cloud : walk) directs.push_back(fitDirectly(cloud, options));
  // One body: each length and shape value the median over the scans fitted (robust to one
  // scan's wrong split), the lower legs' the median of each scan's length to its sole.
  std::vector<size_t> fitted;
  for (size_t i = 0; i < directs.size(); ++i)
    if (directs[i].fitted) fitted.push_back(i);
  if (!fitted.empty()) {
    BodyModel shared = directs[fitted.front()].fit.model;
    auto medianOf = [&](auto value) {
      std::vector<double> values;
      for (size_t i : fitted) values.push_back(value(directs[i].fit.model));
      return median(values);
    };
    for (int s = 0; s < kSegmentCount; ++s) {
      shared.r[s] = medianOf([s](const BodyModel& m) { return m.r[s]; });
      shared.shape.proximal_radius[s] =
          medianOf([s](const BodyModel& m) { return m.shape.proximal_radius[s]; });
      shared.shape.distal_radius[s] =
          medianOf([s](const BodyModel& m) { return m.shape.distal_radius[s]; });
    }
    for (const auto& [name, field] : kJointPlacements)
      shared.shape.*field =
          medianOf([field = field](const BodyModel& m) { return m.shape.*field; });
    std::vector<BodyModel> models;
    std::vector<const Cloud*> clouds;
    for (size_t i : fitted) {
      BodyModel model = directs[i].fit.model;
      model.r = shared.r;
      model.shape = shared.shape;
      models.push_back(model);
      clouds.push_back(&directs[i].without_feet);
    }
    if (options.refine) {
      // An unseen pelvis in any scan: the thighs keep the direct fit's lengths (pelvisSeen). A leg
      // whose knee bends clearly in no scan keeps its thigh's too (kneeBentInWalk).
      RefinementOptions refinement = options.refinement;
      for (size_t i : fitted) refinement.hold_thighs_in_walks |= !directs[i].pelvis_seen;
      for (int side = 0; side < 2; ++side)
        refinement.straight_knee[side] = !kneeBentInWalk(models, side);
      result.refinement = refineWalk(models, clouds, refinement, options.joint_limits);
      for (size_t k = 0; k < fitted.size(); ++k)
        aimLowerLegsAtAnkles(models[k], directs[fitted[k]], options.joint_limits);
      // Each lower leg: the median over the scans where its foot is planted (else over all): a
      // foot rolled onto its toes, as at toe-off with the knee bent 35-40 deg, ends its shank's
      // reach short of the sole (CMU walks: 40-86 mm). A leg whose knee bends clearly in no scan
      // takes every scan: its foot does not roll so (its reach: the mesh people's soles within
      // -8..+3 mm in every scan), and its knee, hanging from the hip by the held thigh, rises and
      // falls with the pelvis between scans (mesh people on the sampler: 20 mm SD), so a length
      // from the one planted scan carried that scan's error into the walk (50 people's lower legs
      // 13 mm SD between a person's walks, 10 mm over every scan).
      std::vector<double> shank_lengths[2], planted_lengths[2];
      for (size_t k = 0; k < fitted.size(); ++k) {
        const auto shanks =
            shankLengthsToSoles(models[k], directs[fitted[k]], options.refinement.min_length);
        for (int side = 0; side < 2; ++side) {
          shank_lengths[side].push_back(shanks.length[side]);
          if (shanks.planted[side]) planted_lengths[side].push_back(shanks.length[side]);
        }
      }
      for (int side = 0; side < 2; ++side)
        if (!refinement.straight_knee[side] && !planted_lengths[side].empty())
          shank_lengths[side] = planted_lengths[side];
      // Each lower arm: the median elbow-to-tip distance over the scans whose tip was found.
      std::vector<HandTips> tips;
      std::vector<double> forearm_lengths[2];
      for (size_t k = 0; k < fitted.size(); ++k) {
        tips.push_back(
            elbowToHandTips(models[k], directs[fitted[k]], options.refinement.max_length_change));
        for (int side = 0; side < 2; ++side)
          if (tips.back().found[side]) forearm_lengths[side].push_back(tips.back().length[side]);
      }
      std::array<double, 2> forearms{};
      for (int side = 0; side < 2; ++side)
        if (!forearm_lengths[side].empty()) forearms[side] = median(forearm_lengths[side]);
      // The head: the median base-to-vertex distance over the scans whose vertex agrees.
      std::vector<double> crowns, head_lengths;
      for (size_t k = 0; k < fitted.size(); ++k) {
        crowns.push_back(
            headBaseToCrown(models[k], directs[fitted[k]], options.refinement.max_length_change));
        if (crowns.back() > 0) head_lengths.push_back(crowns.back());
      }
      const double head_length = head_lengths.empty() ? 0.0 : median(head_lengths);
      for (size_t k = 0; k < fitted.size(); ++k) {
        BodyModel& model = models[k];
        model.r[kRightLowerLeg] = median(shank_lengths[0]);
        model.r[kLeftLowerLeg] = median(shank_lengths[1]);
        aimLowerArmsAtHandTips(model, directs[fitted[k]], tips[k], forearms, options.joint_limits);
        aimHeadAtCrown(model, directs[fitted[k]], crowns[k] > 0, head_length, options.joint_limits);
      }
    }
    for (size_t k = 0; k < fitted.size(); ++k) {
      directs[fitted[k]].fit.model = models[k];
      directs[fitted[k]].fit.refinement = result.refinement;
    }
  }
  for (size_t i = 0; i < directs.size(); ++i) {
    finishFit(walk[i], options, directs[i]);
    result.scans.push_back(std::move(directs[i].fit));
  }
  return result;
}

}  // namespace body_gait_model
