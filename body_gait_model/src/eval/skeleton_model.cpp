// The body model of the simulator's true skeleton (tests and evaluation only).
#include <body_gait_model/eval/skeleton_model.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace body_gait_model::eval {

namespace sim = body_scan_driver::sim;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kHipToCrotch = 0.06;  // of the stature (Drillis & Contini: hip 0.53, crotch 0.47)

Eigen::Vector3d jointNamed(const std::vector<sim::SkeletonJoint>& skeleton,
                           const std::string& name) {
  for (const auto& joint : skeleton)
    if (joint.name == name) return joint.position;
  throw std::invalid_argument("modelFromSkeleton: the skeleton has no joint '" + name +
                              "'; pass the simulator's skeleton (sim::humanSkeleton)");
}

double radiusOfGirth(double girth) { return girth / (2 * kPi); }

}  // namespace

BodyModel modelFromSkeleton(const std::vector<sim::SkeletonJoint>& skeleton,
                            const sim::Anthropometry& body) {
  auto joint = [&](const std::string& name) { return jointNamed(skeleton, name); };
  const Eigen::Vector3d pelvis = joint("pelvis"), neck = joint("neck");
  // The model's lower leg ends at the sole: ankle_height past the ankle along the shank.
  auto sole = [&](const std::string& side) {
    const Eigen::Vector3d knee = joint(side + "_knee"), ankle = joint(side + "_ankle");
    return Eigen::Vector3d(ankle + body.ankle_height * (ankle - knee).normalized());
  };

  BodyModel model;
  // Whole body: level, X_m from the right hip to the left, Y_m up, Z_m = X_m x Y_m (front).
  Eigen::Vector3d lateral = joint("left_hip") - joint("right_hip");
  lateral.z() = 0;
  if (!(lateral.norm() > 0))
    throw std::invalid_argument("modelFromSkeleton: the hips coincide; no body frame");
  lateral.normalize();
  Eigen::Matrix3d rotation;
  rotation.col(0) = lateral;
  rotation.col(1) = Eigen::Vector3d::UnitZ();
  rotation.col(2) = lateral.cross(Eigen::Vector3d::UnitZ());
  model.p = poseVectorFromFrame(pelvis, rotation);

  // Lengths and joint placements first: the children's joint offsets depend on them.
  const Eigen::Vector3d torso_axis = (neck - pelvis).normalized();
  const Eigen::Vector3d head_base = neck + body.neck_length * torso_axis;
  model.r[kUpperTorso] = (neck - pelvis).norm();
  model.r[kNeck] = body.neck_length;
  model.r[kHead] = (joint("head_top") - head_base).norm();
  model.r[kLowerTorso] = kHipToCrotch * body.stature;
  BodyShape& shape = model.shape;
  shape.shoulder_half_width = (joint("left_shoulder") - joint("right_shoulder")).norm() / 2;
  shape.shoulder_drop = 0;
  shape.hip_half_width = (joint("left_hip") - joint("right_hip")).norm() / 2;
  shape.hip_rise = model.r[kLowerTorso];
  struct Limb {
    int segment;
    std::string from, to;
  };
  const Limb limbs[] = {
      {kRightUpperArm, "right_shoulder", "right_elbow"},
      {kRightLowerArm, "right_elbow", "right_hand_tip"},
      {kLeftUpperArm, "left_shoulder", "left_elbow"},
      {kLeftLowerArm, "left_elbow", "left_hand_tip"},
      {kRightUpperLeg, "right_hip", "right_knee"},
      {kRightLowerLeg, "right_knee", "right_sole"},
      {kLeftUpperLeg, "left_hip", "left_knee"},
      {kLeftLowerLeg, "left_knee", "left_sole"},
  };
  auto target = [&](const std::string& name) {
    if (name == "right_sole") return sole("right");
    if (name == "left_sole") return sole("left");
    return joint(name);
  };
  for (const Limb& limb : limbs)
    model.r[limb.segment] = (target(limb.to) - joint(limb.from)).norm();

  // Radii from the girths; the far ends taper like standingModel's.
  auto setRadii = [&](int segment, double proximal, double distal) {
    shape.proximal_radius[segment] = proximal;
    shape.distal_radius[segment] = distal;
  };
  setRadii(kUpperTorso, radiusOfGirth(body.waist_girth), radiusOfGirth(body.chest_girth));
  setRadii(kNeck, radiusOfGirth(body.neck_girth), radiusOfGirth(body.neck_girth));
  setRadii(kHead, radiusOfGirth(body.head_girth), 0.9 * radiusOfGirth(body.head_girth));
  setRadii(kLowerTorso, radiusOfGirth(body.hip_girth), 0.9 * radiusOfGirth(body.hip_girth));
  for (int upper_arm : {kRightUpperArm, kLeftUpperArm}) {
    setRadii(upper_arm, radiusOfGirth(body.upper_arm_girth), radiusOfGirth(body.forearm_girth));
    setRadii(upper_arm + 1, radiusOfGirth(body.forearm_girth),
             0.7 * radiusOfGirth(body.forearm_girth));
  }
  for (int upper_leg : {kRightUpperLeg, kLeftUpperLeg}) {
    setRadii(upper_leg, radiusOfGirth(body.thigh_girth), radiusOfGirth(body.calf_girth));
    setRadii(upper_leg + 1, radiusOfGirth(body.calf_girth), 0.64 * radiusOfGirth(body.calf_girth));
  }

  // Angles, parents before children: each segment points from its (posed) joint to its target.
  auto aim = [&](int segment, const Eigen::Vector3d& to) {
    const PosedModel posed = forwardKinematics(model);
    const int parent = segmentInfo(segment).parent;
    const Eigen::Isometry3d& parent_frame =
        parent == kWholeBody ? posed.whole_body : posed.segments[parent].frame;
    const Eigen::Vector3d from = parent_frame * jointOffset(model, segment);
    const Eigen::Vector2d angles = jointAnglesForDirection(
        parent_frame.linear().transpose() * (to - from), segmentInfo(segment).points_up);
    model.setJointAngles(segment, angles.x(), angles.y());
  };
  aim(kUpperTorso, neck);
  // The lower torso hangs straight down: the simulator's pelvis does not tilt.
  aim(kHead, joint("head_top"));
  for (const Limb& limb : limbs) aim(limb.segment, target(limb.to));
  return model;
}

BodyModel modelFromSkeleton(const sim::HumanBodySpec& spec) {
  return modelFromSkeleton(sim::humanSkeleton(spec), spec.body);
}

BodyModel modelFromSkeleton(const SampledBody& body) {
  return modelFromSkeleton(body.skeleton, body.spec.body);
}

}  // namespace body_gait_model::eval
