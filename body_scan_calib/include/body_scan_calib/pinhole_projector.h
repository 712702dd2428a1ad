// Baseline projector model, the thesis's approach (i) (sec. 3.4.2): the projector as a pinhole
// "line camera" with a 2x4 projection matrix P, stripe coordinate s = (p1 . X) / (p2 . X) for a
// homogeneous camera-frame point X. All its stripe planes p1 - s p2 share one line (the
// projector centre), which a swept-mirror projector does not have: the comparison shows it.
#pragma once

#include <body_scan_driver/pair_model.h>

#include <Eigen/Core>
#include <vector>

namespace body_scan_calib {

struct PinholeProjector {
  Eigen::Matrix<double, 2, 4> projection;  // rows p1, p2; scale is arbitrary (|P| = 1)

  double stripeAt(const Eigen::Vector3d& point) const;
  // The plane of stripe coordinate s, p1 - s p2 (not normalized: linear in s).
  Eigen::Vector4d planeAt(double stripe_coordinate) const;
  // The plane of every stripe centre (i + 0.5). They are left unnormalized, so the Triangulator's
  // linear interpolation between two centres gives exactly planeAt(s).
  body_scan_driver::StripePlaneProjector toStripePlanes(int stripe_count) const;
};

struct PinholeProjectorFit {
  PinholeProjector projector;
  double rms_stripes;  // rms of s - stripeAt(X) after Gauss-Newton
  int iterations;
};

// DLT on Hartley-normalized data (p1 . X - s p2 . X = 0), then Gauss-Newton (Levenberg-Marquardt
// damped) on the stripe-coordinate residual. Needs >= 7 points not all on one plane; throws
// std::invalid_argument otherwise.
PinholeProjectorFit estimatePinholeProjector(const std::vector<Eigen::Vector3d>& points,
                                             const std::vector<double>& stripe_coordinates);

}  // namespace body_scan_calib
