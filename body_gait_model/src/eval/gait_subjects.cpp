// Simulated people: anthropometry from survey distributions, personal gait styles, trial
// variation (tests and evaluation only).
#include <body_gait_model/eval/gait_subjects.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <stdexcept>

namespace body_gait_model::eval {

namespace sim = body_scan_driver::sim;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;

// ANSUR II (Gordon et al. 2014, NATICK/TR-15/007), stature mean and SD in metres.
constexpr double kFemaleStatureMean = 1.6285, kFemaleStatureSd = 0.0642;
constexpr double kMaleStatureMean = 1.7562, kMaleStatureSd = 0.0686;

// Table 5.2 less a margin, in the simulator's angles (modelFromSkeleton maps flexion to
// theta_x and abduction to theta_z one to one): upper leg x 45 deg, lower leg x 30, upper arm
// x 30, lower arm x 45, every z 10.
constexpr double kMaxHipFlexion = 44 * kDegree, kMaxKneeFlexion = 29.5 * kDegree;
constexpr double kMaxShoulderFlexion = 29.5 * kDegree, kMaxElbowFlexion = 44 * kDegree;
constexpr double kMaxAbduction = 9.5 * kDegree;

// One style angle across people: typical value, SD and the range it is kept in (degrees).
struct AngleSpread {
  double GaitStyle::*field;
  double mean, sd, min, max;
};
// Typical sagittal angles of adult walking (Perry & Burnfield, "Gait Analysis", 2nd ed.: hip
// ~25 deg flexion at initial contact and ~15-20 deg extension at its end, knee ~5 deg at
// initial contact and up to ~25 deg in the poses of thesis 5.3, shoulder swing ~+-20 deg) with
// person-to-person SDs a few degrees wide: people differ, but all walk within Table 5.2.
const AngleSpread kStyleSpread[] = {
    {&GaitStyle::hip_swing, 24, 3, 15, 32},          {&GaitStyle::hip_extension, 17, 3, 8, 25},
    {&GaitStyle::lead_knee_flexion, 5, 2, 0, 12},    {&GaitStyle::trail_knee_flexion, 15, 3, 6, 24},
    {&GaitStyle::swing_hip_extension, 14, 3, 6, 22}, {&GaitStyle::knee_flexion, 24, 3, 14, 28},
    {&GaitStyle::arm_swing, 18, 4, 6, 26},           {&GaitStyle::arm_swing_back, 17, 4, 6, 26},
    {&GaitStyle::elbow_flexion, 10, 4, 2, 25},       {&GaitStyle::elbow_swing, 14, 5, 0, 18},
    {&GaitStyle::torso_lean, 3, 2, -2, 9},           {&GaitStyle::arm_abduction, 7, 1, 4, 9},
    {&GaitStyle::hip_abduction, 2, 1, 0, 5},         {&GaitStyle::asymmetry, 0, 1.5, -4, 4},
};
constexpr double kTrialSd = 1.0 * kDegree;  // a whole walk's offset per style angle
constexpr double kPoseSd = 0.5 * kDegree;   // each pose's own jitter per joint angle
constexpr double kStandingSpread = 0.03;    // m, where the person stands in the scanner

// A reproducible stream for (seed, a, b, c): std::seed_seq mixes all of them.
std::mt19937 stream(std::uint32_t seed, std::uint32_t a, std::uint32_t b = 0, std::uint32_t c = 0) {
  std::seed_seq sequence{seed, a, b, c};
  return std::mt19937(sequence);
}

sim::Anthropometry drawBody(bool female, std::mt19937& random) {
  std::normal_distribution<double> standard(0.0, 1.0);
  auto factor = [&](double cv) { return 1.0 + cv * standard(random); };
  const double stature = female ? kFemaleStatureMean + kFemaleStatureSd * standard(random)
                                : kMaleStatureMean + kMaleStatureSd * standard(random);
  sim::Anthropometry body = sim::Anthropometry::fromStature(stature);
  const double arms = factor(0.03), legs = factor(0.03);
  body.upper_arm_length *= arms * factor(0.02);
  body.forearm_length *= arms * factor(0.02);
  body.hand_length *= arms * factor(0.02);
  body.thigh_length *= legs * factor(0.02);
  body.shank_length *= legs * factor(0.02);
  body.head_height *= factor(0.03);
  body.foot_length *= factor(0.04);
  body.shoulder_width *= (female ? 0.96 : 1.0) * factor(0.05);
  body.hip_width *= (female ? 1.04 : 1.0) * factor(0.05);
  // The torso takes up the rest: the stature stays the one drawn.
  body.torso_length = stature - body.ankle_height - body.shank_length - body.thigh_length -
                      body.neck_length - body.head_height;
  const double build = factor(0.06);
  for (double sim::Anthropometry::*girth :
       {&sim::Anthropometry::head_girth, &sim::Anthropometry::neck_girth,
        &sim::Anthropometry::chest_girth, &sim::Anthropometry::waist_girth,
        &sim::Anthropometry::hip_girth, &sim::Anthropometry::upper_arm_girth,
        &sim::Anthropometry::forearm_girth, &sim::Anthropometry::thigh_girth,
        &sim::Anthropometry::calf_girth})
    body.*girth *= (girth == &sim::Anthropometry::head_girth ? 1.0 : build) * factor(0.03);
  if (female) {
    body.chest_girth *= 0.95;
    body.hip_girth *= 1.05;
  }
  return body;
}

GaitStyle drawStyle(std::mt19937& random) {
  std::normal_distribution<double> standard(0.0, 1.0);
  GaitStyle style;
  for (const AngleSpread& angle : kStyleSpread)
    style.*angle.field =
        std::clamp(angle.mean + angle.sd * standard(random), angle.min, angle.max) * kDegree;
  return style;
}

}  // namespace

std::vector<SimulatedPerson> simulatedPeople(int count, std::uint32_t seed) {
  if (count < 0)
    throw std::invalid_argument("simulatedPeople: count must be >= 0, got " +
                                std::to_string(count));
  std::vector<SimulatedPerson> people;
  people.reserve(count);
  for (int i = 0; i < count; ++i) {
    // Each person from their own stream: person i is the same whatever the count.
    std::mt19937 random = stream(seed, static_cast<std::uint32_t>(i));
    SimulatedPerson person;
    char name[32];
    std::snprintf(name, sizeof(name), "person_%03d", i);
    person.name = name;
    const bool female = std::bernoulli_distribution(0.5)(random);
    person.gender = female ? "female" : "male";
    person.age = std::uniform_int_distribution<int>(18, 70)(random);
    person.body = drawBody(female, random);
    person.style = drawStyle(random);
    person.seed = random();
    people.push_back(person);
  }
  return people;
}

sim::HumanBodySpec walkingSubject(const SimulatedPerson& person, int index, int trial,
                                  double heading) {
  if (index < 1 || index > 4)
    throw std::invalid_argument("walkingSubject: index must be 1..4 (thesis 5.3), got " +
                                std::to_string(index));
  if (trial < 0)
    throw std::invalid_argument("walkingSubject: trial must be >= 0, got " + std::to_string(trial));
  std::normal_distribution<double> standard(0.0, 1.0);
  // The walk's own offsets: the same for its four poses.
  std::mt19937 walk_random = stream(person.seed, static_cast<std::uint32_t>(trial));
  GaitStyle style = person.style;
  for (const AngleSpread& angle : kStyleSpread)
    style.*angle.field += kTrialSd * standard(walk_random);
  std::mt19937 pose_random =
      stream(person.seed, static_cast<std::uint32_t>(trial), static_cast<std::uint32_t>(index));
  auto jitter = [&](double angle) { return angle + kPoseSd * standard(pose_random); };

  sim::HumanBodySpec spec;
  spec.name = person.name;
  spec.body = person.body;
  std::uniform_real_distribution<double> standing(-kStandingSpread, kStandingSpread);
  const double x = standing(pose_random), y = standing(pose_random);  // in this order
  spec.position = Eigen::Vector3d(x, y, 0);
  sim::BodyPose& pose = spec.pose;
  pose.heading = heading;
  pose.torso_lean = jitter(style.torso_lean);
  pose.left_shoulder_abduction = jitter(style.arm_abduction);
  pose.right_shoulder_abduction = jitter(style.arm_abduction);
  pose.left_hip_abduction = jitter(style.hip_abduction);
  pose.right_hip_abduction = jitter(style.hip_abduction);
  pose.left_elbow_flexion = jitter(style.elbow_flexion);
  pose.right_elbow_flexion = jitter(style.elbow_flexion);

  // Poses 1, 2 lead with the right leg (and left arm), 3, 4 with the left (thesis 5.3).
  const bool right_leads = index <= 2;
  const double lead_bias = right_leads ? style.asymmetry : -style.asymmetry;
  double& lead_hip = right_leads ? pose.right_hip_flexion : pose.left_hip_flexion;
  double& trail_hip = right_leads ? pose.left_hip_flexion : pose.right_hip_flexion;
  double& lead_knee = right_leads ? pose.right_knee_flexion : pose.left_knee_flexion;
  double& trail_knee = right_leads ? pose.left_knee_flexion : pose.right_knee_flexion;
  double& front_shoulder = right_leads ? pose.left_shoulder_flexion : pose.right_shoulder_flexion;
  double& back_shoulder = right_leads ? pose.right_shoulder_flexion : pose.left_shoulder_flexion;
  double& front_elbow = right_leads ? pose.left_elbow_flexion : pose.right_elbow_flexion;
  if (index == 1 || index == 3) {  // heel strike: the longest stride, arms swing opposite
    lead_hip = jitter(style.hip_swing + lead_bias);
    trail_hip = -jitter(style.hip_extension - lead_bias);
    lead_knee = jitter(style.lead_knee_flexion);
    trail_knee = jitter(style.trail_knee_flexion);
    front_shoulder = jitter(style.arm_swing);
    back_shoulder = -jitter(style.arm_swing_back);
    front_elbow = jitter(style.elbow_flexion + style.elbow_swing);
  } else {  // mid-stance: the stance leg vertical, the other behind, its knee bent
    lead_hip = jitter(0.0);
    trail_hip = -jitter(style.swing_hip_extension - lead_bias);
    lead_knee = jitter(style.lead_knee_flexion * 0.6);
    trail_knee = jitter(style.knee_flexion);
    front_shoulder = jitter(0.0);
    back_shoulder = jitter(0.0);
  }
  // Keep every angle within Table 5.2 (trial variation may push a style past its bound).
  auto bound = [](double& angle, double low, double high) { angle = std::clamp(angle, low, high); };
  for (double* hip : {&pose.left_hip_flexion, &pose.right_hip_flexion})
    bound(*hip, -kMaxHipFlexion, kMaxHipFlexion);
  for (double* knee : {&pose.left_knee_flexion, &pose.right_knee_flexion})
    bound(*knee, 0.0, kMaxKneeFlexion);
  for (double* shoulder : {&pose.left_shoulder_flexion, &pose.right_shoulder_flexion})
    bound(*shoulder, -kMaxShoulderFlexion, kMaxShoulderFlexion);
  for (double* elbow : {&pose.left_elbow_flexion, &pose.right_elbow_flexion})
    bound(*elbow, 0.0, kMaxElbowFlexion);
  for (double* abduction : {&pose.left_shoulder_abduction, &pose.right_shoulder_abduction,
                            &pose.left_hip_abduction, &pose.right_hip_abduction})
    bound(*abduction, -kMaxAbduction, kMaxAbduction);
  return spec;
}

}  // namespace body_gait_model::eval
