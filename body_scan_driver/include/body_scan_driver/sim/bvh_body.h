// The simulator's human body driven by motion capture: a BVH motion (sim/bvh.h) bound to the body
// through a joint map (config/bvh/<scheme>_joint_map.yaml), the body of any frame placed in the
// scanner, and the four representative walking poses of thesis 5.3 found in the motion.
#pragma once

#include <body_scan_driver/sim/bvh.h>
#include <body_scan_driver/sim/human_body.h>

#include <array>
#include <functional>
#include <map>
#include <string>

namespace YAML {
class Node;
}

namespace body_scan_driver::sim {

// How one naming scheme's BVH skeleton maps onto the simulator's body.
struct BvhJointMap {
  std::string scheme;
  double unit_scale = 0;  // metres per BVH unit
  // BVH axes -> simulator axes (x = the subject's front in the rest pose, y = left, z = up).
  Eigen::Matrix3d to_world = Eigen::Matrix3d::Identity();
  std::map<std::string, std::string> joints;     // simulator joint -> BVH joint (its origin)
  std::map<std::string, std::string> end_sites;  // simulator point -> BVH joint (its End Site)
  // Far ends ("hand_tip", "head_top") whose length comes from the body, not the BVH.
  bool hand_length_from_body = false, head_height_from_body = false;
};

// Throws std::runtime_error naming the file, the bad key and the accepted values.
BvhJointMap loadBvhJointMap(const std::string& path);
BvhJointMap bvhJointMapFromYaml(const YAML::Node& node, const std::string& where);

// A subject walking in a BVH file. The skeleton's lengths come from the file (BVH offsets times
// the unit scale); girths and the ankle height from `girths` (by default Anthropometry::
// fromStature of the stature the leg length implies), and so do the far ends the map names in
// far_ends_from_body.
class BvhSubject {
 public:
  // Throws std::invalid_argument naming a joint of the map that the motion does not have.
  BvhSubject(BvhMotion motion, BvhJointMap map, std::string name);

  const std::string& name() const { return name_; }
  const BvhMotion& motion() const { return motion_; }
  int frameCount() const { return static_cast<int>(motion_.frames.size()); }

  // Mapped joints and end sites of a frame (0-based): simulator axes, metres, the file's origin.
  std::map<std::string, Eigen::Vector3d> joints(int frame) const;
  // The skeleton of a frame for poseBodyOnSkeleton (same axes and origin as joints()); far ends
  // the map takes from the body get `body`'s lengths along the BVH's directions.
  SkeletonPose skeleton(int frame, const Anthropometry& body) const;
  // Stature implied by the legs: (thigh + shank) / 0.491, the ratio of fromStature.
  double estimatedStature() const;

  // The body of `frame` placed in the scanner: the pelvis (midpoint of the hip joints) of this
  // frame above the world origin and facing +x (hip line along y), the lower ankle
  // ankle_height above the floor (z = 0). pose.heading is 0 (the front is +x).
  HumanBodySpec body(int frame) const;
  HumanBodySpec body(int frame, const Anthropometry& girths) const;

 private:
  BvhMotion motion_;
  BvhJointMap map_;
  std::string name_;
  std::map<std::string, int> joint_index_, end_site_index_;
};

// The four representative poses of thesis 5.3 (index 0..3 = poses 1..4) as 0-based frames:
// 1 right heel strike (right leg in front, longest stride), 2 right mid-stance (right leg
// vertical, left leg behind), 3 and 4 the same for the left leg. A heel strike is the first
// frame at which a foot that was swinging is planted again: its ankle within 3 cm of its lowest
// (stance) height and its horizontal speed below half the walking speed. Mid-stance is the first
// frame after it at which the hip passes over the planted ankle (along the walking direction).
struct GaitPoseFrames {
  std::array<int, 4> frame{};
  double walking_speed = 0;  // m/s, of the pelvis over the clip
};

// Throws std::runtime_error if the clip holds no complete set (too short, or not a walk).
GaitPoseFrames pickGaitPoses(const BvhSubject& subject);

// A walk named on a command line as [PERSON=]path/WALK.bvh: the person defaults to the file
// name's part before '_' (CMU naming: 07_02.bvh is person "07"), the walk is the file's stem.
struct BvhWalkFile {
  std::string person, walk, file;
};
BvhWalkFile parseBvhWalkFile(const std::string& item);

// Turns a placed body (BvhSubject::body) by `heading` about world z and moves it to `position`
// (floor point under the pelvis): its frames, pose.heading and position.
void moveBody(HumanBodySpec& spec, double heading, const Eigen::Vector3d& position);

// A scene-file object of type bvh_human (config/scenes/bvh_walker.yaml): keys bvh and joint_map
// (files, relative to base_dir), frame (1-based) or gait_pose (1-4, thesis 5.3, picked), and
// human's name, stature (girths; default from the legs), position, heading_deg, materials.
// Throws std::runtime_error naming `where` and the key.
// body_for (optional): the body's lengths and girths from the stature the legs imply, instead
// of the 'stature' key (the mesh human's: its own skeleton, sim/mesh_human.h).
HumanBodySpec bvhHumanFromYaml(
    const YAML::Node& object, const std::string& where, const std::string& base_dir,
    const std::function<Anthropometry(double estimated_stature)>& body_for = {});

}  // namespace body_scan_driver::sim
