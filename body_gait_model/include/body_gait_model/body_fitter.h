// Fitting the kinematic model to a whole-body cloud (thesis 5.5): body axes (5.5.1), torso
// (5.5.2), arms and legs by line fitting (5.5.3, eqs 5.9-5.10), head and neck (5.5.4), then fit
// quality. The fitter sees only the cloud: no simulator, no ground truth.
#pragma once

#include <body_gait_model/body_axes.h>
#include <body_gait_model/kinematic_model.h>
#include <body_gait_model/refinement.h>
#include <body_gait_model/torso_fit.h>

#include <array>
#include <string>
#include <vector>

namespace body_gait_model {

struct FitQualityOptions {
  // Circular cylinders miss an elliptical torso by up to ~3 cm, so good fits of simulated
  // subjects explain 70-90 % of the points within 30 mm at an RMS of 16-25 mm (test_body_fitter);
  // the calibration cylinder: 50 % and 56 mm.
  double explained_distance = 0.03;  // a point is explained within this of the model surface
  double min_explained_fraction = 0.7;
  double max_rms = 0.035;                // m
  int min_points_per_limb_segment = 50;  // arms, legs
  // Limb proportions: the upper segment's share of each arm (shoulder-elbow-wrist) and leg
  // (hip-knee-sole) may differ from the standard (Drillis & Contini: arm 0.186 / 0.44, leg
  // 0.245 / 0.53) by at most this. The knee lies at the standard share of the hip-to-sole
  // length along the leg's line, so the leg's share moves only when the hip lies far off that
  // line (pelvis unseen, e.g. dark trunks: 0.56-0.60 in fits 50-60 mm off; good fits
  // 0.45-0.49). The elbow follows the bend, so the arm's share varies more (good fits
  // 0.32-0.51; an elbow run to the hand: 0.94).
  double max_leg_share_deviation = 0.06;
  double max_arm_share_deviation = 0.2;
  // Distances are taken on an even subsample of at most this many points (the figures are
  // statistics; points_per_segment is scaled back to the whole cloud).
  int max_points = 100000;
};

struct FitOptions {
  BodyAxesOptions axes;
  TorsoOptions torso;
  FitQualityOptions quality;
  // Refine the direct fit against the point-to-surface distance (Ceres), the feet left out
  // (the model has none): on simulated subjects 33 -> 30 mm mean joint error.
  bool refine = true;
  RefinementOptions refinement;
  // Every joint angle stays within these (direct fit and refinement): walking ranges by
  // default (a real swing knee flexes to 60-70 deg), thesisJointLimits() for Table 5.2's.
  JointLimitSet joint_limits = walkingJointLimits();
  // * body height: the feet, left out of refinement: above the lowest point, and from each leg's
  // sole up along its shank (a lifted foot).
  double foot_height = 0.06;
  // Elbow and knee are searched within +- this fraction of the proximal-joint-to-tip length
  // around the standard proportion (Drillis & Contini).
  double arm_split_window = 0.12, leg_split_window = 0.12;
  double limb_track_radius = 0.06;  // m: an arm's next slice lies within this of its centre
  // Hip joint centres above the lowest point, * body height (Drillis & Contini: 0.53). They lie
  // inside the pelvis, so the surface alone does not show them; the thigh line gives x and z.
  double hip_height = 0.53;
  // Hip joint centres this fraction of the body's depth at hip height in front of its back: on
  // the mesh people and the CMU walks on them the hips stood 0.39-0.40 of the midline's depth
  // from the buttocks (SD 0.01), 35-40 mm behind the lower torso's axis.
  double hip_depth_fraction = 0.40;
  // Shoulder joint centres below the top of the shoulder above each upper arm's line, in that
  // arm's proximal radii. The humeral head's centre lies about 5 cm below the acromion, under
  // the deltoid's and skin's 1-2 cm: on the mesh people and the CMU walks on them the shoulder's
  // top stood 74-77 mm above it, about two radii (one radius: shoulders 33-38 mm high, 22-28 mm
  // in); the ellipsoid body's cap-shaped shoulder has it one radius down.
  double shoulder_depth = 2.0;
  // The axis, cross-section and line-fit stages (and refinement's sampling) run on an even
  // subsample of at most this many points: they are statistics over 1 cm slices, which stay
  // dense (> 100 points) at this size; a 1 M point cloud then fits ~2x faster (bench_body_fit).
  // The quality figures still see the whole cloud (FitQualityOptions::max_points). 0 = all.
  int max_fit_points = 250000;
};

struct FitQuality {
  double rms_distance = 0;        // RMS point-to-model-surface distance (m), all points
  double explained_fraction = 0;  // points within explained_distance of the surface
  std::array<int, kSegmentCount> points_per_segment{};  // nearest-segment assignment
  bool low_quality = false;
  std::string reason;  // why it is low quality (empty if not)
  // Every joint angle of the fit that sits on a bound of FitOptions::joint_limits (the body
  // may bend further than the set allows); reported, not a reason for low_quality.
  std::vector<std::string> limits_reached;
};

// Joint points found directly by the line fits (world frame), before the model's tree imposes
// symmetric shoulders and hips. Named like PosedModel::joint.
struct JointPoint {
  std::string name;
  Eigen::Vector3d position;
};

struct BodyFit {
  BodyModel model;
  BodyAxes axes;
  TorsoFit torso;
  std::vector<JointPoint> joint_points;
  FitQuality quality;
  RefinementReport refinement;
};

// Throws std::invalid_argument naming the problem and the fix when the cloud is no standing
// body at all (too few points, longest axis not vertical). A cloud shaped unlike a body (no
// torso profile, missing limbs or head) or fitted badly comes back with quality.low_quality set
// and quality.reason saying why.
BodyFit fitBody(const Cloud& cloud, const FitOptions& options = {});

// The fits of one walk: one BodyFit per scan, in the walk's order.
struct WalkFit {
  std::vector<BodyFit> scans;
  RefinementReport refinement;  // the one refinement of every scan together
};

// The scans of one walk of one person (e.g. the 4 representative poses of 5.3), fitted together:
// each scan's direct fit as fitBody's, then one body for all (each segment length, radius and
// joint offset the median over the scans), then one Ceres refinement of every scan's pose (p, q)
// with the lengths shared; each scan's lower legs are aimed at its shanks' centres just above the
// ankles, the free ends' lengths (lower legs, lower arms, head) are then the medians of each
// scan's distance to the sole on the floor, the hand tip and the vertex it shows, and each scan's
// lower arms and head are aimed at its own. A scan that is no body at all throws
// as in fitBody; one shaped unlike a body comes back flagged and stays out of the shared body.
WalkFit fitWalk(const std::vector<Cloud>& walk, const FitOptions& options = {});

// Point-to-surface quality of a model against a cloud (used by fitBody and by evaluation).
FitQuality evaluateFit(const BodyModel& model, const Cloud& cloud,
                       const FitQualityOptions& options = {});

}  // namespace body_gait_model
