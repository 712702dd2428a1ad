// Torso detection from radial cross-sections (thesis 5.5.2, eqs 5.5-5.8).
#pragma once

#include <body_gait_model/body_axes.h>

#include <Eigen/Core>
#include <vector>

namespace body_gait_model {

struct TorsoOptions {
  int sectors = 36;        // R: regions radiating from the axis point w_h
  double delta_ut = 0.25;  // eq 5.5: top of the upper torso where a_l < delta_ut a_g
  // A top found more than this (* body height) above the shoulders' top (BodyAxes) lies in the
  // head: then a_g is the largest section from g up (a chest much wider than the waist at g).
  double max_top_above_shoulders = 0.05;
  double delta_lt = 0.5;          // eq 5.6: base of the lower torso where a_l < delta_lt a_g
  double slice_step = 0.01;       // m between cross-sections (and their thickness)
  double min_base_height = 0.40;  // * body height above the lowest point: the base's floor
};

// One horizontal cross-section in model coordinates (X_m-Z_m plane at height Y_m = height).
struct CrossSection {
  double height = 0;
  double area = 0;                                   // a_l of the closed polygon (m^2)
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // polygon centroid (x, z)
  int filled_sectors = 0;                // sectors that had points (others interpolated)
  std::vector<Eigen::Vector2d> polygon;  // (x, z), one vertex per sector
};

// The polygon of one slice's points around the axis point (0, 0) in the X_m-Z_m plane: per
// sector the point closest to the axis, empty sectors linearly interpolated in radius from their
// nearest filled neighbours (5.5.2). Area 0 when fewer than 3 sectors have points.
CrossSection crossSection(const std::vector<Eigen::Vector2d>& slice_xz, double height, int sectors);

struct TorsoFit {
  std::vector<CrossSection> sections;  // bottom to top, every slice_step
  double area_g = 0;                   // a_g at the centroid height g = 0
  double top = 0;                      // xi: top of the upper torso (model height)
  double base = 0;                     // zeta: base of the lower torso
  Eigen::Vector3d upper_direction = Eigen::Vector3d::UnitY();   // n_ut, eq 5.7 (model frame)
  Eigen::Vector3d lower_direction = -Eigen::Vector3d::UnitY();  // n_lt, eq 5.8
  Eigen::Vector3d waist = Eigen::Vector3d::Zero();  // w_g: section centre at g (model frame)
  double upper_radius_top = 0, lower_radius_base = 0, waist_radius = 0;

  // The section at a model height (nearest slice).
  const CrossSection& sectionAt(double height) const;
};

// model_points: the cloud in model coordinates (eq 5.4). Throws std::invalid_argument naming the
// problem if no torso-like profile is found (no section at g, or no narrowing above/below it).
TorsoFit fitTorso(const std::vector<Eigen::Vector3d>& model_points, const BodyAxes& axes,
                  const TorsoOptions& options = {});

}  // namespace body_gait_model
