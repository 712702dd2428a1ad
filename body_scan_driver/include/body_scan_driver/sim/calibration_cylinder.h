// The calibration cylinder of the thesis (sec. 4.4.1) as a scene surface: a closed cylinder
// printed with CalibrationCylinderLayout's checker grid and ArUco markers.
#pragma once

#include <body_scan_driver/cylinder_layout.h>
#include <body_scan_driver/sim/scene.h>

#include <opencv2/core/mat.hpp>
#include <vector>

namespace body_scan_driver::sim {

class CalibrationCylinder : public Cylinder {
 public:
  // world_from_cylinder: base centre and orientation (cylinder axis = its z column, grid
  // column 0 starts at its x column).
  CalibrationCylinder(const Eigen::Isometry3d& world_from_cylinder,
                      const CalibrationCylinderLayout& layout, double light_albedo = 0.9,
                      double dark_albedo = 0.5);
  double albedoAt(const Eigen::Vector3d& point) const override;
  Eigen::Vector3d colorAt(const Eigen::Vector3d& point) const override {
    return Eigen::Vector3d::Constant(albedoAt(point));
  }
  bool patterned() const override { return true; }

  const CalibrationCylinderLayout& layout() const { return layout_; }
  const Eigen::Isometry3d& worldFromCylinder() const { return world_from_cylinder_; }

 private:
  Eigen::Isometry3d world_from_cylinder_, cylinder_from_world_;
  CalibrationCylinderLayout layout_;
  double light_albedo_, dark_albedo_;
  std::vector<cv::Mat1b> markers_;  // 6x6 cells (with the black border), 255 = white
};

}  // namespace body_scan_driver::sim
