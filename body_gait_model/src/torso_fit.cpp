// Torso from radial cross-sections (thesis 5.5.2, eqs 5.5-5.8).
#include <body_gait_model/torso_fit.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "order_statistics.h"

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Component-wise median of unit vectors, renormalized (eqs 5.7, 5.8).
Eigen::Vector3d medianDirection(std::vector<Eigen::Vector3d> directions,
                                const Eigen::Vector3d& fallback) {
  if (directions.empty()) return fallback;
  const Eigen::Vector3d median = componentMedian(directions);
  return median.norm() > 0 ? median.normalized() : fallback;
}

}  // namespace

CrossSection crossSection(const std::vector<Eigen::Vector2d>& slice_xz, double height,
                          int sectors) {
  if (sectors < 3)
    throw std::invalid_argument("cross-section: R (sectors) must be >= 3, got " +
                                std::to_string(sectors));
  CrossSection section;
  section.height = height;
  std::vector<double> radius(sectors, -1.0), angle(sectors, 0.0);
  for (const auto& p : slice_xz) {
    const double phi = std::atan2(p.y(), p.x());
    const int sector = std::clamp(int((phi + kPi) / (2 * kPi) * sectors), 0, sectors - 1);
    const double r = p.norm();
    if (radius[sector] < 0 || r < radius[sector]) {
      radius[sector] = r;
      angle[sector] = phi;
    }
  }
  std::vector<int> filled;
  for (int s = 0; s < sectors; ++s)
    if (radius[s] >= 0) filled.push_back(s);
  section.filled_sectors = int(filled.size());
  if (filled.size() < 3) return section;
  // Holes: radius linear between the nearest filled sectors on either side (circularly).
  for (int s = 0; s < sectors; ++s) {
    if (radius[s] >= 0) {
      section.polygon.emplace_back(radius[s] * std::cos(angle[s]), radius[s] * std::sin(angle[s]));
      continue;
    }
    int before = s, after = s, steps_before = 0, steps_after = 0;
    do {
      before = (before - 1 + sectors) % sectors;
      ++steps_before;
    } while (radius[before] < 0);
    do {
      after = (after + 1) % sectors;
      ++steps_after;
    } while (radius[after] < 0);
    const double w = double(steps_before) / (steps_before + steps_after);
    const double r = (1 - w) * radius[before] + w * radius[after];
    const double phi = -kPi + (s + 0.5) * 2 * kPi / sectors;
    section.polygon.emplace_back(r * std::cos(phi), r * std::sin(phi));
  }
  // Shoelace area and centroid of the closed polygon.
  double twice_area = 0;
  Eigen::Vector2d weighted = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < section.polygon.size(); ++i) {
    const Eigen::Vector2d& a = section.polygon[i];
    const Eigen::Vector2d& b = section.polygon[(i + 1) % section.polygon.size()];
    const double cross = a.x() * b.y() - b.x() * a.y();
    twice_area += cross;
    weighted += cross * (a + b);
  }
  section.area = std::abs(twice_area) / 2;
  if (std::abs(twice_area) > 1e-12) section.centre = weighted / (3 * twice_area);
  return section;
}

const CrossSection& TorsoFit::sectionAt(double height) const {
  if (sections.empty()) throw std::logic_error("torso fit has no sections");
  // Sections are evenly spaced: index directly (this runs once per point).
  const double first = sections.front().height;
  const double step = sections.size() > 1 ? sections[1].height - sections[0].height : 1.0;
  const long index = std::lround((height - first) / step);
  return sections[std::clamp<long>(index, 0, long(sections.size()) - 1)];
}

TorsoFit fitTorso(const std::vector<Eigen::Vector3d>& model_points, const BodyAxes& axes,
                  const TorsoOptions& options) {
  if (!(options.delta_ut > 0 && options.delta_ut < 1 && options.delta_lt > 0 &&
        options.delta_lt < 1 && options.slice_step > 0))
    throw std::invalid_argument(
        "torso fit: delta_ut and delta_lt must lie in (0, 1) and slice_step be > 0 (thesis "
        "values: 0.25, 0.5)");
  const double step = options.slice_step;
  const int first = int(std::floor(axes.lowest / step)), last = int(std::ceil(axes.highest / step));
  std::vector<std::vector<Eigen::Vector2d>> slices(last - first + 1);
  for (const auto& p : model_points) {
    const int index = int(std::lround(p.y() / step)) - first;
    if (index >= 0 && index < int(slices.size())) slices[index].emplace_back(p.x(), p.z());
  }
  TorsoFit torso;
  int g_index = -1;
  for (size_t i = 0; i < slices.size(); ++i) {
    const double height = (first + int(i)) * step;
    torso.sections.push_back(crossSection(slices[i], height, options.sectors));
    if (std::abs(height) < step / 2 + 1e-12 && g_index < 0) g_index = int(i);
  }
  // Dark clothing returns no light: where the section at g has more holes than points (trunks
  // around the hips), take the nearest closed section above it as the reference a_g.
  while (g_index >= 0 && g_index + 1 < int(torso.sections.size()) &&
         torso.sections[g_index].filled_sectors < options.sectors * 3 / 4)
    ++g_index;
  if (g_index < 0 || torso.sections[g_index].area <= 0)
    throw std::invalid_argument(
        "torso fit: no cross-section at the centroid height; the cloud has no torso there");
  torso.area_g = torso.sections[g_index].area;
  // Eqs 5.5, 5.6: the first sections above / below g smaller than delta * a_g.
  int top = -1, base = -1;
  auto topAbove = [&](bool largest_reference) {
    double reference = torso.area_g;
    for (int i = g_index + 1; i < int(torso.sections.size()); ++i) {
      if (torso.sections[i].area < options.delta_ut * reference) return i;
      if (largest_reference) reference = std::max(reference, torso.sections[i].area);
    }
    return -1;
  };
  top = topAbove(false);
  // The neck's base lies a few cm above the shoulders' top. A top found far above it is in the
  // head: a waist at g narrower than the chest (a woman's body: neck 0.26-0.30 a_g) never let
  // the sections narrow below delta_ut a_g. Then a_g is the largest section from g up.
  if (top < 0 || torso.sections[top].height >
                     axes.shoulder_top + options.max_top_above_shoulders * axes.height())
    top = topAbove(true);
  // A narrowed section with clearly larger ones below it is the crotch too: in a stride the
  // two thighs apart (and the hands beside them) span a polygon larger than the pelvis, so the
  // sections can widen again before any falls below delta_lt a_g (mesh people: the base then
  // dropped to min_base_height, 150 mm low, in some scans of a walk; the lower torso's length
  // 29 mm SD between two walks of one person, 18 mm with this rule). The widening must hold
  // for kWideBelow sections: a single wider slice is not the thighs (CMU walk 07_08: 0.71 a_g,
  // 1.30 for one slice, then the crotch at 0.13; taken for the crotch, the base rose 20 mm and
  // the walk's shared lengths moved enough to lose the walk's identification).
  auto crotchBelow = [](const std::vector<CrossSection>& sections, int i, double area_g) {
    constexpr double kNarrowed = 0.75, kWidening = 0.15;  // * a_g
    constexpr int kWideBelow = 2;
    if (i < kWideBelow || sections[i].area >= kNarrowed * area_g) return false;
    for (int k = 1; k <= kWideBelow; ++k)
      if (sections[i - k].area <= sections[i].area + kWidening * area_g) return false;
    return true;
  };
  // The crotch lies at ~0.47 of the stature (Drillis & Contini): below min_base_height the
  // sections are legs whatever their area (long strides under dark trunks keep it large).
  for (int i = g_index - 1; i >= 0; --i)
    if (torso.sections[i].area < options.delta_lt * torso.area_g ||
        crotchBelow(torso.sections, i, torso.area_g) ||
        torso.sections[i].height < axes.lowest + options.min_base_height * axes.height()) {
      base = i;
      break;
    }
  if (top < 0 || base < 0)
    throw std::invalid_argument(
        "torso fit: the cross-sections never narrow to delta_ut a_g above or delta_lt a_g below "
        "the centroid: not a human body (or the head / legs are missing from the cloud)");
  torso.top = torso.sections[top].height;
  torso.base = torso.sections[base].height;
  const CrossSection& g = torso.sections[g_index];
  torso.waist = Eigen::Vector3d(g.centre.x(), 0, g.centre.y());
  auto centreOf = [](const CrossSection& s) {
    return Eigen::Vector3d(s.centre.x(), s.height, s.centre.y());
  };
  // Only sections with points in most sectors, and below g only those down to the first open
  // one: a section with more holes than points has its centroid anywhere, and under dark trunks
  // the closed sections below the gap are the thighs with the hands beside them. Below g also
  // only sections at least kMinBaseline under it: the few closed sections just below the waist
  // give directions from w_g that a few mm of centroid noise turns by tens of degrees. With
  // none left, or n_lt beyond kMaxLowerTilt of the vertical, n_lt is the vertical: where a long
  // stride keeps the sections large below the crotch, they hold two legs (and hands), whose
  // polygon's centroid lies anywhere (mesh human in a stride: n_lt 49 deg off the vertical,
  // every leg point on one side of the hips' centre).
  constexpr double kMinBaseline = 0.05;  // m
  constexpr double kMaxLowerTilt = 30 * kPi / 180;
  auto closed = [&](const CrossSection& s) {
    return s.area > 0 && s.filled_sectors >= options.sectors * 3 / 4;
  };
  std::vector<Eigen::Vector3d> up, down;
  for (int i = g_index + 1; i <= top; ++i)
    if (closed(torso.sections[i]))
      up.push_back((centreOf(torso.sections[i]) - torso.waist).normalized());
  for (int i = g_index - 1; i >= base && closed(torso.sections[i]); --i)
    if (torso.sections[i].height < -kMinBaseline)
      down.push_back((centreOf(torso.sections[i]) - torso.waist).normalized());
  torso.upper_direction = medianDirection(up, Eigen::Vector3d::UnitY());
  torso.lower_direction = medianDirection(down, -Eigen::Vector3d::UnitY());
  if (-torso.lower_direction.y() < std::cos(kMaxLowerTilt))
    torso.lower_direction = -Eigen::Vector3d::UnitY();
  // Equivalent-circle radii: at g, and the mean of the quarter next to each end.
  auto meanRadius = [&](int from, int to) {
    double sum = 0;
    int count = 0;
    for (int i = std::min(from, to); i <= std::max(from, to); ++i)
      if (torso.sections[i].area > 0) {
        sum += std::sqrt(torso.sections[i].area / kPi);
        ++count;
      }
    return count > 0 ? sum / count : 0.0;
  };
  torso.waist_radius = std::sqrt(torso.area_g / kPi);
  const int upper_quarter = std::max(1, (top - g_index) / 4);
  const int lower_quarter = std::max(1, (g_index - base) / 4);
  torso.upper_radius_top = meanRadius(top - upper_quarter, top - 1);
  torso.lower_radius_base = meanRadius(base + 1, base + lower_quarter);
  return torso;
}

}  // namespace body_gait_model
