// A skinned human mesh for the virtual pair (uses assets from MakeHuman, CC0: data/mesh_human/).
// The base mesh is shaped by macro parameters (sex, age, muscle, body fat, height, ethnic blend)
// as multilinear blends of morph targets, its skeleton joints are recomputed from the morphed
// vertices, and it is posed by linear-blend skinning on the body segment frames the ellipsoid
// body uses (human_body.h): the gait generator's joint angles (forward kinematics) or a BVH
// frame (poseBodyOnSkeleton), through the bone-to-segment map of config/mesh/mesh_retarget.yaml.
// World frame: metres, x forward (the subject's front), y left, z up, soles on z = 0.
#pragma once

#include <body_scan_driver/sim/human_body.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace body_scan_driver::sim {

// The packed body kit (scripts/pack_mesh_human.py writes it; the format is documented there).
struct MeshHumanModel {
  std::vector<Eigen::Vector3f> base;           // all kept vertices, decimetres, MakeHuman axes
  int body_vertex_count = 0;                   // the skin: vertices 0..body_vertex_count-1
  std::vector<std::array<uint16_t, 4>> quads;  // the skin, counter-clockwise from outside
  struct Joint {
    std::string name;
    std::vector<uint16_t> vertices;  // the joint is their mean
  };
  std::vector<Joint> joints;
  std::map<std::string, int> joint_index;
  struct Bone {
    std::string name, parent;                         // parent "" = the root
    int head = -1, tail = -1;                         // joint indices
    std::vector<std::pair<uint16_t, float>> weights;  // skin vertex, raw weight
  };
  std::vector<Bone> bones;
  std::map<std::string, int> bone_index;
  struct Target {
    std::string name;                 // e.g. "universal-male-old-maxmuscle-minweight"
    std::vector<std::string> states;  // its state tokens (female, old, maxmuscle, ...)
    bool height = false;              // a height target (no old variant: age factor 1)
    int data = -1;                    // index into offsets
  };
  std::vector<Target> targets;
  struct Offset {
    uint16_t vertex;
    std::array<int16_t, 3> delta;  // 1/1000 decimetre
  };
  std::vector<std::vector<Offset>> offsets;

  // Throws std::runtime_error naming the file and the problem (missing, truncated, bad index).
  static MeshHumanModel load(const std::string& path);
  int jointIndex(const std::string& name) const;  // throws std::out_of_range naming it
};

// Where the kit and the retarget map are (sim/data_paths.h: meshHumanFiles() for the package's).
struct MeshHumanFiles {
  std::string model;         // data/mesh_human/mesh_human.bin
  std::string retarget_map;  // config/mesh/mesh_retarget.yaml
};

// The kit at `path`, loaded once per path (thread-safe).
const MeshHumanModel& meshHumanModel(const std::string& path);

// MakeHuman's macro sliders, each 0..1 (0.5 = the average; age 0.5 = 25 years, 1 = 90).
struct MacroParameters {
  double gender = 0.5;  // 0 female, 1 male
  double age = 0.5;     // kit limit 0.5..1
  double muscle = 0.5;
  double weight = 0.5;  // body fat, not mass
  double height = 0.5;
  double african = 1.0 / 3, asian = 1.0 / 3, caucasian = 1.0 / 3;  // normalized to sum 1
};

// Each target's weight: the product of its states' weights (height targets: age factor 1, the
// kit has only the young ones). Throws std::invalid_argument naming a slider outside its range.
std::vector<double> targetWeights(const MeshHumanModel& model, const MacroParameters& macros);

// A morphed rest-pose (A-pose) body in the world frame: metres, x front, y left, z up, the
// lowest skin vertex on z = 0, the midline on x-y origin of MakeHuman (about the crotch).
struct MorphedMesh {
  std::vector<Eigen::Vector3f> vertices;  // all kept vertices
  std::vector<Eigen::Vector3d> joints;    // per MeshHumanModel::joints, from the vertices
  double stature = 0;                     // m, highest skin vertex above the soles
  double volume = 0;                      // m^3, of the closed skin
};
MorphedMesh morphMesh(const MeshHumanModel& model, const MacroParameters& macros);

// The skin's triangles (two per quad) and its boundary edges (0 for a closed surface).
std::vector<std::array<int, 3>> skinTriangles(const MeshHumanModel& model);
int boundaryEdgeCount(const MeshHumanModel& model);

// A person: what a survey records, mapped to macro parameters by personMacros.
struct MeshPersonSpec {
  double stature = 1.75;  // m, soles to vertex
  double gender = 1.0;    // 0 female .. 1 male
  double age = 30;        // years, 25..90
  double bmi = 23;        // kg/m^2: skin volume x 1000 kg/m^3 / stature^2
  double muscle = 0.5;    // slider, 0..1
  double african = 1.0 / 3, asian = 1.0 / 3, caucasian = 1.0 / 3;
};

// Solves the height slider for the stature and the weight (body fat) slider for the BMI, beyond
// whose range the muscle slider moves from person.muscle toward 1 (heavier) or 0 (lighter);
// alternately, by bisection (stature to 0.5 mm, BMI to 0.05). The kit's bodies span BMI about
// 15-24 (women) and 14-31 (men). Throws std::invalid_argument naming a spec value it cannot
// reach (stature 1.40-2.10 m, age 25-90, BMI outside that span).
MacroParameters personMacros(const MeshHumanModel& model, const MeshPersonSpec& person);

// The skinning rig of a morphed body: each skin vertex's weights over the body segments (bone
// weights, renormalized, summed per segment through the retarget map), the segments' rest
// frames, the lengths FK needs (Anthropometry) and the landmarks of the true skeleton.
struct MeshRetargetMap {
  // Body segment (human_body.h names: pelvis, torso, neck, left_upper_arm, ...) -> the bones that
  // move with it; a bone not named follows its parent's segment.
  std::map<std::string, std::vector<std::string>> segment_bones;
  // Skeleton joint (left_shoulder, ...) -> mesh joint (a bone's "<bone>____head" / "____tail").
  std::map<std::string, std::string> joints;
};
MeshRetargetMap loadMeshRetargetMap(const std::string& path);  // throws naming file and key

class MeshHumanRig {
 public:
  MeshHumanRig(const MeshHumanModel& model, MorphedMesh mesh, const MeshRetargetMap& map);

  // The rest pose's dimensions: every length of Anthropometry from the mesh's skeleton (girths
  // scaled from fromStature: the mesh carries its own shape).
  const Anthropometry& anthropometry() const { return anthropometry_; }
  const MorphedMesh& rest() const { return mesh_; }
  const BodySegmentFrames& restFrames() const { return rest_frames_; }

  // Skin vertices posed on segment frames (linear-blend skinning of each segment's affine map
  // rest -> posed, stretched along the bone and across the trunk to the posed lengths).
  std::vector<Eigen::Vector3f> pose(const BodySegmentFrames& frames,
                                    const Anthropometry& lengths) const;
  // The true skeleton of a pose: humanSkeleton's names; joint centres are the posed segment
  // origins (mesh joints of the retarget map at rest), head_top and toe the posed mesh landmarks.
  std::vector<SkeletonJoint> skeleton(const BodySegmentFrames& frames,
                                      const Anthropometry& lengths) const;
  // A mesh joint (MeshHumanModel::joints name) at rest, carried by one segment's map: how the
  // retargeting is checked (e.g. the elbow by the upper arm's map lands on the posed elbow).
  Eigen::Vector3d posedMeshJoint(const std::string& joint, const std::string& segment,
                                 const BodySegmentFrames& frames,
                                 const Anthropometry& lengths) const;
  // Per-triangle material: 0 skin, 1 hair (the cap of the scalp), 2 clothing (briefs).
  const std::vector<uint8_t>& triangleMaterial() const { return material_; }
  // Per-triangle segment (segmentName): the one its vertices' weights favour.
  const std::vector<uint8_t>& triangleSegment() const { return triangle_segment_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }
  const MeshHumanModel& model() const { return model_; }

  static constexpr int kSegmentCount = 15;
  static const char* segmentName(int segment);

 private:
  std::array<SegmentFrame, kSegmentCount> segmentFrames(const BodySegmentFrames& frames) const;
  std::array<Eigen::Matrix<double, 3, 4>, kSegmentCount> segmentMaps(
      const BodySegmentFrames& frames, const Anthropometry& lengths) const;

  const MeshHumanModel& model_;
  MorphedMesh mesh_;
  Anthropometry anthropometry_;
  BodySegmentFrames rest_frames_;
  std::array<double, kSegmentCount> rest_length_{};  // along each segment's bone (trunk: height)
  std::array<double, 2> rest_width_{};               // hip and shoulder widths
  struct Influence {
    uint8_t segment;
    float weight;
  };
  std::vector<std::array<Influence, 4>> influences_;  // per skin vertex, weight 0 = unused
  std::vector<std::array<int, 3>> triangles_;
  std::vector<uint8_t> material_;
  std::vector<uint8_t> triangle_segment_;
  int head_top_vertex_ = 0;
  std::array<int, 2> toe_vertex_{};
};

// A mesh person in a scene: who (the person spec) and how posed (the HumanBodySpec's pose and
// position, or its segment_frames from a BVH frame).
struct MeshHumanSpec {
  MeshPersonSpec person;
  HumanBodySpec body;  // name, pose / segment_frames, position, materials; lengths from the mesh
};

// The rig of a person (solve the macros, morph, rig: tens of ms).
std::shared_ptr<const MeshHumanRig> meshHumanRig(const MeshPersonSpec& person,
                                                 const MeshHumanFiles& files);

// Adds the posed skin (one Embree-backed TriangleMesh surface "<name>/skin") and the true skeleton
// to the scene. body.body's lengths are replaced by the rig's unless segment_frames are set
// (a BVH pose keeps the file's lengths and the mesh stretches to them).
void addMeshHuman(const MeshHumanSpec& spec, const MeshHumanFiles& files, Scene& scene);
void addMeshHuman(const MeshHumanRig& rig, const HumanBodySpec& body, Scene& scene);

// The person keys of a scene object (stature, gender, age, bmi, muscle, african, asian,
// caucasian); absent keys keep the defaults. Throws std::runtime_error naming the key.
MeshPersonSpec meshPersonFromYaml(const YAML::Node& node, const std::string& where);

// A scene-file object of type mesh_human (config/scenes/mesh_person.yaml): the person keys, then
// either a pose like a human's (pose, position, heading_deg) or a BVH frame like a bvh_human's
// (bvh, joint_map, frame or gait_pose; the stature defaults to the one the legs imply), and
// materials; model and retarget_map name the kit and the map (defaults: the package's, relative
// to base_dir = the scene file's folder). Throws std::runtime_error naming `where` and the key.
void addMeshHumanFromYaml(const YAML::Node& object, const std::string& where,
                          const std::string& base_dir, Scene& scene);

}  // namespace body_scan_driver::sim
