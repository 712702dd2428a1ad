// Projector calibration from reference-plane poses (thesis sec. 3.3.2, eqs 3.27-3.30): each pose
// of a plane of known pose (the printed checkerboard) lifts the pixels of every stripe to 3D in
// the camera frame, and one least-squares plane per stripe (eq 3.5) is fitted to the points of
// all poses.
#pragma once

#include <body_scan_driver/pair_model.h>
#include <body_scan_driver/robust_decoding.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace body_scan_calib {

// A point of the centre line of one stripe in a decoded image: where the decoded coordinate
// equals stripe + 0.5 (the plane of stripe i is its centre, see StripePlaneProjector).
struct StripeCentreSample {
  int stripe;
  Eigen::Vector2d pixel;  // distorted pixel, subpixel along the stripe-changing axis
};

// Walks every image line across the stripes and interpolates the subpixel position where the
// coordinate crosses each stripe centre. Only pixels where `region` is non-zero are used (empty
// region = all). Jumps of more than one stripe between neighbours (surface edges) are skipped.
std::vector<StripeCentreSample> extractStripeCentres(const cv::Mat1f& coordinate, int stripe_count,
                                                     const cv::Mat1b& region = cv::Mat1b());

// Eq 3.30: the 4x3 image-to-camera transform [I; r3^T / (r3^T t)] of a reference plane with
// pose board_to_camera (plane z_p = 0). Applied to the ideal normalized point (x, y, 1) it gives
// the homogeneous camera-frame point on the plane.
Eigen::Matrix<double, 4, 3> imageToCameraTransform(const Eigen::Isometry3d& board_to_camera);

// Lifts distorted pixels to the reference plane (eq 3.30 after undistortion, eq 3.3). Points
// whose ray misses the plane (behind the camera) are NaN.
std::vector<Eigen::Vector3d> liftStripePixels(const body_scan_driver::PinholeCamera& camera,
                                              const Eigen::Isometry3d& board_to_camera,
                                              const std::vector<StripeCentreSample>& samples);

// Total least-squares plane (a, b, c, d) with unit normal; rms of the point distances.
struct PlaneFit {
  Eigen::Vector4d plane;
  double rms;
};
PlaneFit fitPlane(const std::vector<Eigen::Vector3d>& points);

// One reference-plane pose as the projector calibration sees it.
struct ReferencePlaneObservation {
  Eigen::Isometry3d board_to_camera;
  cv::Mat1f stripe_coordinate;  // decoded (StripeDecoder), NaN where invalid
  cv::Mat1b region;             // pixels on the board; empty = all
};

// The smooth model across stripe index: a pencil of planes through one line (a 1-D pinhole
// projector, pinhole_projector.h) fitted robustly to the lifted points of all stripes at once,
// its stripe coordinate corrected by a cubic B-spline of the stripe index (lens distortion).
// A stripe that one pose showed is a line on that board, which with the pencil fixes its
// plane: every stripe a board showed gets one.
enum class StripePlaneModel {
  kPerStripe,        // thesis eq 3.5 per stripe only: < min_poses_per_stripe -> NaN
  kSmoothFillsGaps,  // per stripe where >= min_poses_per_stripe, the smooth model elsewhere
  kSmooth,           // the smooth model for every stripe
};

struct ProjectorCalibrationOptions {
  int stripe_count = 256;
  // Per-stripe planes need a stripe on this many poses (fewer: the smooth model's plane, or NaN
  // with kPerStripe).
  int min_poses_per_stripe = 3;
  StripePlaneModel model = StripePlaneModel::kPerStripe;
  int stripes_per_spline_segment = 32;
  // The smooth model gives planes up to this many stripes beyond the outermost stripes a board
  // showed (listed as extrapolated); farther stripes are NaN (missing).
  int extrapolation_margin = 8;
  // Points farther than this many rms from the first fit are dropped and the plane refitted
  // (checker edges and board borders blur the decoded coordinate).
  double outlier_rms_factor = 3.0;
};

struct ProjectorCalibrationResult {
  body_scan_driver::StripePlaneProjector projector;  // NaN plane for every missing stripe
  std::vector<int> poses_per_stripe;                 // how many poses saw each stripe
  std::vector<int> points_per_stripe;                // points used in the final fit
  std::vector<double> rms_per_stripe_m;   // point-to-plane rms of the final fit (NaN if missing)
  std::vector<int> missing_stripes;       // NaN planes: seen on too few poses / beyond the margin
  std::vector<int> smooth_stripes;        // planes from the smooth model (kSmooth: every one)
  std::vector<int> extrapolated_stripes;  // of those, stripes no board showed (within the margin)
  double smooth_rms_m = 0;                // point-to-plane rms of the smooth model (inliers)
  double rms_m = 0;                       // over all fitted points
  // The lifted centre-line points of every pose, with their stripe (for the pinhole baseline
  // and the joint refinement): the same data for every model.
  std::vector<Eigen::Vector3d> points;
  std::vector<int> point_stripes, point_poses;
  std::vector<Eigen::Vector2d> point_pixels;
};

// Throws std::invalid_argument naming the problem when there are fewer than 3 poses or a
// coordinate image is empty.
ProjectorCalibrationResult calibrateStripePlanes(
    const body_scan_driver::PinholeCamera& camera,
    const std::vector<ReferencePlaneObservation>& observations,
    const ProjectorCalibrationOptions& options = {});

// Orients plane to the suite's sign convention (normal with a non-positive dominant y or x
// component, as the simulator's factory planes), so that neighbouring planes interpolate.
Eigen::Vector4d orientPlane(const Eigen::Vector4d& plane);

using body_scan_driver::stripesChangeAlongRows;  // robust_decoding.h

}  // namespace body_scan_calib
