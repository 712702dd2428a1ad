// Gait reconstruction (thesis 5.6, 5.8.2) and symmetric poses (5.8.3): a 20-frame gait cycle
// interpolated from the 4 representative poses s1..s4 of thesis 5.3, and the mirror images
// that make the training sets eta1 and eta2.
#pragma once

#include <body_gait_model/kinematic_model.h>

#include <Eigen/Core>
#include <array>
#include <vector>

namespace body_gait_model {

constexpr int kGaitCycleFrames = 20;  // 5.8.2: one cycle, frames Y = 1..20
// Frames of the representative poses s1..s4 (5.8.2); the others are interpolated.
constexpr std::array<int, 4> kRepresentativeFrames{1, 6, 11, 16};

// s1..s4 in thesis 5.3 order: 1 right heel strike (right leg and left arm forward, longest
// stride), 2 right mid-stance, 3 left heel strike, 4 left mid-stance.
using RepresentativePoses = std::array<BodyModel, 4>;

// The pose's mirror image across its sagittal plane (5.8.3: right and left parameters
// exchanged). The plane is vertical, through the root (p's translation), along the heading
// (p's theta_y). Every right segment takes its left partner's theta_x and lengths and the
// negated theta_z (coronal swings change side); the central segments and p's theta_z negate
// their theta_z; p's translation, theta_x (forward tilt) and theta_y (heading) stay.
BodyModel mirroredPose(const BodyModel& pose);

// The symmetric poses of 5.8.3: sbar_i = mirroredPose(s_{i+2 mod 4}) (sbar1 from s3, sbar2
// from s4, sbar3 from s1, sbar4 from s2), so sbar_i is again a pose of phase i.
RepresentativePoses symmetricPoses(const RepresentativePoses& s);

// 5.8.3: eta1 = {s1, sbar2, s3, sbar4} and eta2 = {sbar1, s2, sbar3, s4} (training),
// eta3 = {s1, s2, s3, s4} (testing).
enum class GaitSet { kEta1, kEta2, kEta3 };
RepresentativePoses gaitSet(const RepresentativePoses& s, GaitSet which);

struct GaitCycle {
  std::vector<BodyModel> frames;                       // kGaitCycleFrames; frames[f - 1] is frame f
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // world m per frame (eq 5.11's v)
  double stride_length = 0;                            // m
};

// Eqs 5.11-5.13. q (and p's angles) interpolate linearly between consecutive representative
// poses, frames 17-20 between s4 and the next cycle's s1 (eq 5.12); r and the shape are the
// mean of the four (eq 5.13). Stride length: the forward distance from the trailing to the
// leading sole at s1 plus the same at s3 (two steps); v is stride / kGaitCycleFrames along the
// mean heading of the four poses (5.8.2: "speed = stride / number of poses"; the subjects stand
// in the scanner, so their own heading gives the direction the thesis set by hand). Frame f's
// translation is the interpolated translation of its neighbours (sway and bob of the fits) plus
// (f - 1) v (eq 5.11), so frames 1, 6, 11, 16 equal s1..s4 in q and p's angles, and in p's
// translation up to the walked (f - 1) v.
// Throws std::invalid_argument if neither step goes forward (s1 and s3 swapped, or facing
// back); when only one does (one misfitted foot), the stride is twice that step.
GaitCycle reconstructGaitCycle(const RepresentativePoses& poses);

}  // namespace body_gait_model
