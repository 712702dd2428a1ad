#include <body_scan_driver/sim/calibration_cylinder.h>

#include <algorithm>
#include <cmath>
#include <opencv2/aruco.hpp>

namespace body_scan_driver::sim {

constexpr int kMarkerCells = 6;  // 4x4 bits + a one-cell black border

CalibrationCylinder::CalibrationCylinder(const Eigen::Isometry3d& world_from_cylinder,
                                         const CalibrationCylinderLayout& layout,
                                         double light_albedo, double dark_albedo)
    : Cylinder(world_from_cylinder.translation(), world_from_cylinder.linear().col(2),
               layout.radius, layout.height, Material{light_albedo, {0.9, 0.9, 0.9}}),
      world_from_cylinder_(world_from_cylinder),
      cylinder_from_world_(world_from_cylinder.inverse()),
      layout_(layout),
      light_albedo_(light_albedo),
      dark_albedo_(dark_albedo) {
  const cv::Ptr<cv::aruco::Dictionary> dictionary =
      cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_1000);
  markers_.resize(layout_.markerCount());
  for (int id = 0; id < layout_.markerCount(); ++id)
    dictionary->drawMarker(id, kMarkerCells, markers_[id], 1);
}

double CalibrationCylinder::albedoAt(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d local = cylinder_from_world_ * point;
  const double pitch = layout_.grid_pitch;
  const double z = local.z() - layout_.bottom();
  // Caps and the unprinted rims are plain light.
  if (local.head<2>().norm() < layout_.radius * (1 - 1e-6) || z < 0 || z >= layout_.rows() * pitch)
    return light_albedo_;
  double angle = std::atan2(local.y(), local.x());
  if (angle < 0) angle += 2 * M_PI;
  const double column_position = angle / layout_.columnAngle();
  const int col = std::min(static_cast<int>(column_position), layout_.columns() - 1);
  const int row = static_cast<int>(z / pitch);
  if (!layout_.isLight(col, row)) return dark_albedo_;
  // Position inside the marker, seen from outside: cells left to right with the angle, top to
  // bottom with falling z (the marker reads correctly, not mirrored).
  const double margin = 0.5 * (1 - layout_.marker_fraction);
  const double across = (column_position - col - margin) / layout_.marker_fraction;
  const double down = (1 - (z / pitch - row) - margin) / layout_.marker_fraction;
  if (across < 0 || across >= 1 || down < 0 || down >= 1) return light_albedo_;
  const cv::Mat1b& marker = markers_[layout_.markerId(col, row)];
  return marker(static_cast<int>(down * kMarkerCells), static_cast<int>(across * kMarkerCells)) >
                 127
             ? light_albedo_
             : dark_albedo_;
}

}  // namespace body_scan_driver::sim
