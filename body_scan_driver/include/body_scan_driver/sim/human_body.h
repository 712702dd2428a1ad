// Posable procedural human body for the virtual pair: ellipsoids sized from anthropometric
// parameters and posed by joint angles. Body frame: x forward (the subject's front), y to the
// subject's left, z up, origin on the floor under the pelvis (DESIGN.md section 3).
#pragma once

#include <body_scan_driver/sim/scene.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace body_scan_driver::sim {

// Body dimensions in metres. fromStature() fills every field from standard segment-length
// ratios of stature (Drillis & Contini) and typical girths; any field may then be overridden.
struct Anthropometry {
  double stature = 1.75;
  double head_height = 0;       // vertex to chin
  double neck_length = 0;       // chin to shoulder line
  double shoulder_width = 0;    // between the shoulder joint centres
  double torso_length = 0;      // shoulder joints to hip joints (vertical)
  double hip_width = 0;         // between the hip joint centres
  double upper_arm_length = 0;  // shoulder to elbow
  double forearm_length = 0;    // elbow to wrist
  double hand_length = 0;
  double thigh_length = 0;  // hip to knee
  double shank_length = 0;  // knee to ankle
  double ankle_height = 0;  // floor to ankle joint
  double foot_length = 0;
  double head_girth = 0;
  double neck_girth = 0;
  double chest_girth = 0;
  double waist_girth = 0;
  double hip_girth = 0;
  double upper_arm_girth = 0;
  double forearm_girth = 0;
  double thigh_girth = 0;
  double calf_girth = 0;

  static Anthropometry fromStature(double stature);
};

// Joint angles in radians. Flexion is about the body's lateral (y) axis, positive = limb
// forward (knee and elbow flexion positive = bending); abduction is about the body's x axis,
// positive = away from the midline. Defaults: standing, arms slightly abducted.
struct BodyPose {
  double heading = 0;     // rotation of the body about world z (0 = facing world +x)
  double torso_lean = 0;  // forward lean of the upper torso about the hips
  double neck_flexion = 0;
  double left_shoulder_flexion = 0, left_shoulder_abduction = 0.2, left_elbow_flexion = 0.1;
  double right_shoulder_flexion = 0, right_shoulder_abduction = 0.2, right_elbow_flexion = 0.1;
  double left_hip_flexion = 0, left_hip_abduction = 0.03, left_knee_flexion = 0;
  double right_hip_flexion = 0, right_hip_abduction = 0.03, right_knee_flexion = 0;
};

// Albedos of skin, hair and clothing (defaults: DESIGN/issue defaults, dark hair and
// dark trunks 0.15, skin 0.6).
struct BodyMaterials {
  Material skin{0.6, {0.87, 0.68, 0.58}};
  Material hair{0.15, {0.12, 0.09, 0.07}};
  Material clothing{0.15, {0.10, 0.10, 0.12}};
};

// A rigid frame posed in the world: world point = origin + rotation * local point.
struct SegmentFrame {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();

  Eigen::Vector3d at(double x, double y, double z) const {
    return origin + rotation * Eigen::Vector3d(x, y, z);
  }
  // A frame attached at a local point, turned by local_rotation relative to this one.
  SegmentFrame child(const Eigen::Vector3d& local_origin,
                     const Eigen::Matrix3d& local_rotation = Eigen::Matrix3d::Identity()) const {
    return {rotation * local_rotation, origin + rotation * local_origin};
  }
};

// The posed segment frames the ellipsoids and the skeleton are read off. Trunk frames have z up;
// limb frames sit on the proximal joint with the bone along local -z and local x toward the
// segment's front. Index 0 = left, 1 = right.
struct BodySegmentFrames {
  SegmentFrame pelvis;  // midpoint of the hip joints
  SegmentFrame torso;   // same origin, z toward the middle of the shoulder line
  SegmentFrame neck;    // middle of the shoulder line, z toward the vertex
  SegmentFrame upper_arm[2], forearm[2], hand[2], thigh[2], shank[2], foot[2];
  // Per-side limb lengths of a measured skeleton (m); 0 = the Anthropometry's (both sides).
  struct Lengths {
    double upper_arm = 0, forearm = 0, hand = 0, thigh = 0, shank = 0, foot = 0;
  };
  Lengths side_lengths[2];
};

struct HumanBodySpec {
  std::string name = "person";
  Anthropometry body = Anthropometry::fromStature(1.75);
  BodyPose pose;
  BodyMaterials materials;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world, floor point under the pelvis
  // When set (e.g. by poseBodyOnSkeleton from motion capture), the body is posed by these frames
  // instead of `pose` and `position` (pose.heading still names the front for evaluation).
  std::optional<BodySegmentFrames> segment_frames;
};

// A skeleton measured elsewhere (motion capture), in the world frame (m, z up). `joints` needs
// left_/right_ hip, knee, ankle, toe (the tip of the foot), shoulder, elbow, wrist, hand_tip, and
// head_top. `orientations` gives each segment's orientation (columns: front, left, up of the
// segment in the standing reference pose) for pelvis, torso, neck and left_/right_ upper_arm,
// forearm, hand, thigh, shank, foot; only the directions across each bone are used, the bone
// itself runs between the joints.
struct SkeletonPose {
  std::map<std::string, Eigen::Vector3d> joints;
  std::map<std::string, Eigen::Matrix3d> orientations;
};

// Poses the ellipsoid body on a measured skeleton: sets spec.segment_frames and every length of
// spec.body from the joints (the girths and the ankle height stay as given), and the skeleton
// that addHumanBody records then has those joints. Throws std::invalid_argument naming a missing
// joint or orientation.
void poseBodyOnSkeleton(const SkeletonPose& skeleton, HumanBodySpec& spec);

// The true skeleton (world frame) of a posed body: joints named head_top, neck, left_shoulder,
// left_elbow, left_wrist, left_hand_tip, left_hip, left_knee, left_ankle, left_toe (and right_),
// pelvis, chest.
std::vector<SkeletonJoint> humanSkeleton(const HumanBodySpec& spec);

// The posed segment frames of a spec (its segment_frames, or the angles' forward kinematics).
BodySegmentFrames bodySegmentFrames(const HumanBodySpec& spec);

// Adds the body's surfaces (named "<name>/<segment>") and skeleton to the scene.
void addHumanBody(const HumanBodySpec& spec, Scene& scene);

// Reads a spec from a scene-file node (keys documented in config/scenes/standing_person.yaml).
// Throws std::runtime_error naming the bad key and the accepted values.
HumanBodySpec humanBodyFromYaml(const YAML::Node& node);

// The scene-file node of a spec (every dimension, angle and material written out), read back by
// humanBodyFromYaml to the same spec: how tools hand a generated person to a scene file.
YAML::Node humanBodyToYaml(const HumanBodySpec& spec);

}  // namespace body_scan_driver::sim
