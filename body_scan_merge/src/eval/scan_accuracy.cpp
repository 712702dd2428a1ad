#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/sim/triangle_mesh.h>
#include <body_scan_merge/eval/scan_accuracy.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace body_scan_merge::eval {
namespace {

// Uniform hash grid of 3D points for neighbour queries within one cell size.
class PointGrid {
 public:
  explicit PointGrid(double cell) : cell_(cell) {}
  void add(const Eigen::Vector3d& p, size_t index) { cells_[key(p)].push_back(index); }
  // Calls visit(index) for every point in the 27 cells around p.
  template <typename Visit>
  void forNear(const Eigen::Vector3d& p, Visit visit) const {
    const int64_t x = cellOf(p.x()), y = cellOf(p.y()), z = cellOf(p.z());
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(pack(x + dx, y + dy, z + dz));
          if (it == cells_.end()) continue;
          for (size_t index : it->second) visit(index);
        }
  }

 private:
  int64_t cellOf(double v) const { return static_cast<int64_t>(std::floor(v / cell_)); }
  static uint64_t pack(int64_t x, int64_t y, int64_t z) {
    return (static_cast<uint64_t>(x & 0x1FFFFF) << 42) |
           (static_cast<uint64_t>(y & 0x1FFFFF) << 21) | static_cast<uint64_t>(z & 0x1FFFFF);
  }
  uint64_t key(const Eigen::Vector3d& p) const {
    return pack(cellOf(p.x()), cellOf(p.y()), cellOf(p.z()));
  }
  double cell_;
  std::unordered_map<uint64_t, std::vector<size_t>> cells_;
};

double ellipsoidArea(const Eigen::Vector3d& r) {  // Knud Thomsen's formula (error < 1.1 %)
  const double p = 1.6075;
  const double a = std::pow(r.x(), p), b = std::pow(r.y(), p), c = std::pow(r.z(), p);
  return 4 * M_PI * std::pow((a * b + a * c + b * c) / 3, 1 / p);
}

bool endsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

const Eigen::Vector3d& joint(const std::vector<body_scan_driver::sim::SkeletonJoint>& skeleton,
                             const std::string& name) {
  for (const auto& j : skeleton)
    if (j.name == name) return j.position;
  throw std::invalid_argument("the scene's skeleton has no joint '" + name +
                              "': is there a human body in the scene?");
}

}  // namespace

const char* regionName(Region region) {
  switch (region) {
    case Region::kSoles:
      return "soles";
    case Region::kUnderChin:
      return "under_chin";
    case Region::kArmpitLeft:
      return "armpit_left";
    case Region::kArmpitRight:
      return "armpit_right";
    case Region::kGroin:
      return "groin";
    case Region::kTorsoSideLeft:
      return "torso_side_left";
    case Region::kTorsoSideRight:
      return "torso_side_right";
    default:
      return "other";
  }
}

std::vector<SurfaceSample> sampleBodySurface(const body_scan_driver::sim::Scene& scene,
                                             const std::string& body_name, double spacing,
                                             std::vector<std::string>* segment_names) {
  std::vector<const body_scan_driver::sim::Ellipsoid*> parts;
  std::vector<std::string> segments;
  const body_scan_driver::sim::TriangleMesh* skin = nullptr;  // a mesh human's
  for (const auto& surface : scene.surfaces()) {
    if (surface->name.rfind(body_name + "/", 0) != 0) continue;
    if (const auto* mesh = dynamic_cast<const body_scan_driver::sim::TriangleMesh*>(surface.get()))
      skin = mesh;
    const auto* ellipsoid = dynamic_cast<const body_scan_driver::sim::Ellipsoid*>(surface.get());
    if (!ellipsoid) continue;
    parts.push_back(ellipsoid);
    segments.push_back(surface->name.substr(body_name.size() + 1));
  }
  if (parts.empty() && !skin)
    throw std::invalid_argument("the scene has no body named '" + body_name + "'");
  if (skin) segments = skin->partNames();

  // Body frame from the true skeleton: up = world z, left = the hips' direction, forward = x.
  const auto& skeleton = scene.skeleton();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d left = joint(skeleton, "left_hip") - joint(skeleton, "right_hip");
  left.z() = 0;
  left.normalize();
  const Eigen::Vector3d forward = left.cross(up);
  const Eigen::Vector3d neck = joint(skeleton, "neck"), head_top = joint(skeleton, "head_top");
  const double chin_z = neck.z() + 0.286 * (head_top.z() - neck.z());  // Drillis & Contini
  const double hip_z = 0.5 * (joint(skeleton, "left_hip").z() + joint(skeleton, "right_hip").z());
  double crotch_z = hip_z;
  for (size_t i = 0; i < parts.size(); ++i)
    if (segments[i] == "pelvis") {
      const Eigen::Matrix3d& o = parts[i]->orientation();
      const Eigen::Vector3d& r = parts[i]->radii();
      crotch_z = parts[i]->center().z() -
                 std::sqrt(std::pow(o(2, 0) * r.x(), 2) + std::pow(o(2, 1) * r.y(), 2) +
                           std::pow(o(2, 2) * r.z(), 2));
    }

  auto regionOf = [&](const std::string& segment, const Eigen::Vector3d& p,
                      const Eigen::Vector3d& n) {
    if (endsWith(segment, "foot") && n.dot(up) < -0.5) return Region::kSoles;
    if ((segment == "head" || segment == "neck" || segment == "hair") && p.z() >= neck.z() - 0.01 &&
        p.z() <= chin_z + 0.02 && (p - neck).dot(forward) > 0 && n.dot(up) < 0.2)
      return Region::kUnderChin;
    const bool torso = segment == "chest" || segment == "shoulders" || segment == "abdomen" ||
                       segment == "pelvis" || segment == "torso";
    for (int side = 0; side < 2; ++side) {
      const std::string prefix = side == 0 ? "left_" : "right_";
      const Eigen::Vector3d outward = side == 0 ? left : Eigen::Vector3d(-left);
      const Eigen::Vector3d shoulder = joint(skeleton, prefix + "shoulder");
      const bool arm = segment == prefix + "upper_arm" || segment == prefix + "shoulder";
      if ((torso || arm) && p.z() <= shoulder.z() - 0.03 && p.z() >= shoulder.z() - 0.15 &&
          std::abs((p - shoulder).dot(left)) < 0.10 &&
          ((torso && n.dot(outward) > 0.3) || (arm && n.dot(outward) < -0.3)))
        return side == 0 ? Region::kArmpitLeft : Region::kArmpitRight;
    }
    if (p.z() >= crotch_z - 0.12 && p.z() <= crotch_z + 0.03) {
      for (int side = 0; side < 2; ++side) {
        const std::string prefix = side == 0 ? "left_" : "right_";
        const Eigen::Vector3d inward = side == 0 ? Eigen::Vector3d(-left) : left;
        if ((segment == prefix + "thigh" || segment == prefix + "hip") && n.dot(inward) > 0.3)
          return Region::kGroin;
      }
      if (segment == "pelvis" && n.dot(up) < -0.5) return Region::kGroin;
    }
    const double shoulder_z =
        0.5 * (joint(skeleton, "left_shoulder").z() + joint(skeleton, "right_shoulder").z());
    if (torso && p.z() >= hip_z && p.z() <= shoulder_z - 0.10) {
      if (n.dot(left) > std::cos(M_PI / 4)) return Region::kTorsoSideLeft;
      if (-n.dot(left) > std::cos(M_PI / 4)) return Region::kTorsoSideRight;
    }
    return Region::kOther;
  };

  std::vector<SurfaceSample> samples;
  if (skin) {
    // The mesh's crotch: its pelvis part's lowest point near the midline.
    const Eigen::Vector3d hip_mid =
        0.5 * (joint(skeleton, "left_hip") + joint(skeleton, "right_hip"));
    crotch_z = hip_z;
    const auto& names = skin->partNames();
    for (size_t t = 0; t < skin->triangles().size(); ++t)
      if (names[skin->trianglePart()[t]] == "pelvis")
        for (const int v : skin->triangles()[t]) {
          const Eigen::Vector3d p = skin->vertices()[v].cast<double>();
          if (std::abs((p - hip_mid).dot(left)) < 0.03) crotch_z = std::min(crotch_z, p.z());
        }
    // Each triangle split into n^2 equal sub-triangles (n ~ its size / spacing), one sample at
    // each one's centroid.
    for (size_t t = 0; t < skin->triangles().size(); ++t) {
      const auto& tri = skin->triangles()[t];
      const Eigen::Vector3d a = skin->vertices()[tri[0]].cast<double>(),
                            b = skin->vertices()[tri[1]].cast<double>(),
                            c = skin->vertices()[tri[2]].cast<double>();
      const Eigen::Vector3d cross = (b - a).cross(c - a);
      const double area = 0.5 * cross.norm();
      if (!(area > 0)) continue;
      const Eigen::Vector3d normal = cross.normalized();
      const int n = std::max(1, static_cast<int>(std::ceil(std::sqrt(area) / spacing)));
      const int part = skin->trianglePart().empty() ? 0 : skin->trianglePart()[t];
      const std::string& segment = segments.empty() ? std::string() : segments[part];
      auto add = [&](double u, double v) {
        SurfaceSample sample;
        sample.position = a + u / n * (b - a) + v / n * (c - a);
        sample.normal = normal;
        sample.area = area / (n * n);
        sample.region = regionOf(segment, sample.position, normal);
        sample.segment = part;
        samples.push_back(sample);
      };
      for (int i = 0; i < n; ++i)
        for (int j = 0; i + j < n; ++j) {
          add(i + 1.0 / 3, j + 1.0 / 3);
          if (i + j < n - 1) add(i + 2.0 / 3, j + 2.0 / 3);
        }
    }
    if (segment_names) *segment_names = segments;
    return samples;
  }
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (size_t i = 0; i < parts.size(); ++i) {
    const body_scan_driver::sim::Ellipsoid& part = *parts[i];
    const Eigen::Vector3d& r = part.radii();
    const double area = ellipsoidArea(r);
    const int count = std::max(16, static_cast<int>(std::ceil(area / (spacing * spacing))));
    // Fibonacci points on the unit sphere, mapped to the ellipsoid; each weighted by the area
    // element of the mapping, so the weights sum to the ellipsoid's area.
    std::vector<SurfaceSample> part_samples;
    double weight_sum = 0;
    for (int k = 0; k < count; ++k) {
      const double z = 1 - (2.0 * k + 1) / count, radius = std::sqrt(1 - z * z);
      const Eigen::Vector3d u(radius * std::cos(golden * k), radius * std::sin(golden * k), z);
      SurfaceSample sample;
      sample.position = part.center() + part.orientation() * r.cwiseProduct(u);
      sample.normal = (part.orientation() * u.cwiseQuotient(r)).normalized();
      sample.area =
          Eigen::Vector3d(r.y() * r.z() * u.x(), r.x() * r.z() * u.y(), r.x() * r.y() * u.z())
              .norm();
      weight_sum += sample.area;
      part_samples.push_back(sample);
    }
    for (SurfaceSample& sample : part_samples) {
      sample.area *= area / weight_sum;
      bool inside = false;
      for (size_t j = 0; j < parts.size() && !inside; ++j)
        inside = j != i && parts[j]->contains(sample.position);
      if (inside) continue;
      sample.region = regionOf(segments[i], sample.position, sample.normal);
      sample.segment = static_cast<int>(i);
      samples.push_back(sample);
    }
  }
  if (segment_names) *segment_names = segments;
  return samples;
}

ScanAccuracy evaluateScan(const std::vector<float>& cloud,
                          const body_scan_driver::sim::Scene& scene, const AccuracyOptions& options,
                          const std::string& body_name) {
  std::vector<std::string> segment_names;
  const std::vector<SurfaceSample> samples =
      sampleBodySurface(scene, body_name, options.spacing, &segment_names);
  ScanAccuracy result;
  result.points = cloud.size() / 4;
  bool has_floor = false;
  for (const auto& surface : scene.surfaces())
    has_floor |= dynamic_cast<const body_scan_driver::sim::Plane*>(surface.get()) != nullptr;

  // Distances: nearest true sample, point-to-plane on its normal (samples are 2 mm apart, so
  // the tangent plane is exact to a few micrometres); the floor when it is nearer.
  const double search = std::max(options.outlier_distance, 4 * options.spacing);
  PointGrid sample_grid(search);
  for (size_t i = 0; i < samples.size(); ++i) sample_grid.add(samples[i].position, i);
  std::vector<double> distances(result.points);
  for (size_t k = 0; k < result.points; ++k) {
    const Eigen::Vector3d p(cloud[4 * k], cloud[4 * k + 1], cloud[4 * k + 2]);
    double best = std::numeric_limits<double>::infinity();
    size_t nearest = samples.size();
    sample_grid.forNear(p, [&](size_t i) {
      const double d = (p - samples[i].position).squaredNorm();
      if (d < best) best = d, nearest = i;
    });
    double distance = std::numeric_limits<double>::infinity();
    if (nearest < samples.size()) {
      const Eigen::Vector3d offset = p - samples[nearest].position;
      const double normal_part = std::abs(offset.dot(samples[nearest].normal));
      const double tangential =
          std::sqrt(std::max(0.0, offset.squaredNorm() - normal_part * normal_part));
      distance = tangential <= 2 * options.spacing ? normal_part : offset.norm();
    }
    if (has_floor) distance = std::min(distance, std::abs(p.z()));
    distances[k] = distance;
  }
  double sum = 0, inlier_sum = 0;
  size_t inliers = 0;
  for (size_t k = 0; k < distances.size(); ++k) {
    double& d = distances[k];
    if (d > options.outlier_distance) {
      ++result.outliers;
      result.outlier_indices.push_back(k);
      d = std::min(d, 1.0);  // unbounded for the mean: cap at 1 m
    } else {
      inlier_sum += d;
      ++inliers;
    }
    sum += d;
  }
  if (!distances.empty()) {
    result.mean_distance = sum / distances.size();
    result.mean_distance_inliers = inliers ? inlier_sum / inliers : 0;
    std::vector<double> sorted = distances;
    std::sort(sorted.begin(), sorted.end());
    result.median_distance = sorted[sorted.size() / 2];
    result.p95_distance = sorted[std::min(sorted.size() - 1, sorted.size() * 95 / 100)];
  }

  // Coverage: a true sample is covered by a cloud point within coverage_distance.
  PointGrid cloud_grid(options.coverage_distance);
  for (size_t k = 0; k < result.points; ++k)
    cloud_grid.add({cloud[4 * k], cloud[4 * k + 1], cloud[4 * k + 2]}, k);
  const double limit2 = options.coverage_distance * options.coverage_distance;
  for (const SurfaceSample& sample : samples) {
    bool covered = false;
    cloud_grid.forNear(sample.position, [&](size_t k) {
      covered |=
          (Eigen::Vector3d(cloud[4 * k], cloud[4 * k + 1], cloud[4 * k + 2]) - sample.position)
              .squaredNorm() <= limit2;
    });
    RegionCoverage& region = result.regions[sample.region];
    region.area += sample.area;
    region.covered_area += covered ? sample.area : 0;
    RegionCoverage& segment = result.segments[segment_names[sample.segment]];
    segment.area += sample.area;
    segment.covered_area += covered ? sample.area : 0;
    if (sample.region == Region::kSoles) continue;
    result.body.area += sample.area;
    result.body.covered_area += covered ? sample.area : 0;
  }
  return result;
}

std::string accuracyReportYaml(const ScanAccuracy& accuracy, const std::string& description) {
  std::ostringstream out;
  out << std::setprecision(6);
  out << "# Scan accuracy against the simulator's true surface (body_scan_merge evaluate_scan)\n"
      << "description: \"" << description << "\"\n"
      << "points: " << accuracy.points << "\n"
      << "outliers: " << accuracy.outliers << "\n"
      << "distance_mm:\n"
      << "  mean: " << 1000 * accuracy.mean_distance << "\n"
      << "  mean_without_outliers: " << 1000 * accuracy.mean_distance_inliers << "\n"
      << "  median: " << 1000 * accuracy.median_distance << "\n"
      << "  p95: " << 1000 * accuracy.p95_distance << "\n"
      << "coverage:  # area fraction of the true surface with a point within 5 mm\n"
      << "  body_without_soles: " << accuracy.body.fraction() << "\n"
      << "  body_area_m2: " << accuracy.body.area << "\n"
      << "  regions:\n";
  for (const auto& [region, coverage] : accuracy.regions)
    out << "    " << regionName(region) << ": {fraction: " << coverage.fraction()
        << ", area_m2: " << coverage.area << "}\n";
  out << "  segments:\n";
  for (const auto& [segment, coverage] : accuracy.segments)
    out << "    " << segment << ": {fraction: " << coverage.fraction()
        << ", uncovered_m2: " << coverage.area - coverage.covered_area << "}\n";
  return out.str();
}

void writeAccuracyReport(const std::string& path, const ScanAccuracy& accuracy,
                         const std::string& description) {
  body_scan_driver::writeFileAtomically(path, accuracyReportYaml(accuracy, description));
}

}  // namespace body_scan_merge::eval
