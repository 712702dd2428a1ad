// Posable procedural human body: one forward-kinematics routine poses the segment frames; the
// skeleton and the ellipsoids that dress it are both read off those frames.
#include <body_scan_driver/sim/human_body.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "../yaml_file.h"

namespace body_scan_driver::sim {

Anthropometry Anthropometry::fromStature(double stature) {
  if (!(stature > 0))
    throw std::runtime_error("human body: stature must be > 0 m, got " + std::to_string(stature));
  // Joint heights and segment lengths as fractions of stature H (Drillis & Contini 1966, as
  // drawn in Winter, "Biomechanics and Motor Control of Human Movement", fig. 4.1): chin 0.870,
  // shoulder 0.818, hip (greater trochanter) 0.530, knee 0.285, ankle 0.039; upper arm 0.186,
  // forearm 0.146, hand 0.108, head 0.130, foot 0.152. Joint-centre breadths are narrower than
  // the outer breadths (bi-acromial 0.259, bi-trochanteric 0.191): ~0.20 and ~0.10.
  Anthropometry body;
  const double h = stature;
  body.stature = h;
  body.head_height = 0.130 * h;
  body.neck_length = (0.870 - 0.818) * h;
  body.shoulder_width = 0.200 * h;
  body.torso_length = (0.818 - 0.530) * h;
  body.hip_width = 0.100 * h;
  body.upper_arm_length = 0.186 * h;
  body.forearm_length = 0.146 * h;
  body.hand_length = 0.108 * h;
  body.thigh_length = (0.530 - 0.285) * h;
  body.shank_length = (0.285 - 0.039) * h;
  body.ankle_height = 0.039 * h;
  body.foot_length = 0.152 * h;
  // Girths of a typical adult of 1.75 m (ANSUR II medians, rounded), scaled with stature.
  const double scale = h / 1.75;
  body.head_girth = 0.57 * scale;
  body.neck_girth = 0.38 * scale;
  body.chest_girth = 0.98 * scale;
  body.waist_girth = 0.84 * scale;
  body.hip_girth = 0.98 * scale;
  body.upper_arm_girth = 0.30 * scale;
  body.forearm_girth = 0.27 * scale;
  body.thigh_girth = 0.56 * scale;
  body.calf_girth = 0.37 * scale;
  return body;
}

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;

// Every Anthropometry field by its C++ name: validation and the YAML reader share the list.
const std::pair<const char*, double Anthropometry::*> kDimensions[] = {
    {"stature", &Anthropometry::stature},
    {"head_height", &Anthropometry::head_height},
    {"neck_length", &Anthropometry::neck_length},
    {"shoulder_width", &Anthropometry::shoulder_width},
    {"torso_length", &Anthropometry::torso_length},
    {"hip_width", &Anthropometry::hip_width},
    {"upper_arm_length", &Anthropometry::upper_arm_length},
    {"forearm_length", &Anthropometry::forearm_length},
    {"hand_length", &Anthropometry::hand_length},
    {"thigh_length", &Anthropometry::thigh_length},
    {"shank_length", &Anthropometry::shank_length},
    {"ankle_height", &Anthropometry::ankle_height},
    {"foot_length", &Anthropometry::foot_length},
    {"head_girth", &Anthropometry::head_girth},
    {"neck_girth", &Anthropometry::neck_girth},
    {"chest_girth", &Anthropometry::chest_girth},
    {"waist_girth", &Anthropometry::waist_girth},
    {"hip_girth", &Anthropometry::hip_girth},
    {"upper_arm_girth", &Anthropometry::upper_arm_girth},
    {"forearm_girth", &Anthropometry::forearm_girth},
    {"thigh_girth", &Anthropometry::thigh_girth},
    {"calf_girth", &Anthropometry::calf_girth},
};

const std::pair<const char*, double BodyPose::*> kAngles[] = {
    {"heading", &BodyPose::heading},
    {"torso_lean", &BodyPose::torso_lean},
    {"neck_flexion", &BodyPose::neck_flexion},
    {"left_shoulder_flexion", &BodyPose::left_shoulder_flexion},
    {"left_shoulder_abduction", &BodyPose::left_shoulder_abduction},
    {"left_elbow_flexion", &BodyPose::left_elbow_flexion},
    {"right_shoulder_flexion", &BodyPose::right_shoulder_flexion},
    {"right_shoulder_abduction", &BodyPose::right_shoulder_abduction},
    {"right_elbow_flexion", &BodyPose::right_elbow_flexion},
    {"left_hip_flexion", &BodyPose::left_hip_flexion},
    {"left_hip_abduction", &BodyPose::left_hip_abduction},
    {"left_knee_flexion", &BodyPose::left_knee_flexion},
    {"right_hip_flexion", &BodyPose::right_hip_flexion},
    {"right_hip_abduction", &BodyPose::right_hip_abduction},
    {"right_knee_flexion", &BodyPose::right_knee_flexion},
};

const std::pair<const char*, Material BodyMaterials::*> kMaterials[] = {
    {"skin", &BodyMaterials::skin},
    {"hair", &BodyMaterials::hair},
    {"clothing", &BodyMaterials::clothing}};

void validate(const Anthropometry& body) {
  for (const auto& [name, field] : kDimensions) {
    if (!(body.*field > 0))
      throw std::runtime_error(std::string("human body: '") + name +
                               "' must be > 0 (metres), got " + std::to_string(body.*field));
  }
}

// Shape fractions not covered by Anthropometry, relative to the segment they belong to.
constexpr double kLimbOverlap = 0.10;      // limb ellipsoids reach past each joint by this * bone
constexpr double kChestHeight = 0.64;      // chest centre above the hips, * torso_length
constexpr double kHeelBehindAnkle = 0.25;  // * foot_length
constexpr double kFootCentreBelowAnkle = 0.45;  // * ankle_height (the sole touches the floor)
constexpr double kHairThickness = 0.045;        // * head_height

Eigen::Matrix3d aboutAxis(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

using Frame = SegmentFrame;
using PosedBody = BodySegmentFrames;

const char* const kSideNames[2] = {"left", "right"};
constexpr double kSideSign[2] = {1.0, -1.0};  // +y is the subject's left

PosedBody forwardKinematics(const HumanBodySpec& spec) {
  validate(spec.body);
  if (spec.segment_frames) return *spec.segment_frames;
  const Anthropometry& b = spec.body;
  const BodyPose& p = spec.pose;
  const Eigen::Vector3d x_axis = Eigen::Vector3d::UnitX(), y_axis = Eigen::Vector3d::UnitY();
  const Frame root{aboutAxis(Eigen::Vector3d::UnitZ(), p.heading), spec.position};
  PosedBody body;
  body.pelvis = root.child({0, 0, b.ankle_height + b.shank_length + b.thigh_length});
  // A rotation about +y turns +z toward +x: positive lean and neck flexion tip forward.
  body.torso = body.pelvis.child(Eigen::Vector3d::Zero(), aboutAxis(y_axis, p.torso_lean));
  body.neck = body.torso.child({0, 0, b.torso_length}, aboutAxis(y_axis, p.neck_flexion));
  for (int side = 0; side < 2; ++side) {
    const double sign = kSideSign[side];
    const bool left = side == 0;
    const double shoulder_flexion = left ? p.left_shoulder_flexion : p.right_shoulder_flexion;
    const double shoulder_abduction = left ? p.left_shoulder_abduction : p.right_shoulder_abduction;
    const double elbow_flexion = left ? p.left_elbow_flexion : p.right_elbow_flexion;
    const double hip_flexion = left ? p.left_hip_flexion : p.right_hip_flexion;
    const double hip_abduction = left ? p.left_hip_abduction : p.right_hip_abduction;
    const double knee_flexion = left ? p.left_knee_flexion : p.right_knee_flexion;
    // A bone along -z swings forward under a rotation about -y and outward about sign * x.
    body.upper_arm[side] = body.torso.child(
        {0, sign * b.shoulder_width / 2, b.torso_length},
        aboutAxis(y_axis, -shoulder_flexion) * aboutAxis(x_axis, sign * shoulder_abduction));
    body.forearm[side] =
        body.upper_arm[side].child({0, 0, -b.upper_arm_length}, aboutAxis(y_axis, -elbow_flexion));
    body.hand[side] = body.forearm[side].child({0, 0, -b.forearm_length});
    body.thigh[side] = body.pelvis.child(
        {0, sign * b.hip_width / 2, 0},
        aboutAxis(y_axis, -hip_flexion) * aboutAxis(x_axis, sign * hip_abduction));
    // The knee bends the shank backward.
    body.shank[side] =
        body.thigh[side].child({0, 0, -b.thigh_length}, aboutAxis(y_axis, knee_flexion));
    body.foot[side] = body.shank[side].child({0, 0, -b.shank_length});
  }
  return body;
}

// One side's limb length: the measured skeleton's if it has one, else the body's.
double sideLength(const PosedBody& body, int side, double PosedBody::Lengths::*measured,
                  const Anthropometry& b, double Anthropometry::*common) {
  const double length = body.side_lengths[side].*measured;
  return length > 0 ? length : b.*common;
}

Eigen::Vector3d toeIn(const Frame& foot, double foot_length, const Anthropometry& b) {
  return foot.at((1 - kHeelBehindAnkle) * foot_length, 0, -kFootCentreBelowAnkle * b.ankle_height);
}

std::vector<SkeletonJoint> skeletonOf(const PosedBody& body, const Anthropometry& b) {
  std::vector<SkeletonJoint> joints = {
      {"head_top", body.neck.at(0, 0, b.neck_length + b.head_height)},
      {"neck", body.neck.origin},
      {"chest", body.torso.at(0, 0, kChestHeight * b.torso_length)},
      {"pelvis", body.pelvis.origin},
  };
  for (int side = 0; side < 2; ++side) {
    const std::string prefix = std::string(kSideNames[side]) + "_";
    joints.push_back({prefix + "shoulder", body.upper_arm[side].origin});
    joints.push_back({prefix + "elbow", body.forearm[side].origin});
    joints.push_back({prefix + "wrist", body.hand[side].origin});
    const double hand_length =
        sideLength(body, side, &PosedBody::Lengths::hand, b, &Anthropometry::hand_length);
    joints.push_back({prefix + "hand_tip", body.hand[side].at(0, 0, -hand_length)});
    joints.push_back({prefix + "hip", body.thigh[side].origin});
    joints.push_back({prefix + "knee", body.shank[side].origin});
    joints.push_back({prefix + "ankle", body.foot[side].origin});
    const double foot_length =
        sideLength(body, side, &PosedBody::Lengths::foot, b, &Anthropometry::foot_length);
    joints.push_back({prefix + "toe", toeIn(body.foot[side], foot_length, b)});
  }
  return joints;
}

// Semi-axes (depth along x, width along y) of an ellipse whose perimeter is the girth, for a
// given depth/width ratio: Ramanujan's perimeter approximation is linear in the width.
Eigen::Vector2d semiAxesFromGirth(double girth, double depth_to_width) {
  const double k = depth_to_width;
  const double h = std::pow((1 - k) / (1 + k), 2);
  const double perimeter_per_width = kPi * (1 + k) * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h)));
  const double width = girth / perimeter_per_width;
  return {k * width, width};
}

double radiusOfGirth(double girth) { return girth / (2 * kPi); }

}  // namespace

std::vector<SkeletonJoint> humanSkeleton(const HumanBodySpec& spec) {
  return skeletonOf(forwardKinematics(spec), spec.body);
}

BodySegmentFrames bodySegmentFrames(const HumanBodySpec& spec) { return forwardKinematics(spec); }

namespace {

// A limb frame on `proximal` with the bone along local -z toward `distal` and local x toward the
// segment's front (the orientation's first column, made perpendicular to the bone).
Frame limbFrame(const Eigen::Vector3d& proximal, const Eigen::Vector3d& distal,
                const Eigen::Matrix3d& orientation) {
  const Eigen::Vector3d z = (proximal - distal).normalized();
  const Eigen::Vector3d front = orientation.col(0);
  Eigen::Vector3d x = front - front.dot(z) * z;
  // A front along the bone (degenerate): fall back on the segment's up direction.
  if (x.norm() < 1e-6) x = orientation.col(2) - orientation.col(2).dot(z) * z;
  x.normalize();
  Frame frame;
  frame.origin = proximal;
  frame.rotation.col(0) = x;
  frame.rotation.col(1) = z.cross(x);
  frame.rotation.col(2) = z;
  return frame;
}

// A trunk frame on `origin` with z toward `top` and y toward `left` (made perpendicular to z).
Frame trunkFrame(const Eigen::Vector3d& origin, const Eigen::Vector3d& top,
                 const Eigen::Vector3d& left) {
  const Eigen::Vector3d z = (top - origin).normalized();
  const Eigen::Vector3d y = (left - left.dot(z) * z).normalized();
  Frame frame;
  frame.origin = origin;
  frame.rotation.col(0) = y.cross(z);
  frame.rotation.col(1) = y;
  frame.rotation.col(2) = z;
  return frame;
}

}  // namespace

void poseBodyOnSkeleton(const SkeletonPose& skeleton, HumanBodySpec& spec) {
  auto joint = [&](const std::string& name) -> const Eigen::Vector3d& {
    const auto found = skeleton.joints.find(name);
    if (found == skeleton.joints.end() || !found->second.allFinite())
      throw std::invalid_argument("poseBodyOnSkeleton: joint '" + name +
                                  "' is missing or not finite (map it in the joint map)");
    return found->second;
  };
  auto orientation = [&](const std::string& segment) -> const Eigen::Matrix3d& {
    const auto found = skeleton.orientations.find(segment);
    if (found == skeleton.orientations.end() || !found->second.allFinite())
      throw std::invalid_argument("poseBodyOnSkeleton: orientation of segment '" + segment +
                                  "' is missing or not finite");
    return found->second;
  };
  Anthropometry& b = spec.body;
  PosedBody body;
  const Eigen::Vector3d hip_mid = (joint("left_hip") + joint("right_hip")) / 2;
  const Eigen::Vector3d shoulder_mid = (joint("left_shoulder") + joint("right_shoulder")) / 2;
  const Eigen::Vector3d hip_line = joint("left_hip") - joint("right_hip");
  const Eigen::Vector3d shoulder_line = joint("left_shoulder") - joint("right_shoulder");
  body.pelvis = trunkFrame(hip_mid, hip_mid + orientation("pelvis").col(2), hip_line);
  body.torso = trunkFrame(hip_mid, shoulder_mid, shoulder_line);
  body.neck = trunkFrame(shoulder_mid, joint("head_top"), shoulder_line);
  b.hip_width = hip_line.norm();
  b.shoulder_width = shoulder_line.norm();
  b.torso_length = (shoulder_mid - hip_mid).norm();
  // Shoulder line to vertex, split as in fromStature (neck 0.052 H, head 0.130 H).
  const double neck_and_head = (joint("head_top") - shoulder_mid).norm();
  b.head_height = neck_and_head * 0.130 / (0.130 + 0.052);
  b.neck_length = neck_and_head - b.head_height;
  for (int side = 0; side < 2; ++side) {
    const std::string prefix = std::string(kSideNames[side]) + "_";
    const Eigen::Vector3d &shoulder = joint(prefix + "shoulder"), &elbow = joint(prefix + "elbow"),
                          &wrist = joint(prefix + "wrist"), &tip = joint(prefix + "hand_tip"),
                          &hip = joint(prefix + "hip"), &knee = joint(prefix + "knee"),
                          &ankle = joint(prefix + "ankle"), &toe = joint(prefix + "toe");
    body.upper_arm[side] = limbFrame(shoulder, elbow, orientation(prefix + "upper_arm"));
    body.forearm[side] = limbFrame(elbow, wrist, orientation(prefix + "forearm"));
    body.hand[side] = limbFrame(wrist, tip, orientation(prefix + "hand"));
    body.thigh[side] = limbFrame(hip, knee, orientation(prefix + "thigh"));
    body.shank[side] = limbFrame(knee, ankle, orientation(prefix + "shank"));
    // The foot frame is pitched so that its toe point (toeIn) lands on the measured toe: in the
    // frame the toe is `forward` ahead and kFootCentreBelowAnkle * ankle_height below the ankle.
    const Eigen::Vector3d to_toe = toe - ankle;
    const double below = kFootCentreBelowAnkle * b.ankle_height;
    const double forward = std::sqrt(std::max(to_toe.squaredNorm() - below * below, 1e-6));
    const Eigen::Vector3d along = to_toe.normalized();
    const Eigen::Vector3d lateral = orientation(prefix + "foot").col(1);
    const Eigen::Vector3d y = (lateral - lateral.dot(along) * along).normalized();
    const Eigen::Vector3d up = along.cross(y);
    const double pitch = std::atan2(below, forward);
    Frame& foot = body.foot[side];
    foot.origin = ankle;
    foot.rotation.col(0) = std::cos(pitch) * along + std::sin(pitch) * up;
    foot.rotation.col(1) = y;
    foot.rotation.col(2) = foot.rotation.col(0).cross(y);
    // The body's lengths are the means of the sides (the sides' own drive the frames).
    const double half = 0.5;
    if (side == 0) {
      b.upper_arm_length = b.forearm_length = b.hand_length = 0;
      b.thigh_length = b.shank_length = b.foot_length = 0;
    }
    PosedBody::Lengths& lengths = body.side_lengths[side];
    lengths.upper_arm = (elbow - shoulder).norm();
    lengths.forearm = (wrist - elbow).norm();
    lengths.hand = (tip - wrist).norm();
    lengths.thigh = (knee - hip).norm();
    lengths.shank = (ankle - knee).norm();
    lengths.foot = forward / (1 - kHeelBehindAnkle);
    b.upper_arm_length += half * lengths.upper_arm;
    b.forearm_length += half * lengths.forearm;
    b.hand_length += half * lengths.hand;
    b.thigh_length += half * lengths.thigh;
    b.shank_length += half * lengths.shank;
    b.foot_length += half * lengths.foot;
  }
  spec.segment_frames = body;
}

void addHumanBody(const HumanBodySpec& spec, Scene& scene) {
  const PosedBody body = forwardKinematics(spec);
  const Anthropometry& b = spec.body;
  const BodyMaterials& materials = spec.materials;
  const double torso = b.torso_length;

  auto add = [&](const std::string& segment, const Frame& frame, const Eigen::Vector3d& centre,
                 const Eigen::Vector3d& radii, const Material& material) {
    auto surface = std::make_unique<Ellipsoid>(frame.at(centre.x(), centre.y(), centre.z()),
                                               frame.rotation, radii, material);
    surface->name = spec.name + "/" + segment;
    scene.add(std::move(surface));
  };
  // Trunk cross-sections: (depth, width) semi-axes from the girth, then the vertical semi-axis.
  auto trunkRadii = [](double girth, double depth_to_width, double half_height) {
    const Eigen::Vector2d section = semiAxesFromGirth(girth, depth_to_width);
    return Eigen::Vector3d(section.x(), section.y(), half_height);
  };
  // A limb ellipsoid centred mid-bone, a little longer than the bone so neighbours overlap.
  auto addLimb = [&](const std::string& segment, const Frame& frame, double length,
                     const Eigen::Vector2d& section, const Material& material) {
    add(segment, frame, {0, 0, -length / 2},
        {section.x(), section.y(), (0.5 + kLimbOverlap) * length}, material);
  };
  auto addJoint = [&](const std::string& segment, const Frame& frame, double radius) {
    add(segment, frame, Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(radius), materials.skin);
  };

  // Trunk: heights relative to the hip line, as fractions of the torso length. The hip joints
  // lie 40 % of the pelvis's depth in front of the buttocks (measured on the mesh people:
  // 0.39-0.40): the pelvis's centre 0.05 torso lengths in front of them.
  add("pelvis", body.pelvis, {0.05 * torso, 0, -0.07 * torso},
      trunkRadii(b.hip_girth, 0.72, 0.30 * torso), materials.clothing);
  add("abdomen", body.torso, {0, 0, 0.30 * torso}, trunkRadii(b.waist_girth, 0.75, 0.32 * torso),
      materials.skin);
  add("chest", body.torso, {0, 0, kChestHeight * torso},
      trunkRadii(b.chest_girth, 0.70, 0.43 * torso), materials.skin);
  // Shoulder girdle: spans the shoulder joints, whose spheres round off its ends.
  add("shoulders", body.torso, {-0.02 * torso, 0, 0.97 * torso},
      {0.17 * torso, 0.6 * b.shoulder_width, 0.13 * torso}, materials.skin);

  // Neck and head. The skull stops a hair's thickness below the vertex; the hair cap, shifted
  // up and back, covers the top and back of the skull and reaches the vertex.
  const double neck_depth_to_width = 0.9;
  const Eigen::Vector2d neck_section = semiAxesFromGirth(b.neck_girth, neck_depth_to_width);
  add("neck", body.neck, {0, 0, 0.58 * b.neck_length},
      {neck_section.x(), neck_section.y(), 1.15 * b.neck_length}, materials.skin);
  const double hair = kHairThickness * b.head_height;
  const double skull_half_height = (b.head_height - hair) / 2;
  const Eigen::Vector3d skull_centre(0.04 * b.head_height, 0, b.neck_length + skull_half_height);
  const Eigen::Vector3d skull = trunkRadii(b.head_girth, 1.25, skull_half_height);
  add("head", body.neck, skull_centre, skull, materials.skin);
  const Eigen::Vector3d hair_centre =
      skull_centre + Eigen::Vector3d(-0.066, 0, 0.088) * b.head_height;
  const double vertex = b.neck_length + b.head_height;
  add("hair", body.neck, hair_centre,
      {skull.x() + 0.5 * hair, skull.y() + 0.8 * hair, vertex - hair_centre.z()}, materials.hair);

  const double upper_arm_radius = radiusOfGirth(b.upper_arm_girth);
  const double forearm_radius = radiusOfGirth(b.forearm_girth);
  const double thigh_radius = radiusOfGirth(b.thigh_girth);
  const double calf_radius = radiusOfGirth(b.calf_girth);
  for (int side = 0; side < 2; ++side) {
    const std::string prefix = std::string(kSideNames[side]) + "_";
    auto length = [&](double PosedBody::Lengths::*measured, double Anthropometry::*common) {
      return sideLength(body, side, measured, b, common);
    };
    using L = PosedBody::Lengths;
    using A = Anthropometry;
    const double upper_arm_length = length(&L::upper_arm, &A::upper_arm_length);
    const double forearm_length = length(&L::forearm, &A::forearm_length);
    const double hand_length = length(&L::hand, &A::hand_length);
    const double thigh_length = length(&L::thigh, &A::thigh_length);
    const double shank_length = length(&L::shank, &A::shank_length);
    const double foot_length = length(&L::foot, &A::foot_length);
    addJoint(prefix + "shoulder", body.upper_arm[side], 0.95 * upper_arm_radius);
    addLimb(prefix + "upper_arm", body.upper_arm[side], upper_arm_length,
            {upper_arm_radius, upper_arm_radius}, materials.skin);
    addJoint(prefix + "elbow", body.forearm[side], 0.75 * forearm_radius);
    addLimb(prefix + "forearm", body.forearm[side], forearm_length,
            {forearm_radius, forearm_radius}, materials.skin);
    addJoint(prefix + "wrist", body.hand[side], 0.55 * forearm_radius);
    // A flat hand, palm toward the thigh: breadth along x, thickness along y.
    add(prefix + "hand", body.hand[side], {0, 0, -hand_length / 2},
        {0.23 * hand_length, 0.08 * hand_length, 0.52 * hand_length}, materials.skin);

    addJoint(prefix + "hip", body.thigh[side], 0.8 * thigh_radius);
    addLimb(prefix + "thigh", body.thigh[side], thigh_length, {thigh_radius, thigh_radius},
            materials.skin);
    addJoint(prefix + "knee", body.shank[side], 0.85 * calf_radius);
    addLimb(prefix + "shank", body.shank[side], shank_length, {calf_radius, calf_radius},
            materials.skin);
    addJoint(prefix + "ankle", body.foot[side], 0.55 * calf_radius);
    // The foot runs from the heel to the toe joint, its sole on the floor when standing.
    const double foot_half_height = (1 - kFootCentreBelowAnkle) * b.ankle_height;
    add(prefix + "foot", body.foot[side],
        {(0.5 - kHeelBehindAnkle) * foot_length, 0, -kFootCentreBelowAnkle * b.ankle_height},
        {0.5 * foot_length, 0.18 * foot_length, foot_half_height}, materials.skin);
  }
  scene.addJoints(skeletonOf(body, b));
}

// ---------------------------------------------------------------------------------------------
namespace {

double readNumber(const YAML::Node& map, const std::string& key, const std::string& where) {
  try {
    return map[key].as<double>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(where + ": '" + key + "' must be a number");
  }
}

double readAlbedo(const YAML::Node& map, const std::string& key, const std::string& where) {
  const double albedo = readNumber(map, key, where);
  if (!(albedo >= 0 && albedo <= 1))
    throw std::runtime_error(where + ": '" + key + "' must be within [0, 1]");
  return albedo;
}

Eigen::Vector3d readTriple(const YAML::Node& map, const std::string& key,
                           const std::string& where) {
  const YAML::Node value = map[key];
  try {
    if (value.IsSequence() && value.size() == 3)
      return {value[0].as<double>(), value[1].as<double>(), value[2].as<double>()};
  } catch (const YAML::Exception&) {
  }
  throw std::runtime_error(where + ": '" + key + "' must be a list of 3 numbers");
}

}  // namespace

HumanBodySpec humanBodyFromYaml(const YAML::Node& node) {
  HumanBodySpec spec;
  if (node.IsMap() && node["name"]) spec.name = node["name"].as<std::string>();
  const std::string where = "human '" + spec.name + "'";

  std::vector<std::string> accepted = {"type",        "name", "position",
                                       "heading_deg", "pose", "materials"};
  for (const auto& dimension : kDimensions) accepted.push_back(dimension.first);
  requireKnownKeys(node, accepted, where);
  if (node["type"] && node["type"].as<std::string>() != "human")
    throw std::runtime_error(where + ": 'type' must be 'human'");

  // Stature first: it sets every default, which the other dimensions may then override.
  if (node["stature"]) {
    const double stature = readNumber(node, "stature", where);
    if (!(stature > 0)) throw std::runtime_error(where + ": 'stature' must be > 0 (metres)");
    spec.body = Anthropometry::fromStature(stature);
  }
  for (const auto& [key, field] : kDimensions) {
    if (!node[key]) continue;
    spec.body.*field = readNumber(node, key, where);
    if (!(spec.body.*field > 0))
      throw std::runtime_error(where + ": '" + key + "' must be > 0 (metres)");
  }
  if (node["position"]) spec.position = readTriple(node, "position", where);
  if (node["heading_deg"]) spec.pose.heading = readNumber(node, "heading_deg", where) * kDegree;

  if (const YAML::Node pose = node["pose"]) {
    std::vector<std::string> angle_keys;
    for (const auto& angle : kAngles) angle_keys.push_back(std::string(angle.first) + "_deg");
    requireKnownKeys(pose, angle_keys, where + ": pose");
    if (pose["heading_deg"] && node["heading_deg"])
      throw std::runtime_error(where + ": give 'heading_deg' once, not also under 'pose'");
    for (const auto& [name, field] : kAngles) {
      const std::string key = std::string(name) + "_deg";
      if (pose[key]) spec.pose.*field = readNumber(pose, key, where + ": pose") * kDegree;
    }
  }

  if (const YAML::Node materials = node["materials"]) {
    const std::string material_where = where + ": materials";
    std::vector<std::string> material_keys;
    for (const auto& material : kMaterials) {
      material_keys.push_back(std::string(material.first) + "_albedo");
      material_keys.push_back(std::string(material.first) + "_color");
    }
    requireKnownKeys(materials, material_keys, material_where);
    for (const auto& [name, field] : kMaterials) {
      const std::string albedo_key = std::string(name) + "_albedo";
      const std::string color_key = std::string(name) + "_color";
      if (materials[albedo_key])
        (spec.materials.*field).albedo = readAlbedo(materials, albedo_key, material_where);
      if (materials[color_key])
        (spec.materials.*field).color = readTriple(materials, color_key, material_where);
    }
  }
  return spec;
}

YAML::Node humanBodyToYaml(const HumanBodySpec& spec) {
  // The keys humanBodyFromYaml reads, from the same tables, so the two cannot drift apart.
  YAML::Node node;
  node["type"] = "human";
  node["name"] = spec.name;
  for (const auto& [key, field] : kDimensions) node[key] = spec.body.*field;
  for (int i = 0; i < 3; ++i) node["position"].push_back(spec.position[i]);
  for (const auto& [name, field] : kAngles)
    node["pose"][std::string(name) + "_deg"] = spec.pose.*field / kDegree;
  for (const auto& [name, field] : kMaterials) {
    const Material& material = spec.materials.*field;
    node["materials"][std::string(name) + "_albedo"] = material.albedo;
    for (int i = 0; i < 3; ++i)
      node["materials"][std::string(name) + "_color"].push_back(material.color[i]);
  }
  return node;
}

}  // namespace body_scan_driver::sim
