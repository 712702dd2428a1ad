// Simulated whole-body clouds for tests and evaluation (NOT used by the fitter): rays cast into
// the simulator's Scene from a rig like the thesis's (3 poles around the subject, 4 heights per
// pole), the four representative gait poses of thesis 5.3 and subjects of varied anthropometry.
// Only this library reads the simulator's ground truth (the true skeleton).
#pragma once

#include <body_gait_model/kinematic_model.h>
#include <body_scan_driver/sim/human_body.h>
#include <body_scan_driver/sim/mesh_human.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace body_gait_model::eval {

// The simulator's body a spec is dressed with: 32 ellipsoids (human_body.h) or the skinned mesh
// human (mesh_human.h, posed by the same angles or BVH frame).
enum class BodyKind { kEllipsoid, kMesh };
// "ellipsoid" or "mesh"; throws std::invalid_argument naming the accepted values.
BodyKind parseBodyKind(const std::string& name);
const char* bodyKindName(BodyKind kind);

// The mesh person of a spec made for the ellipsoid body: its stature; female where the hips are
// 5 % wider than the chest (gait_subjects' women); BMI 22 (women 21) scaled by the square of the
// waist girth over fromStature's, kept in the kit's span; age 30.
body_scan_driver::sim::MeshPersonSpec meshPersonOf(
    const body_scan_driver::sim::HumanBodySpec& spec);

// Adds the spec's body of that kind and its true skeleton to the scene; returns the spec as
// placed (a mesh's lengths are the mesh's own unless the spec has BVH segment frames). Mesh rigs
// are built once per person (thread-safe cache).
body_scan_driver::sim::HumanBodySpec addSimulatedBody(
    const body_scan_driver::sim::HumanBodySpec& spec, BodyKind kind,
    body_scan_driver::sim::Scene& scene);

// The scene-file object (sim::loadScene) of the spec's body of that kind, so a launched scanner
// scans exactly what addSimulatedBody adds: a `human` (humanBodyToYaml), or a `mesh_human` of
// meshPersonOf(spec) in the spec's pose whose kit and retarget map are named by absolute paths
// (the file may be written anywhere).
YAML::Node simulatedBodyToYaml(const body_scan_driver::sim::HumanBodySpec& spec, BodyKind kind);

struct ScanRig {
  int poles = 3;               // evenly spaced around the subject
  double pole_angle = 0.5236;  // world azimuth of the first pole (rad)
  double pole_distance = 1.0;  // horizontal distance from the subject's vertical axis (m)
  std::vector<double> heights = {0.25, 0.7, 1.15, 1.6};  // viewpoint heights on each pole (m)
  double horizontal_fov = 1.15;  // of each viewpoint (rad); it looks horizontally at the axis
  double vertical_fov = 0.95;
  int columns = 320, rows = 260;  // ray grid of each viewpoint
  double noise_sigma = 0.0;       // Gaussian range noise along the ray (m)
  // Surfaces darker than this return no light (dark hair, dark trousers): no points.
  double min_albedo = 0.0;
  std::vector<int> missing_viewpoints;  // indices pole * heights.size() + height: no data
  std::uint32_t seed = 1;
  BodyKind body = BodyKind::kEllipsoid;  // the body the rays hit
};

struct SampledBody {
  std::vector<Eigen::Vector3d> points;  // world frame
  std::vector<int> surface_of_point;    // index into the scene's surfaces (evaluation only)
  std::vector<std::string> surface_names;
  std::vector<body_scan_driver::sim::SkeletonJoint> skeleton;  // ground truth (evaluation only)
  body_scan_driver::sim::HumanBodySpec spec;
};

SampledBody sampleBody(const body_scan_driver::sim::HumanBodySpec& spec, const ScanRig& rig = {});

// The four representative poses of thesis 5.3 (index 1..4): 1 right leg and left arm forward,
// longest stride; 2 right leg vertical, left leg behind, hands along the sides; 3 and 4 the
// mirror images. Angles stay within Table 5.2 so a perfect fit is representable.
body_scan_driver::sim::BodyPose gaitPose(int index, double heading = 0.0);

// count subjects of varied stature (1.55-1.95 m), girth and limb proportions, deterministic.
std::vector<body_scan_driver::sim::HumanBodySpec> simulatedSubjects(int count);

// Position of a named joint of the true skeleton; throws std::invalid_argument if absent.
Eigen::Vector3d trueJoint(const SampledBody& body, const std::string& name);

}  // namespace body_gait_model::eval

namespace body_gait_model::eval {

// Errors of a fitted model against the simulator's true skeleton (evaluation only).
struct FitErrors {
  std::map<std::string, double> joint_error;           // m, per joint name (PosedModel names)
  std::map<std::string, double> segment_length_error;  // fraction, per limb segment name
  std::map<std::string, double> swing_error;           // rad, upper/lower arms and legs
  // Diagnostics: fitted minus true joint in the true body frame (forward, left, up; m) and the
  // signed segment-length error (fraction; > 0 = fitted too long).
  std::map<std::string, Eigen::Vector3d> joint_offset;
  std::map<std::string, double> segment_length_bias;
  double mean_joint_error = 0, mean_length_error = 0, mean_swing_error = 0;
  // Mean joint error after the rigid motion that best aligns the fitted joints with the true
  // ones (rotation + translation removed, as pose-estimation papers report it).
  double procrustes_joint_error = 0;
  bool front_right = false;  // fitted front within 45 degrees of the true heading
  bool left_right = false;   // the fitted left arm/leg is the subject's left (true left side)
};

FitErrors compareWithTruth(const BodyModel& model, const SampledBody& body);

}  // namespace body_gait_model::eval
