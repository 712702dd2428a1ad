// The printed pattern of the calibration cylinder (thesis sec. 4.4.1, Fig 4.9): a checker grid
// of `grid_pitch` squares wrapped around a cylinder, each light square carrying an ArUco marker
// (DICT_4X4_1000) so that every pair can tell which grid points it sees. The grid points are
// the checker corners. The simulator renders this layout; calibration reads it as the target's
// specification (what a user would print), never the simulator's pose of it.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace body_scan_driver {

struct CalibrationCylinderLayout {
  double radius = 0.2075;  // 415 mm diameter
  double height = 1.8;
  double grid_pitch = 0.05;      // 50 mm squares (along the arc and the axis)
  double marker_fraction = 0.6;  // marker side / square side, centred in the light square

  // Squares around the circumference (the arc pitch is the closest to grid_pitch that closes
  // the circle with an even count, so the checker alternates across the seam).
  int columns() const {
    const int count = static_cast<int>(std::lround(2 * M_PI * radius / grid_pitch));
    return count + count % 2;
  }
  int rows() const { return static_cast<int>(std::floor(height / grid_pitch + 1e-9)); }
  double columnAngle() const { return 2 * M_PI / columns(); }
  double bottom() const { return 0.5 * (height - rows() * grid_pitch); }  // z of grid row 0

  // Square (col, row) is light when col + row is odd; light squares carry markers.
  bool isLight(int col, int row) const { return (col + row) % 2 == 1; }
  // Marker id of a light square, -1 for a dark one.
  int markerId(int col, int row) const {
    return isLight(col, row) ? (row * columns() + col) / 2 : -1;
  }
  int markerCount() const { return rows() * columns() / 2; }
  // Lower-left (smallest angle, lowest z) square corner of the light square carrying the marker.
  void markerSquare(int id, int& col, int& row) const {
    row = 2 * id / columns();
    col = 2 * id % columns();
    if (!isLight(col, row)) ++col;
  }

  // Grid points: checker corners (col, row), col in [0, columns), row in [1, rows) (the rims
  // are not corners). Id = row * columns + col.
  int gridPointId(int col, int row) const {
    const int n = columns();
    return row * n + ((col % n) + n) % n;
  }
  bool isGridPoint(int /*col*/, int row) const { return row >= 1 && row < rows(); }
  // Point on the surface at angle (about +z from +x) and height z, cylinder frame (base centre
  // at the origin, axis +z).
  Eigen::Vector3d surfacePoint(double angle, double z) const {
    return {radius * std::cos(angle), radius * std::sin(angle), z};
  }
  Eigen::Vector3d gridPoint(int id) const {
    const int n = columns();
    return surfacePoint((id % n) * columnAngle(), bottom() + (id / n) * grid_pitch);
  }
};

}  // namespace body_scan_driver
