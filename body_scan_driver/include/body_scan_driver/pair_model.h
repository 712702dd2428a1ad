// Geometric model of one projector-camera pair (thesis sec. 3.2): a pinhole camera with 2-term
// radial distortion and a projector represented by one plane per light stripe. This is the
// model every calibration file describes; the simulator exports its true geometry in it.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace body_scan {

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

struct PairCalibration {
  std::string pair_id;
  std::string source;  // "factory (simulator)" or how it was estimated
  PinholeCamera camera;
  StripePlaneProjector projector;
};

// Ray-plane intersection (eqs 3.9-3.12 written for a general plane): the point on the ray
// through the ideal normalized point (x, y, 1) that lies on the plane; NaN if none in front.
Eigen::Vector3d intersectRayPlane(const Eigen::Vector2d& normalized, const Eigen::Vector4d& plane);

}  // namespace body_scan
