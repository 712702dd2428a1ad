// Geometric model of one projector-camera pair (thesis sec. 3.2): a pinhole camera with 2-term
// radial distortion and a projector represented by one plane per light stripe. This is the
// model every calibration file describes; the simulator exports its true geometry in it.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

namespace body_scan_driver {

// Pinhole camera, eqs 3.1-3.4: A = [alpha gamma u0; 0 beta v0; 0 0 1]; radial distortion k1, k2
// about the principal point in normalized coordinates. Pixel centres are at integer (u, v).
struct PinholeCamera {
  int width = 640, height = 480;
  double alpha = 810, beta = 810, gamma = 0, u0 = 319.5, v0 = 239.5;
  double k1 = 0, k2 = 0;

  // Ideal normalized point (x/z, y/z) -> distorted pixel (eq 3.3 then eq 3.1).
  Eigen::Vector2d distortedPixel(const Eigen::Vector2d& normalized) const;
  // Distorted pixel -> ideal normalized point (inverse of the above, by fixed-point iteration).
  Eigen::Vector2d normalizedPoint(const Eigen::Vector2d& pixel) const;
  Eigen::Vector2d project(const Eigen::Vector3d& point) const {
    return distortedPixel(point.head<2>() / point.z());
  }
};

// Projector as one plane per stripe in the camera frame, eq 3.5: a x + b y + c z + d = 0.
// Plane i is the centre of stripe i, i.e. stripe coordinate s = i + 0.5; a fractional
// coordinate interpolates the two neighbouring planes.
struct StripePlaneProjector {
  std::vector<Eigen::Vector4d> planes;  // (a, b, c, d)

  int stripeCount() const { return static_cast<int>(planes.size()); }
  Eigen::Vector4d planeAt(double stripe_coordinate) const;
  // Explicit parameters of eqs 3.6-3.8 (baseline l_i, projection angle theta_i, tilt phi_i).
  // They assume a dominant a_i, i.e. a horizontal baseline; for the pole's vertical baseline
  // they are reported about the camera's x and y axes swapped (see docs/ARCHITECTURE.md).
  struct Explicit {
    double baseline, projection_angle, tilt_angle;
  };
  Explicit explicitParameters(int stripe) const;
};

// Camera frame -> world frame of one pair (thesis eq 4.1): M_w = A M_c + t, a 12-parameter
// affine fitted to calibration-cylinder points. The polar decomposition A = R L splits it into a
// rigid part (R, t), published as the tf2 transform world -> camera optical frame, and a
// symmetric residual linear part L that Triangulate applies to camera-frame points first.
struct WorldAlignment {
  Eigen::Isometry3d world_from_camera = Eigen::Isometry3d::Identity();  // (R, t)
  Eigen::Matrix3d residual_linear = Eigen::Matrix3d::Identity();        // L

  // Throws std::invalid_argument when A is singular or not finite.
  static WorldAlignment fromAffine(const Eigen::Matrix<double, 3, 4>& affine);
  Eigen::Matrix<double, 3, 4> affine() const;  // [R L | t]
  Eigen::Vector3d applyResidualLinear(const Eigen::Vector3d& camera_point) const {
    return residual_linear * camera_point;
  }
  Eigen::Vector3d toWorld(const Eigen::Vector3d& camera_point) const {
    return world_from_camera * applyResidualLinear(camera_point);
  }
};

struct PairCalibration {
  std::string pair_id;
  std::string source;  // "factory (simulator)" or how it was estimated
  PinholeCamera camera;
  StripePlaneProjector projector;
  std::optional<WorldAlignment> alignment;  // set once the pair is aligned to the world
};

// Ray-plane intersection (eqs 3.9-3.12 written for a general plane): the point on the ray
// through the ideal normalized point (x, y, 1) that lies on the plane; NaN if none in front.
Eigen::Vector3d intersectRayPlane(const Eigen::Vector2d& normalized, const Eigen::Vector4d& plane);

}  // namespace body_scan_driver
