#include <body_scan_merge/timing_groups.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

namespace body_scan_merge {
namespace {

struct SurfacePoint {
  Eigen::Vector3d position, normal;  // world
  int part = -1;                     // proxy part it lies on (-1: the floor)
};

// True if the segment from a to b crosses the side of the part (a vertical elliptic cylinder).
bool crosses(const ProxyCylinder& part, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double px = (a.x() - part.center_x) / part.semi_axis_x;
  const double py = (a.y() - part.center_y) / part.semi_axis_y;
  const double dx = (b.x() - a.x()) / part.semi_axis_x, dy = (b.y() - a.y()) / part.semi_axis_y;
  const double qa = dx * dx + dy * dy, qb = 2 * (px * dx + py * dy), qc = px * px + py * py - 1;
  const double discriminant = qb * qb - 4 * qa * qc;
  if (qa <= 0 || discriminant < 0) return false;
  for (double sign : {-1.0, 1.0}) {
    const double t = (-qb + sign * std::sqrt(discriminant)) / (2 * qa);
    const double z = a.z() + t * (b.z() - a.z());
    if (t > 1e-6 && t < 1 && z >= part.min_z && z <= part.max_z) return true;
  }
  return false;
}

// True if another part of the proxy lies between the sample and `to` (a source or camera).
bool shadowed(const InterferenceProxy& proxy, const SurfacePoint& point,
              const Eigen::Vector3d& to) {
  for (size_t i = 0; i < proxy.parts.size(); ++i)
    if (static_cast<int>(i) != point.part && crosses(proxy.parts[i], point.position, to))
      return true;
  return false;
}

std::vector<SurfacePoint> sampleProxy(const InterferenceProxy& proxy) {
  std::vector<SurfacePoint> samples;
  for (const ProxyCylinder& part : proxy.parts) {
    const double a = part.semi_axis_x, b = part.semi_axis_y;
    // Ramanujan's perimeter of the ellipse, for an even spacing around it.
    const double perimeter = M_PI * (3 * (a + b) - std::sqrt((3 * a + b) * (a + 3 * b)));
    const int around = std::max(8, static_cast<int>(perimeter / proxy.spacing));
    for (double z = part.min_z; z <= part.max_z; z += proxy.spacing)
      for (int k = 0; k < around; ++k) {
        const double t = 2 * M_PI * k / around;
        samples.push_back({{part.center_x + a * std::cos(t), part.center_y + b * std::sin(t), z},
                           Eigen::Vector3d(std::cos(t) / a, std::sin(t) / b, 0).normalized(),
                           static_cast<int>(&part - proxy.parts.data())});
      }
    // The top (the top of the head, the shoulders): pairs looking down light and see it. Not
    // where another part stands on it (the neck on the torso).
    auto inside = [&](const ProxyCylinder& other, double x, double y, double z) {
      const double u = (x - other.center_x) / other.semi_axis_x;
      const double v = (y - other.center_y) / other.semi_axis_y;
      return &other != &part && u * u + v * v < 1 && z > other.min_z && z < other.max_z;
    };
    for (double x = -a; x <= a; x += proxy.spacing)
      for (double y = -b; y <= b; y += proxy.spacing) {
        if ((x / a) * (x / a) + (y / b) * (y / b) > 1) continue;
        const Eigen::Vector3d point(part.center_x + x, part.center_y + y, part.max_z);
        if (std::any_of(proxy.parts.begin(), proxy.parts.end(), [&](const ProxyCylinder& other) {
              return inside(other, point.x(), point.y(), point.z());
            }))
          continue;
        samples.push_back(
            {point, Eigen::Vector3d::UnitZ(), static_cast<int>(&part - proxy.parts.data())});
      }
  }
  // The floor, more coarsely (a larger area; its overlaps are large too).
  const double floor_step = 2 * proxy.spacing;
  for (double x = -proxy.floor_radius; x <= proxy.floor_radius; x += floor_step)
    for (double y = -proxy.floor_radius; y <= proxy.floor_radius; y += floor_step)
      if (std::hypot(x, y) <= proxy.floor_radius)
        samples.push_back({{x, y, 0}, Eigen::Vector3d::UnitZ(), -1});
  return samples;
}

// Where the projector's light leaves: the point closest (least squares) to all its planes.
Eigen::Vector3d projectorSource(const body_scan_driver::StripePlaneProjector& projector) {
  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  int used = 0;
  for (const Eigen::Vector4d& plane : projector.planes) {
    if (!plane.allFinite()) continue;  // never-observed stripes
    const Eigen::Vector3d n = plane.head<3>();
    const double scale = n.norm();
    normal_matrix += n * n.transpose() / (scale * scale);
    rhs += -plane[3] * n / (scale * scale);
    ++used;
  }
  if (used < 3) throw std::invalid_argument("a projector needs at least 3 calibrated planes");
  // The planes nearly share a line (the mirror axis), along which the least-squares point is
  // undetermined: a weak pull toward the camera centre picks the point of that line beside it.
  normal_matrix += 0.01 * used * Eigen::Matrix3d::Identity();
  return normal_matrix.ldlt().solve(rhs);
}

struct PairView {
  Eigen::Isometry3d camera_from_world;
  Eigen::Vector3d camera_position;  // world
  Eigen::Vector3d source_world;
  // Camera frame, finite, unit normals oriented so the swept wedge is where both are >= 0.
  Eigen::Vector4d first_plane, last_plane;
  body_scan_driver::PinholeCamera camera;
};

PairView pairView(const PairGeometry& pair) {
  PairView view;
  view.camera_from_world = pair.world_from_camera.inverse();
  view.camera_position = pair.world_from_camera.translation();
  view.source_world = pair.world_from_camera * projectorSource(pair.calibration.projector);
  const auto& planes = pair.calibration.projector.planes;
  auto first = std::find_if(planes.begin(), planes.end(), [](auto& p) { return p.allFinite(); });
  auto last = std::find_if(planes.rbegin(), planes.rend(), [](auto& p) { return p.allFinite(); });
  // A point inside the sweep: where the optical axis meets the middle calibrated plane (else a
  // point 1 m ahead); the first and last planes are oriented to be positive there.
  Eigen::Vector4d middle = planes[(first - planes.begin() + (planes.rend() - last) - 1) / 2];
  if (!middle.allFinite()) middle = *first;
  const double depth = std::abs(middle[2]) > 1e-9 ? -middle[3] / middle[2] : 1.0;
  const Eigen::Vector3d inside(0, 0, depth > 0 ? depth : 1.0);
  auto oriented = [&](Eigen::Vector4d plane) {
    plane /= plane.head<3>().norm();
    return plane.head<3>().dot(inside) + plane[3] < 0 ? Eigen::Vector4d(-plane) : plane;
  };
  view.first_plane = oriented(*first);
  view.last_plane = oriented(*last);
  view.camera = pair.calibration.camera;
  return view;
}

bool lit(const PairView& view, const SurfacePoint& point, double margin) {
  if (point.normal.dot(view.source_world - point.position) <= 0) return false;  // faces away
  const Eigen::Vector3d p = view.camera_from_world * point.position;
  if (p.z() <= 0) return false;  // behind the pair
  // Between the first and the last stripe plane, each moved `margin` outward.
  return view.first_plane.head<3>().dot(p) + view.first_plane[3] >= -margin &&
         view.last_plane.head<3>().dot(p) + view.last_plane[3] >= -margin;
}

bool seen(const PairView& view, const SurfacePoint& point, double margin) {
  if (point.normal.dot(view.camera_position - point.position) <= 0) return false;
  const Eigen::Vector3d p = view.camera_from_world * point.position;
  if (p.z() <= 0.05) return false;
  const Eigen::Vector2d pixel = view.camera.distortedPixel(p.head<2>() / p.z());
  return pixel.x() >= -margin && pixel.y() >= -margin && pixel.x() < view.camera.width + margin &&
         pixel.y() < view.camera.height + margin;
}

}  // namespace

std::vector<std::vector<bool>> lightConflicts(const std::vector<PairGeometry>& pairs,
                                              const InterferenceProxy& proxy) {
  const std::vector<SurfacePoint> samples = sampleProxy(proxy);
  std::vector<PairView> views;
  for (const PairGeometry& pair : pairs) views.push_back(pairView(pair));
  const size_t n = pairs.size();
  std::vector<std::vector<bool>> conflicts(n, std::vector<bool>(n, false));
  std::vector<std::vector<bool>> lit_by(n), seen_by(n);
  for (size_t i = 0; i < n; ++i) {
    lit_by[i].resize(samples.size());
    seen_by[i].resize(samples.size());
    for (size_t k = 0; k < samples.size(); ++k) {
      lit_by[i][k] = lit(views[i], samples[k], proxy.light_margin) &&
                     !shadowed(proxy, samples[k], views[i].source_world);
      seen_by[i][k] = seen(views[i], samples[k], proxy.image_margin) &&
                      !shadowed(proxy, samples[k], views[i].camera_position);
    }
  }
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      size_t shared = 0;
      for (size_t k = 0; k < samples.size(); ++k) shared += lit_by[i][k] && seen_by[j][k];
      conflicts[i][j] = shared * proxy.spacing * proxy.spacing > proxy.min_overlap_area;
    }
  return conflicts;
}

double proxyCoverage(const std::vector<PairGeometry>& pairs, const InterferenceProxy& proxy) {
  InterferenceProxy body = proxy;
  body.floor_radius = 0;
  std::vector<SurfacePoint> samples = sampleProxy(body);
  samples.erase(std::remove_if(samples.begin(), samples.end(),
                               [](const SurfacePoint& sample) { return sample.part < 0; }),
                samples.end());
  std::vector<PairView> views;
  for (const PairGeometry& pair : pairs) views.push_back(pairView(pair));
  size_t covered = 0;
  for (const SurfacePoint& sample : samples)
    for (const PairView& view : views)
      if (seen(view, sample, 0) && lit(view, sample, 0) &&
          !shadowed(body, sample, view.camera_position) &&
          !shadowed(body, sample, view.source_world)) {
        ++covered;
        break;
      }
  return samples.empty() ? 0 : static_cast<double>(covered) / samples.size();
}

std::vector<std::vector<int>> minimumGroups(const std::vector<std::vector<bool>>& conflicts) {
  const int n = static_cast<int>(conflicts.size());
  if (n == 0) return {};
  auto adjacent = [&](int a, int b) { return conflicts[a][b] || conflicts[b][a]; };
  // Colour the most constrained pairs first (degree order, ties by index): exact backtracking
  // with k colours for k = 1, 2, ... (12 pairs: instant).
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::vector<int> degree(n, 0);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) degree[a] += a != b && adjacent(a, b);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return degree[a] > degree[b]; });
  std::vector<int> colour(n, -1);
  // Whether colour c is free for the pair: no conflicting pair has it yet.
  auto fits = [&](int pair, int c) {
    for (int other = 0; other < n; ++other)
      if (colour[other] == c && adjacent(pair, other)) return false;
    return true;
  };
  std::function<bool(int, int, int)> assign = [&](int position, int k, int used) {
    if (position == n) return true;
    const int pair = order[position];
    // A new colour only as the next unused one (symmetry breaking).
    for (int c = 0; c < std::min(k, used + 1); ++c) {
      if (!fits(pair, c)) continue;
      colour[pair] = c;
      if (assign(position + 1, k, std::max(used, c + 1))) return true;
      colour[pair] = -1;
    }
    return false;
  };
  int k = 1;
  while (!assign(0, k, 0)) ++k;
  // Among the minimum colourings, the most balanced one (least sum of squared group sizes; the
  // first found on ties): groups of 2-4 pairs rather than 4+1. Exhaustive with a bound (12
  // pairs: at most a few hundred thousand steps); past the step budget the best so far stays.
  std::vector<int> best = colour, sizes(k, 0);
  auto squares = [](const std::vector<int>& counts) {
    int sum = 0;
    for (int c : counts) sum += c * c;
    return sum;
  };
  for (int c : colour) ++sizes[c];
  int best_squares = squares(sizes);
  std::fill(colour.begin(), colour.end(), -1);
  std::fill(sizes.begin(), sizes.end(), 0);
  long budget = 5000000;
  std::function<void(int, int, int)> balance = [&](int position, int used, int partial) {
    if (--budget < 0) return;
    if (partial >= best_squares) return;  // squares only grow as pairs are added
    if (position == n) {
      if (used == k) {
        best = colour;
        best_squares = partial;
      }
      return;
    }
    const int pair = order[position];
    for (int c = 0; c < std::min(k, used + 1); ++c) {
      if (!fits(pair, c)) continue;
      colour[pair] = c;
      ++sizes[c];
      balance(position + 1, std::max(used, c + 1), partial + 2 * sizes[c] - 1);
      --sizes[c];
      colour[pair] = -1;
    }
  };
  balance(0, 0, 0);
  colour = best;
  // Groups ordered by their first pair; pairs in input order within a group.
  std::vector<std::vector<int>> groups;
  std::vector<int> group_of_colour(k, -1);
  for (int pair = 0; pair < n; ++pair) {
    int& group = group_of_colour[colour[pair]];
    if (group < 0) {
      group = static_cast<int>(groups.size());
      groups.emplace_back();
    }
    groups[group].push_back(pair);
  }
  return groups;
}

double GroupTiming::seconds() const {
  if (pattern_frames < 1)
    throw std::invalid_argument("group timing: pattern_frames " + std::to_string(pattern_frames) +
                                " must be at least 1 (2 + 2 x bits with inverse frames)");
  if (!(camera_fps > 0) || !std::isfinite(camera_fps))
    throw std::invalid_argument("group timing: camera_fps " + std::to_string(camera_fps) +
                                " must be a positive frame rate");
  if (settle_frames < 0)
    throw std::invalid_argument("group timing: settle_frames " + std::to_string(settle_frames) +
                                " must not be negative");
  return pattern_frames * (1.0 + settle_frames) / camera_fps;
}

TimingPlan planTimingGroups(const std::vector<PairGeometry>& pairs,
                            const InterferenceProxy& proxy) {
  const auto conflicts = lightConflicts(pairs, proxy);
  TimingPlan plan;
  for (const auto& group : minimumGroups(conflicts)) {
    plan.groups.emplace_back();
    for (int index : group) plan.groups.back().push_back(pairs[index].pair_id);
  }
  for (size_t i = 0; i < pairs.size(); ++i)
    for (size_t j = 0; j < pairs.size(); ++j)
      if (conflicts[i][j]) plan.conflicts.emplace_back(pairs[i].pair_id, pairs[j].pair_id);
  return plan;
}

}  // namespace body_scan_merge
