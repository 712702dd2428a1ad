// Scan accuracy against the simulator's true surface (issue 4, must-show 3).
//
// True surface: every body ellipsoid x = c + M u (M = R diag(r), u on the unit sphere) is
// sampled area-uniformly by rejection: candidates uniform on the sphere are kept with
// probability J(u) / max J, J(u) = det(M) |M^-T u| the area stretch (Nanson's formula); each
// kept sample stands for area(ellipsoid) / kept. Samples inside another body ellipsoid are not
// skin (the segments overlap at the joints) and are dropped.
//
// Regions, in the body's frame from the true skeleton (up = world z, left = from the right
// to the left shoulder, horizontal; forward = left x up), first match wins:
//  soles        foot surface facing down (n.z < -0.5): the subject stands on them; excluded.
//  under_chin   head surface facing down (n.z < -0.3) in front of the neck joint (> -2 cm),
//               and neck surface facing forward (n.forward > 0.3) above 3 cm below the chin
//               (chin z = neck + 0.286 (head_top - neck), the chin-to-shoulder /
//               vertex-to-shoulder ratio of the body model).
//  armpit_L/R   torso/shoulder/upper-arm surface from 8 cm below to the shoulder joint, laterally
//               between 55 % of the shoulder offset and the joint, within 7 cm fore/aft of it,
//               facing the gap: torso facing out (n.side > 0.2), arm facing in (n.side < -0.2).
//  groin        pelvis/hip/thigh surface from 10 cm below the crotch (the lower edge of the
//               pelvis at the midline) to 2 cm above it, between the hip joints, facing the
//               midline (n.side sign opposite to its side, |n.side| > 0.2) or down (n.z < -0.5).
//  torso_side   pelvis/abdomen/chest/shoulders surface between the hip and shoulder joint
//               heights facing +-left within 45 deg (|n.left| > cos 45 deg).
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/sim/scene.h>
#include <body_scan_merge/scan_accuracy.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace body_scan {

const char* bodyRegionName(BodyRegion region) {
  switch (region) {
    case BodyRegion::kOther:
      return "other";
    case BodyRegion::kSoles:
      return "soles";
    case BodyRegion::kUnderChin:
      return "under_chin";
    case BodyRegion::kArmpitLeft:
      return "armpit_left";
    case BodyRegion::kArmpitRight:
      return "armpit_right";
    case BodyRegion::kGroin:
      return "groin";
    case BodyRegion::kTorsoSideLeft:
      return "torso_side_left";
    case BodyRegion::kTorsoSideRight:
      return "torso_side_right";
  }
  return "unknown";
}

namespace {

bool startsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// Segment name after the body prefix, side stripped ("left_upper_arm" -> "upper_arm").
std::string segmentOf(const std::string& name, const std::string& prefix, int& side) {
  std::string segment = name.substr(prefix.size());
  side = 0;
  if (startsWith(segment, "left_")) {
    side = 1;
    segment = segment.substr(5);
  } else if (startsWith(segment, "right_")) {
    side = -1;
    segment = segment.substr(6);
  }
  return segment;
}

struct BodyFrame {
  Eigen::Vector3d up{0, 0, 1}, left, forward, centre, neck;
  double chin_z = 0, hip_z = 0, shoulder_z = 0, crotch_z = 0, hip_half_width = 0;
  Eigen::Vector3d shoulder[2];  // [0] right, [1] left
};

BodyFrame bodyFrameOf(const sim::Scene& scene) {
  std::map<std::string, Eigen::Vector3d> joints;
  for (const auto& joint : scene.skeleton()) joints[joint.name] = joint.position;
  for (const char* name :
       {"head_top", "neck", "pelvis", "left_shoulder", "right_shoulder", "left_hip", "right_hip"})
    if (!joints.count(name))
      throw std::runtime_error(std::string("scan accuracy: the scene's skeleton has no '") + name +
                               "' joint; evaluate a scene with one human (type: human)");
  BodyFrame f;
  Eigen::Vector3d left = joints["left_shoulder"] - joints["right_shoulder"];
  left.z() = 0;
  f.left = left.normalized();
  f.forward = f.left.cross(f.up);
  f.centre = joints["pelvis"];
  f.neck = joints["neck"];
  f.chin_z = joints["neck"].z() + 0.286 * (joints["head_top"].z() - joints["neck"].z());
  f.hip_z = 0.5 * (joints["left_hip"].z() + joints["right_hip"].z());
  f.shoulder[0] = joints["right_shoulder"];
  f.shoulder[1] = joints["left_shoulder"];
  f.shoulder_z = 0.5 * (f.shoulder[0].z() + f.shoulder[1].z());
  f.hip_half_width = 0.5 * std::abs((joints["left_hip"] - joints["right_hip"]).dot(f.left));
  return f;
}

BodyRegion regionOf(const std::string& segment, int side, const Eigen::Vector3d& p,
                    const Eigen::Vector3d& n, const BodyFrame& f) {
  const bool trunk =
      segment == "pelvis" || segment == "abdomen" || segment == "chest" || segment == "shoulders";
  const double lateral = (p - f.centre).dot(f.left);
  const double n_left = n.dot(f.left);
  if (segment == "foot" && n.z() < -0.5) return BodyRegion::kSoles;
  if ((segment == "head" && n.z() < -0.3 && (p - f.neck).dot(f.forward) > -0.02) ||
      (segment == "neck" && p.z() > f.chin_z - 0.03 && n.dot(f.forward) > 0.3))
    return BodyRegion::kUnderChin;
  for (int s = 0; s < 2; ++s) {
    const double sign = s == 1 ? 1.0 : -1.0;  // +left for the left armpit
    const Eigen::Vector3d& joint = f.shoulder[s];
    const double joint_lateral = sign * (joint - f.centre).dot(f.left);
    const double out = sign * lateral;
    const bool arm = (segment == "upper_arm" || segment == "shoulder") && side == sign;
    if ((!trunk && !arm) || p.z() > joint.z() || p.z() < joint.z() - 0.08 ||
        out < 0.55 * joint_lateral || out > joint_lateral ||
        std::abs((p - joint).dot(f.forward)) > 0.07)
      continue;
    const double facing = sign * n_left;  // > 0: facing away from the midline
    if ((trunk && facing > 0.2) || (arm && facing < -0.2))
      return s == 1 ? BodyRegion::kArmpitLeft : BodyRegion::kArmpitRight;
  }
  const bool leg = segment == "hip" || segment == "thigh";
  if ((leg || segment == "pelvis") && p.z() <= f.crotch_z + 0.02 && p.z() >= f.crotch_z - 0.10 &&
      std::abs(lateral) < f.hip_half_width) {
    const bool toward_midline = lateral * n_left < 0 && std::abs(n_left) > 0.2;
    if (toward_midline || n.z() < -0.5) return BodyRegion::kGroin;
  }
  if (trunk && p.z() >= f.hip_z && p.z() <= f.shoulder_z && std::abs(n_left) > std::sqrt(0.5))
    return n_left > 0 ? BodyRegion::kTorsoSideLeft : BodyRegion::kTorsoSideRight;
  return BodyRegion::kOther;
}

// Uniform hash grid of points for radius queries.
class PointGrid {
 public:
  PointGrid(const std::vector<Eigen::Vector3f>& points, double cell) : cell_(cell) {
    for (size_t i = 0; i < points.size(); ++i) cells_[keyOf(points[i])].push_back(i);
  }
  // Calls visit(index) for every point in the cells overlapping the cube of half size radius
  // around p (radius <= cell: the 27 neighbouring cells).
  template <typename Visit>
  void forNear(const Eigen::Vector3f& p, Visit&& visit) const {
    const Eigen::Vector3i c = cellOf(p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (size_t i : it->second) visit(i);
        }
  }

 private:
  Eigen::Vector3i cellOf(const Eigen::Vector3f& p) const {
    return (p.cast<double>() / cell_).array().floor().cast<int>();
  }
  static int64_t key(const Eigen::Vector3i& c) {
    return (int64_t(c.x() & 0x1FFFFF) << 42) | (int64_t(c.y() & 0x1FFFFF) << 21) |
           int64_t(c.z() & 0x1FFFFF);
  }
  int64_t keyOf(const Eigen::Vector3f& p) const { return key(cellOf(p)); }

  double cell_;
  std::unordered_map<int64_t, std::vector<size_t>> cells_;
};

double percentile(std::vector<double>& values, double q) {
  if (values.empty()) return 0.0;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * (values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace

std::vector<TrueSurfaceSample> sampleTrueSurface(const sim::Scene& scene,
                                                 const ScanAccuracyOptions& options) {
  if (!(options.sample_spacing > 0))
    throw std::runtime_error("scan accuracy: sample_spacing must be > 0 (e.g. 0.0025 m)");
  std::vector<std::pair<int, const sim::Ellipsoid*>> body;
  for (size_t i = 0; i < scene.surfaces().size(); ++i) {
    const auto& surface = scene.surfaces()[i];
    if (!startsWith(surface->name, options.body_prefix)) continue;
    if (auto e = dynamic_cast<const sim::Ellipsoid*>(surface.get()))
      body.emplace_back(static_cast<int>(i), e);
  }
  if (body.empty())
    throw std::runtime_error("scan accuracy: the scene has no ellipsoid named '" +
                             options.body_prefix + "...'; add a human (type: human) to it");
  BodyFrame frame = bodyFrameOf(scene);

  std::mt19937 rng(options.seed);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<TrueSurfaceSample> samples;
  for (const auto& [index, ellipsoid] : body) {
    const Eigen::Matrix3d m = ellipsoid->orientation() * ellipsoid->radii().asDiagonal();
    const Eigen::Matrix3d m_inv_t = m.inverse().transpose();
    const double det = std::abs(m.determinant());
    const Eigen::Vector3d r = ellipsoid->radii();
    // Area of the ellipsoid (Knud Thomsen's approximation, <= 1.1 % error) and the largest
    // stretch det * |M^-T u| = det / smallest radius.
    const double pp = 1.6075;
    const double area = 4 * M_PI *
                        std::pow((std::pow(r.x() * r.y(), pp) + std::pow(r.x() * r.z(), pp) +
                                  std::pow(r.y() * r.z(), pp)) /
                                     3,
                                 1 / pp);
    const double max_stretch = det / r.minCoeff();
    const size_t wanted =
        static_cast<size_t>(std::ceil(area / std::pow(options.sample_spacing, 2)));
    const double weight = area / wanted;
    size_t kept = 0;
    while (kept < wanted) {
      const Eigen::Vector3d u = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
      const Eigen::Vector3d g = m_inv_t * u;
      if (uniform(rng) * max_stretch > det * g.norm()) continue;
      ++kept;
      const Eigen::Vector3d p = ellipsoid->center() + m * u;
      bool inside = false;
      for (const auto& [other_index, other] : body)
        if (other != ellipsoid && (p - other->center()).norm() < other->boundingRadius() &&
            other->contains(p)) {
          inside = true;
          break;
        }
      if (inside) continue;
      TrueSurfaceSample s;
      s.point = p.cast<float>();
      s.normal = g.normalized().cast<float>();
      s.area = static_cast<float>(weight);
      s.surface_index = index;
      samples.push_back(s);
    }
  }
  // Crotch: the lowest pelvis skin near the midline.
  frame.crotch_z = frame.hip_z;
  for (const auto& s : samples) {
    const std::string& name = scene.surfaces()[s.surface_index]->name;
    if (name == options.body_prefix + "pelvis" &&
        std::abs((s.point.cast<double>() - frame.centre).dot(frame.left)) < 0.02)
      frame.crotch_z = std::min(frame.crotch_z, double(s.point.z()));
  }
  for (auto& s : samples) {
    int side = 0;
    const std::string segment =
        segmentOf(scene.surfaces()[s.surface_index]->name, options.body_prefix, side);
    s.region = regionOf(segment, side, s.point.cast<double>(), s.normal.cast<double>(), frame);
  }
  return samples;
}

ScanAccuracy evaluateScan(const std::vector<Eigen::Vector3f>& cloud,
                          const std::vector<TrueSurfaceSample>& samples,
                          const ScanAccuracyOptions& options) {
  ScanAccuracy result;
  std::vector<Eigen::Vector3f> sample_points;
  sample_points.reserve(samples.size());
  for (const auto& s : samples) sample_points.push_back(s.point);
  const double cell = std::max(options.near_body, options.coverage_radius);
  const PointGrid grid(sample_points, cell);
  const float near2 = static_cast<float>(options.near_body * options.near_body);
  const float cover2 = static_cast<float>(options.coverage_radius * options.coverage_radius);
  std::vector<char> covered(samples.size(), 0);
  std::vector<double> distances;
  distances.reserve(cloud.size());
  for (const auto& p : cloud) {
    if (!p.allFinite()) continue;
    ++result.points;
    if (p.z() < options.floor_height) {
      ++result.floor_points;
      continue;
    }
    float best = near2;
    long nearest = -1;
    grid.forNear(p, [&](size_t i) {
      const float d2 = (sample_points[i] - p).squaredNorm();
      if (d2 <= cover2) covered[i] = 1;
      if (d2 < best) {
        best = d2;
        nearest = static_cast<long>(i);
      }
    });
    if (nearest < 0) {
      ++result.far_points;
      continue;
    }
    const double d = std::abs((p - samples[nearest].point).dot(samples[nearest].normal));
    distances.push_back(d);
    if (d > options.outlier_distance) ++result.outliers;
  }
  result.evaluated_points = distances.size();
  if (!distances.empty()) {
    double sum = 0;
    for (double d : distances) sum += d;
    result.mean_distance = sum / distances.size();
    result.median_distance = percentile(distances, 0.5);
    result.p95_distance = percentile(distances, 0.95);
  }
  for (size_t i = 0; i < samples.size(); ++i) {
    RegionCoverage& region = result.regions[static_cast<int>(samples[i].region)];
    RegionCoverage& surface = result.surfaces[samples[i].surface_index];
    region.area += samples[i].area;
    if (samples[i].region != BodyRegion::kSoles) surface.area += samples[i].area;
    if (covered[i]) {
      region.covered_area += samples[i].area;
      if (samples[i].region != BodyRegion::kSoles) surface.covered_area += samples[i].area;
    }
  }
  double covered_area = 0;
  for (int r = 0; r < kBodyRegionCount; ++r) {
    if (static_cast<BodyRegion>(r) == BodyRegion::kSoles) continue;
    result.body_area += result.regions[r].area;
    covered_area += result.regions[r].covered_area;
  }
  result.coverage = result.body_area > 0 ? covered_area / result.body_area : 0.0;
  return result;
}

ScanAccuracy evaluateScan(const std::vector<Eigen::Vector3f>& cloud, const sim::Scene& scene,
                          const ScanAccuracyOptions& options) {
  return evaluateScan(cloud, sampleTrueSurface(scene, options), options);
}

std::string scanAccuracyYaml(const ScanAccuracy& a, const ScanAccuracyOptions& options,
                             const sim::Scene* scene) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(3);
  out << "# Scan accuracy against the simulator's true surface (evaluate_scan)\n";
  out << "points: " << a.points << "\n";
  out << "floor_points: " << a.floor_points << "\n";
  out << "far_points: " << a.far_points << "  # farther than " << 1000 * options.near_body
      << " mm from the body\n";
  out << "evaluated_points: " << a.evaluated_points << "\n";
  out << "outliers: " << a.outliers << "  # farther than " << 1000 * options.outlier_distance
      << " mm\n";
  out << "mean_distance_mm: " << 1000 * a.mean_distance << "\n";
  out << "median_distance_mm: " << 1000 * a.median_distance << "\n";
  out << "p95_distance_mm: " << 1000 * a.p95_distance << "\n";
  out << "body_area_m2: " << a.body_area << "  # soles excluded\n";
  out << "coverage_radius_mm: " << 1000 * options.coverage_radius << "\n";
  out << "coverage_percent: " << 100 * a.coverage << "\n";
  out << "regions:\n";
  for (int r = 0; r < kBodyRegionCount; ++r) {
    out << "  " << bodyRegionName(static_cast<BodyRegion>(r))
        << ": {area_m2: " << std::setprecision(4) << a.regions[r].area
        << ", coverage_percent: " << std::setprecision(2) << 100 * a.regions[r].fraction() << "}\n";
    out << std::setprecision(3);
  }
  if (scene) {
    out << "surfaces:  # soles excluded\n";
    for (const auto& [index, coverage] : a.surfaces)
      out << "  " << scene->surfaces().at(index)->name << ": {area_m2: " << std::setprecision(4)
          << coverage.area << ", coverage_percent: " << std::setprecision(2)
          << 100 * coverage.fraction() << "}\n";
  }
  return out.str();
}

void writeScanAccuracyReport(const std::string& path, const ScanAccuracy& accuracy,
                             const ScanAccuracyOptions& options, const sim::Scene* scene) {
  writeFileAtomically(path, scanAccuracyYaml(accuracy, options, scene));
}

}  // namespace body_scan
