// Accuracy of a calibrated pair on spheres of known radius (thesis sec. 3.4.2): the ideal
// sphere (radius fixed at the known value) is fitted to the reconstructed points and
// E_s = 1/N sum (r_j - r_hat)^2 (eq 3.31), r_j the distance of point j from the fitted centre.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace body_scan_calib {

struct IdealSphereFit {
  Eigen::Vector3d center;
  double e_s_m2;  // eq 3.31, square metres
  int points;
};

// Gauss-Newton on the centre with the radius fixed, started from an algebraic free-radius fit.
// Needs >= 4 points (throws std::invalid_argument otherwise).
IdealSphereFit fitIdealSphere(const std::vector<Eigen::Vector3d>& points, double radius);

// Splits a cloud into the spheres nearest to their nominal centres: a point belongs to sphere k
// if it lies within capture_radius of nominal_centers[k] (the placement of the evaluation rig,
// known to the operator to a few millimetres; not the reconstructed truth).
std::vector<std::vector<Eigen::Vector3d>> segmentSpheres(
    const std::vector<Eigen::Vector3d>& cloud, const std::vector<Eigen::Vector3d>& nominal_centers,
    double capture_radius);

}  // namespace body_scan_calib
