// Simulated people who differ as people do: bodies drawn from anthropometric
// survey distributions, a personal way of walking, and walks that vary from trial to trial.
// Tests and evaluation only. simulatedSubjects()/gaitPose() (body_cloud_sampler.h) stay as they
// are: the body-fit figures are measured on them.
#pragma once

#include <body_scan_driver/sim/human_body.h>

#include <cstdint>
#include <string>
#include <vector>

namespace body_gait_model::eval {

// A person's own way of walking: the joint angles (radians) of the representative poses of
// thesis 5.3 (heel strike = poses 1 and 3, mid-stance = poses 2 and 4). The stride follows from
// hip_swing + hip_extension and the leg length. Simulator sign conventions (human_body.h):
// flexion positive = limb forward / joint bent.
struct GaitStyle {
  double hip_swing = 0;            // lead hip flexion at heel strike
  double hip_extension = 0;        // trailing hip extension at heel strike (> 0 = behind)
  double lead_knee_flexion = 0;    // lead knee at heel strike (nearly straight)
  double trail_knee_flexion = 0;   // trailing knee at heel strike
  double swing_hip_extension = 0;  // the unloaded leg behind the body at mid-stance
  double knee_flexion = 0;         // its knee at mid-stance: the largest knee bend
  double arm_swing = 0;            // forward arm's shoulder flexion at heel strike
  double arm_swing_back = 0;       // backward arm's shoulder extension at heel strike
  double elbow_flexion = 0;        // elbows at rest (mid-stance) and of the backward arm
  double elbow_swing = 0;          // extra flexion of the forward arm's elbow at heel strike
  double torso_lean = 0;           // forward lean of the upper body
  double arm_abduction = 0;        // arms away from the body
  double hip_abduction = 0;        // legs away from the midline
  double asymmetry = 0;  // added to the right leg's swings and taken off the left's (a limp)
};

struct SimulatedPerson {
  std::string name;
  std::string gender;  // "female" or "male"
  int age = 0;         // years; recorded for the gallery, not modelled in the gait
  body_scan_driver::sim::Anthropometry body;
  GaitStyle style;
  std::uint32_t seed = 0;  // the person's own stream: their walks are reproducible
};

// count people, deterministic from seed. Stature by gender from ANSUR II (2012 US Army
// anthropometric survey; Gordon et al. 2014, NATICK/TR-15/007): women 1628.5 +- 64.2 mm, men
// 1756.2 +- 68.6 mm, genders 50/50. Segment lengths are Drillis & Contini's fractions of the
// stature (Anthropometry::fromStature) times person factors: arms and legs a shared factor
// (CV 3 %) and each segment its own (CV 2 %), head 3 %, foot 4 %, shoulder and hip widths 5 %
// (women's shoulders 4 % narrower, hips 4 % wider relative to stature); the torso takes up the
// rest of the stature (sitting-height ratio varies). Girths: a build factor (CV 6 %) times each
// girth's own (CV 3 %). Ages uniform 18-70. The style: each angle normal about a typical
// adult's walk (Perry & Burnfield, "Gait Analysis", sagittal ranges) with SDs of 1-4 deg, kept
// within Table 5.2 (see gait_subjects.cpp).
std::vector<SimulatedPerson> simulatedPeople(int count, std::uint32_t seed = 1);

// Representative pose `index` (1..4, thesis 5.3) of walk `trial` (0, 1, ...): the person's
// style plus trial-to-trial variation (each walk offsets every angle by N(0, 1 deg), each pose
// of it by another N(0, 0.5 deg); the person stands within +-3 cm of the scanner's centre), so
// two walks of one person differ but less than two people do. Deterministic from (person.seed,
// trial, index). Every angle stays within Table 5.2 after modelFromSkeleton.
body_scan_driver::sim::HumanBodySpec walkingSubject(const SimulatedPerson& person, int index,
                                                    int trial, double heading = 0.0);

}  // namespace body_gait_model::eval
