// The 12-segment kinematic body model of thesis section 5.4: a tree of tapered cylinders with
// 2-DOF joints (about the local x and z axes), the bounds of Table 5.2 and the pose vectors
// p (eq 5.1), q (eq 5.2) and r (eq 5.3).
//
// Model frame (thesis 5.5.1): X_m coronal (toward the subject's left), Y_m vertical (up), Z_m
// sagittal (toward the subject's front); right-handed, so X_m = Y_m x Z_m. Every segment frame
// has the same convention and its cylinder axis along local +Y (upper torso, neck, head) or
// local -Y (all others). A joint turns its child by Rx(theta_x) * Rz(theta_z): theta_x swings a
// segment in the sagittal plane, theta_z in the coronal plane; there is no twist (5.4).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

namespace body_gait_model {

// Segment index = thesis part ID - 1 (Table 5.2).
enum Segment : int {
  kUpperTorso = 0,
  kNeck,
  kHead,
  kRightUpperArm,
  kRightLowerArm,
  kLeftUpperArm,
  kLeftLowerArm,
  kLowerTorso,
  kRightUpperLeg,
  kRightLowerLeg,
  kLeftUpperLeg,
  kLeftLowerLeg,
};
constexpr int kSegmentCount = 12;
constexpr int kWholeBody = -1;  // parent of the upper and lower torso (part 0 of Table 5.2)

struct SegmentInfo {
  const char* name;  // snake_case, used for URDF links and reports
  int parent;        // segment index, or kWholeBody
  bool points_up;    // cylinder along local +Y (else -Y)
  bool fixed;        // the neck: no joint angles (5.4)
};
const SegmentInfo& segmentInfo(int segment);

// Bounds of a joint's two angles in radians (the neck's are all zero).
struct JointLimits {
  double x_min, x_max, z_min, z_max;
};
// Table 5.2's bounds of one joint.
JointLimits jointLimits(int segment);

// Bounds of every joint, indexed by segment. theta_x > 0 swings a segment's far end backward
// (knee flexion, hip and shoulder extension), < 0 forward (hip and shoulder flexion, elbow
// flexion); theta_z swings it toward the left.
using JointLimitSet = std::array<JointLimits, kSegmentCount>;
// Table 5.2 (symmetric, knee +-30 deg): the thesis protocol's set.
const JointLimitSet& thesisJointLimits();
// Normal level walking from gait biomechanics (knee flexion to 80 deg, hip, shoulder and elbow
// ranges of gait; the lower torso level across: its theta_z limits are both 0, which holds that
// axis): the fitter's default; config/body_fitter.yaml lists the values and sources.
const JointLimitSet& walkingJointLimits();

using PoseVector = Eigen::Matrix<double, 6, 1>;       // p, eq 5.1: tau_x,y,z, theta_x,y,z
using JointAngles = Eigen::Matrix<double, 22, 1>;     // q, eq 5.2
using SegmentLengths = Eigen::Matrix<double, 12, 1>;  // r, eq 5.3: l^1 .. l^12

// Index into q of a segment's theta_x (theta_z follows it), or -1 for the fixed neck.
int jointAngleIndex(int segment);

// What the thesis's 40 DOF leave out but a surface model needs: the cylinders' radii and where
// the shoulder and hip joints sit on the torso. Estimated by the fitter, not part of p, q, r.
struct BodyShape {
  std::array<double, kSegmentCount> proximal_radius{};  // at the segment's joint
  std::array<double, kSegmentCount> distal_radius{};    // at its far end
  double shoulder_half_width = 0.18;  // shoulder joints at +-X_m from the upper-torso axis ...
  double shoulder_drop = 0.06;        // ... this far below the upper torso's top
  double hip_half_width = 0.09;       // hip joints at +-X_m from the lower-torso axis ...
  double hip_rise = 0.05;             // ... this far above the lower torso's base ...
  double hip_back = 0;                // ... and this far behind its axis (-Z_m)
};

// The shape's joint placements by name, for files, messages and per-field statistics.
struct JointPlacement {
  const char* name;
  double BodyShape::*field;
};
constexpr JointPlacement kJointPlacements[] = {
    {"shoulder_half_width", &BodyShape::shoulder_half_width},
    {"shoulder_drop", &BodyShape::shoulder_drop},
    {"hip_half_width", &BodyShape::hip_half_width},
    {"hip_rise", &BodyShape::hip_rise},
    {"hip_back", &BodyShape::hip_back}};

struct BodyModel {
  PoseVector p = PoseVector::Zero();
  JointAngles q = JointAngles::Zero();
  SegmentLengths r = SegmentLengths::Zero();
  BodyShape shape;

  // theta_x / theta_z of a segment's joint (0 for the neck).
  double thetaX(int segment) const;
  double thetaZ(int segment) const;
  void setJointAngles(int segment, double theta_x, double theta_z);
};

// A plausible standing adult of the given stature: lengths and radii from standard ratios,
// all angles zero, standing at the world origin facing world +x. Used as the initial shape
// for refinement and in tests; not a fit.
BodyModel standingModel(double stature);

// Rotation taking model axes to world axes for p's angles: the upright body faces world +x
// with X_m = world +y, Y_m = world +z; then Ry(theta_y) (heading about the vertical) *
// Rx(theta_x) * Rz(theta_z).
Eigen::Matrix3d wholeBodyRotation(const PoseVector& p);

struct PosedSegment {
  Eigen::Isometry3d frame;   // segment frame -> world; origin at the joint
  Eigen::Vector3d proximal;  // joint end of the cylinder axis (world)
  Eigen::Vector3d distal;    // far end (world)
  double proximal_radius = 0, distal_radius = 0;
};

struct PosedModel {
  Eigen::Isometry3d whole_body;  // model frame -> world (origin: the torso joint, eq 5.4's e_0)
  std::array<PosedSegment, kSegmentCount> segments;

  // Joint centres by name: neck_base (top of the upper torso), head_base, head_top, waist
  // (root), right_/left_ shoulder, elbow, wrist (distal end of the lower arm), hip, knee, ankle
  // (distal end of the lower leg). Throws std::invalid_argument naming the accepted names.
  Eigen::Vector3d joint(const std::string& name) const;
};

// Joint angles (theta_x, theta_z) that point a segment along direction (unit, in its parent's
// frame): the inverse of the Rx * Rz convention above for a +Y or -Y cylinder.
Eigen::Vector2d jointAnglesForDirection(const Eigen::Vector3d& direction, bool points_up);

// p (eq 5.1) of a whole-body frame at origin with the given model-to-world rotation (columns
// X_m, Y_m, Z_m); inverse of wholeBodyRotation.
PoseVector poseVectorFromFrame(const Eigen::Vector3d& origin, const Eigen::Matrix3d& rotation);

// Where a segment's joint sits in its parent's frame (the whole-body frame for the torso).
Eigen::Vector3d jointOffset(const BodyModel& model, int segment);

// Forward kinematics of the tree (Table 5.2 parents).
PosedModel forwardKinematics(const BodyModel& model);

// True if every joint angle lies within the limits (the neck's must be zero).
bool withinJointLimits(const BodyModel& model, const JointLimitSet& limits = thesisJointLimits());
// The model with every joint angle clamped into the limits.
BodyModel clampToJointLimits(BodyModel model, const JointLimitSet& limits = thesisJointLimits());
// Every joint angle within `tolerance` (rad) of one of its bounds, named like
// "right_lower_leg theta_x at its max 80 deg".
std::vector<std::string> jointLimitsReached(const BodyModel& model, const JointLimitSet& limits,
                                            double tolerance = 0.01);

// Distance from a point to the lateral surface of a tapered cylinder whose axis runs from
// proximal (radius r0) to distal (radius r1): in the half-plane (axial, radial) through the
// point, the distance to the profile segment (0, r0)-(L, r1). Negative inside the cylinder.
double taperedCylinderDistance(const Eigen::Vector3d& point, const Eigen::Vector3d& proximal,
                               const Eigen::Vector3d& distal, double r0, double r1);

// The same distance with the per-cylinder terms computed once (for many points: refinement,
// quality); distance(p) == taperedCylinderDistance(p, proximal, distal, r0, r1).
class TaperedCylinder {
 public:
  TaperedCylinder() = default;
  TaperedCylinder(const Eigen::Vector3d& proximal, const Eigen::Vector3d& distal, double r0,
                  double r1);
  explicit TaperedCylinder(const PosedSegment& segment)
      : TaperedCylinder(segment.proximal, segment.distal, segment.proximal_radius,
                        segment.distal_radius) {}
  double distance(const Eigen::Vector3d& point) const;

 private:
  Eigen::Vector3d proximal_ = Eigen::Vector3d::Zero(), unit_ = Eigen::Vector3d::Zero();
  double length_ = 0, r0_ = 0, r1_ = 0, slope_ = 0, inverse_profile_squared_ = 0;
};

// The segment whose surface is nearest to `point`, with the unsigned distance to it.
struct NearestSegment {
  int segment;
  double distance;
};
using SegmentSurfaces = std::array<TaperedCylinder, kSegmentCount>;
SegmentSurfaces segmentSurfaces(const PosedModel& posed);
NearestSegment nearestSegment(const SegmentSurfaces& surfaces, const Eigen::Vector3d& point);
NearestSegment nearestSegment(const PosedModel& posed, const Eigen::Vector3d& point);

}  // namespace body_gait_model
