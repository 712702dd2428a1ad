// The body model of a simulated person read straight off the simulator's true skeleton, with no
// cloud and no fit (tests and fast evaluation only: it reads ground truth).
#pragma once

#include <body_gait_model/eval/body_cloud_sampler.h>
#include <body_gait_model/kinematic_model.h>
#include <body_scan_driver/sim/human_body.h>

#include <vector>

namespace body_gait_model::eval {

// The BodyModel whose joints are the skeleton's: forwardKinematics of it puts the shoulders,
// elbows, hand tips, hips, knees, soles, the neck base and the head top on the true joints.
// Conventions (the simulator's torso leans about the hip centre, so the model does too):
// * root (waist) at the true pelvis (mid-hip), whole-body frame level with X_m along right hip
//   -> left hip, heading from the hips (the simulator's pelvis does not tilt);
// * upper torso from the pelvis to the neck (mid-shoulder) joint, shoulders on its top
//   (shoulder_drop 0); the neck continues it by the chin height (body.neck_length, fixed neck,
//   thesis 5.4) and the head runs from there to the head top;
// * lower torso straight down from the pelvis, 0.06 of the stature (hip to crotch), hips at its
//   top (hip_rise = its length);
// * lower arm elbow -> hand tip, lower leg knee -> sole (ankle + ankle_height along the shank,
//   as compareWithTruth); lengths are joint distances, angles from jointAnglesForDirection;
// * radii from the girths (circumference / 2 pi).
// Differences from a fit: the fitter's waist sits ~0.05 of the stature above the hips, so its
// upper torso is shorter. Throws std::invalid_argument naming a missing joint.
BodyModel modelFromSkeleton(const std::vector<body_scan_driver::sim::SkeletonJoint>& skeleton,
                            const body_scan_driver::sim::Anthropometry& body);
// The same for a posed spec (its skeleton from humanSkeleton) and for a sampled body.
BodyModel modelFromSkeleton(const body_scan_driver::sim::HumanBodySpec& spec);
BodyModel modelFromSkeleton(const SampledBody& body);

}  // namespace body_gait_model::eval
