// Refinement of the whole model (after 5.5's direct fits): p, q and r minimize the robust
// point-to-surface distance of the cloud to the tapered cylinders, q within the joint limits. Ceres
// stays inside refinement.cpp.
#pragma once

#include <body_gait_model/body_axes.h>
#include <body_gait_model/kinematic_model.h>

#include <array>
#include <vector>

namespace body_gait_model {

struct RefinementOptions {
  int sample_points = 2500;   // points drawn evenly from the cloud
  int rounds = 2;             // nearest-segment assignment, then a solve, per round
  int max_iterations = 12;    // per solve
  double huber_scale = 0.02;  // m: beyond this a point counts linearly (hands, feet, hair)
  double min_length = 0.03;   // m: lower bound of every l^r
  // Each free length stays within this fraction of the direct fit's: refinement adjusts lengths,
  // it does not find them (with a whole pole missing a wrong direct fit let an upper arm run
  // away to 5 m).
  double max_length_change = 0.3;
  // A single scan's thighs keep the direct fit's length (a straight leg's knee fits the surface
  // anywhere along its line); in a walk they are refined unless this is set (fitWalk sets it
  // when a scan's pelvis is unseen: nothing there holds the hips). Held in every walk, the
  // CMU walks on the mesh people fit better (knees 25-29 -> 17-24 mm, segment lengths 7.7 ->
  // 6.0 %), but fewer walks of the mesh people were identified (seeds 1 and 3: 92 and 90 % ->
  // 86 and 88 %).
  bool hold_thighs_in_walks = false;
  // Per leg (right, left): no scan of the walk bends this knee clearly (fitWalk finds it), so
  // its thigh's length is held too: a straight knee fits the surface anywhere along the leg.
  std::array<bool, 2> straight_knee{};
};

struct RefinementReport {
  double initial_rms = 0, final_rms = 0;  // of the sampled points, to their assigned segments
  int iterations = 0;
};

// Refines model in place; returns what changed. The shape (radii, joint offsets) and the lengths
// of the free ends (head, lower arms, lower legs), of the lower torso, of the neck and of the upper
// legs (hips and knees as the direct fit placed them) stay fixed.
RefinementReport refineModel(BodyModel& model, const Cloud& cloud,
                             const RefinementOptions& options = {},
                             const JointLimitSet& limits = walkingJointLimits());

// The scans of one walk refined together: each model keeps its own pose (p, q) against its own
// cloud, all share one set of lengths and one shape (the first model's; every model gets them
// back). Ceres, one problem. Throws std::invalid_argument when the counts differ.
RefinementReport refineWalk(std::vector<BodyModel>& models, const std::vector<const Cloud*>& clouds,
                            const RefinementOptions& options = {},
                            const JointLimitSet& limits = walkingJointLimits());

}  // namespace body_gait_model
