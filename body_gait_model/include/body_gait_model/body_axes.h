// Body axes and centroid of a whole-body cloud by PCA (thesis 5.5.1, eq 5.4), with the front
// and the left told apart: PCA gives axes only up to sign, and a body fitted facing backwards
// swaps left and right limbs and mirrors every swing angle.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace body_gait_model {

using Cloud = std::vector<Eigen::Vector3d>;

struct BodyAxesOptions {
  // The torso band whose horizontal PCA gives the coronal and sagittal axes (5.5.1, second
  // step), as fractions of the body height above the lowest point: the shoulder girdle (joint
  // centres at 0.818 of stature), the torso's widest and flattest section. Lower (chest) bands
  // were measured to be nearly round in the point distribution once the arms cover its sides.
  double shoulder_band_low = 0.77, shoulder_band_high = 0.83;
  // The band's heights hold for a body whose shoulders' top (the highest slice at least
  // shoulder_width * body height wide) lies at shoulder_top of the height; the band moves with
  // the top found in the cloud (a crown missing from the scan shortens the measured height).
  double shoulder_width = 0.16, shoulder_top = 0.845;
  // Take the vertical axis from the scanner's floor frame (world +z) instead of e_1. The
  // subject stands on the floor, and in the long-stride poses of 5.3 the asymmetric limbs tilt
  // e_1 by up to 7.5 degrees (test_body_axes), which skews every later cross-section.
  bool vertical_from_floor = true;
  // Foot and lower-shank bands, as fractions of the body height above the leg's lowest point,
  // and the radius (* body height) around the shank's line within which foot points count.
  double foot_band = 0.06, shank_band_low = 0.08, shank_band_high = 0.18, foot_radius = 0.15;
};

struct BodyAxes {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // e_0
  // Columns in world coordinates: X_m (coronal, toward the subject's left), Y_m (vertical, up),
  // Z_m (sagittal, toward the front). Right-handed.
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  double lowest = 0, highest = 0;  // extent of the cloud along Y_m, model coordinates
  double shoulder_top = 0;         // top of the shoulders along Y_m, model coordinates
  // The subject's height: the cloud's extent, or more where the shoulders' top lies lower in it
  // than on a whole body (a crown above the highest viewpoints missing from the cloud).
  double stature = 0;
  // How far (m) the feet reach ahead of their shank axes along +Z_m: the front/back evidence.
  double foot_reach = 0;
  Eigen::Vector3d pca_vertical = Eigen::Vector3d::UnitZ();  // e_1 of 5.5.1, for reports

  double height() const { return highest - lowest; }
  // Eq 5.4: model coordinates of a world point.
  Eigen::Vector3d toModel(const Eigen::Vector3d& world) const {
    return axes.transpose() * (world - centroid);
  }
  Eigen::Vector3d toWorld(const Eigen::Vector3d& model) const { return centroid + axes * model; }
};

// Centroid and vertical axis (e_1, or the floor normal, see the options) from all points, coronal
// and sagittal axes from the torso band (5.5.1). Up is the side of the world's +z (the scanner's
// floor frame, REP 103). Front is where the feet point: each foot reaches further forward than
// backward from the line of its shank; left then follows from right-handedness (X_m = Y_m x Z_m).
// Throws std::invalid_argument naming the problem if the cloud cannot be a standing body.
BodyAxes estimateBodyAxes(const Cloud& cloud, const BodyAxesOptions& options = {});

}  // namespace body_gait_model
