// Gait reconstruction (thesis 5.6, eqs 5.11-5.13) and symmetric poses (5.8.3).
#include <body_gait_model/gait_cycle.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The segment on the other side of the body (itself for the torso, neck and head).
int mirrorSegment(int segment) {
  switch (segment) {
    case kRightUpperArm:
      return kLeftUpperArm;
    case kRightLowerArm:
      return kLeftLowerArm;
    case kLeftUpperArm:
      return kRightUpperArm;
    case kLeftLowerArm:
      return kRightLowerArm;
    case kRightUpperLeg:
      return kLeftUpperLeg;
    case kRightLowerLeg:
      return kLeftLowerLeg;
    case kLeftUpperLeg:
      return kRightUpperLeg;
    case kLeftLowerLeg:
      return kRightLowerLeg;
    default:
      return segment;
  }
}

// Horizontal unit vector of the body's front (Z_m in the world).
Eigen::Vector3d horizontalFront(const BodyModel& pose) {
  Eigen::Vector3d front = wholeBodyRotation(pose.p).col(2);
  front.z() = 0;
  return front.normalized();
}

BodyShape meanShape(const RepresentativePoses& poses) {
  BodyShape mean = poses[0].shape;
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    mean.proximal_radius[segment] = mean.distal_radius[segment] = 0;
    for (const BodyModel& pose : poses) {
      mean.proximal_radius[segment] += pose.shape.proximal_radius[segment] / poses.size();
      mean.distal_radius[segment] += pose.shape.distal_radius[segment] / poses.size();
    }
  }
  for (const auto& [name, field] : kJointPlacements) {
    mean.*field = 0;
    for (const BodyModel& pose : poses) mean.*field += pose.shape.*field / poses.size();
  }
  return mean;
}

// Forward distance (along `front`) from the trailing to the leading sole: one step.
double stepLength(const BodyModel& pose, const char* leading, const char* trailing,
                  const Eigen::Vector3d& front) {
  const PosedModel posed = forwardKinematics(pose);
  return (posed.joint(std::string(leading) + "_sole") -
          posed.joint(std::string(trailing) + "_sole"))
      .dot(front);
}

}  // namespace

BodyModel mirroredPose(const BodyModel& pose) {
  BodyModel mirrored = pose;
  // Reflection S = diag(-1, 1, 1) in a joint's frame: S Rx(a) Rz(b) S = Rx(a) Rz(-b), and the
  // joint offsets at +-X_m change side. So segment s of the mirror takes its partner's theta_x
  // and -theta_z; about the heading plane the root frame becomes H Rx(theta_x) Rz(-theta_z).
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    if (segment == kNeck) continue;
    const int partner = mirrorSegment(segment);
    mirrored.setJointAngles(segment, pose.thetaX(partner), -pose.thetaZ(partner));
    mirrored.r[segment] = pose.r[partner];
    mirrored.shape.proximal_radius[segment] = pose.shape.proximal_radius[partner];
    mirrored.shape.distal_radius[segment] = pose.shape.distal_radius[partner];
  }
  mirrored.p[5] = -pose.p[5];
  return mirrored;
}

RepresentativePoses symmetricPoses(const RepresentativePoses& s) {
  RepresentativePoses symmetric;
  for (int i = 0; i < 4; ++i) symmetric[i] = mirroredPose(s[(i + 2) % 4]);
  return symmetric;
}

RepresentativePoses gaitSet(const RepresentativePoses& s, GaitSet which) {
  if (which == GaitSet::kEta3) return s;
  const RepresentativePoses mirrored = symmetricPoses(s);
  // eta1 keeps the heel strikes s1, s3 and mirrors the mid-stances; eta2 the other way round.
  const bool keep_odd = which == GaitSet::kEta1;
  RepresentativePoses set;
  for (int i = 0; i < 4; ++i) set[i] = (i % 2 == 0) == keep_odd ? s[i] : mirrored[i];
  return set;
}

GaitCycle reconstructGaitCycle(const RepresentativePoses& poses) {
  GaitCycle cycle;
  // Direction: the mean heading of the four fits (5.8.2 sets it by hand).
  Eigen::Vector3d front = Eigen::Vector3d::Zero();
  for (const BodyModel& pose : poses) front += horizontalFront(pose);
  if (!(front.norm() > 1e-6))
    throw std::invalid_argument(
        "gait cycle: the four poses face opposite ways (no mean heading); check the fits' "
        "front/back");
  front.normalize();
  // Stride = two steps: at s1 the right foot leads, at s3 the left.
  const double right_step = stepLength(poses[0], "right", "left", front);
  const double left_step = stepLength(poses[2], "left", "right", front);
  if (!(right_step > 0) && !(left_step > 0))
    throw std::invalid_argument(
        "gait cycle: the soles give no forward stride (s1 right step " +
        std::to_string(right_step) + " m, s3 left step " + std::to_string(left_step) +
        " m); s1 must lead with the right foot and s3 with the left (thesis 5.3), facing front");
  // One step backwards is one misfitted foot (e.g. a real trailing leg bent beyond the model's
  // range), not a walk in the wrong order: the other step stands in for it. The stride only sets
  // the walked v (eq 5.11); the poses' angles and lengths are kept as fitted.
  cycle.stride_length = right_step > 0 && left_step > 0 ? right_step + left_step
                                                        : 2 * std::max(right_step, left_step);
  // 5.8.2: speed = stride / number of poses; one cycle of 20 frames walks one stride.
  cycle.velocity = cycle.stride_length / kGaitCycleFrames * front;

  // Eq 5.13: lengths (and the radii and joint placements) are the mean of the four poses.
  SegmentLengths mean_lengths = SegmentLengths::Zero();
  for (const BodyModel& pose : poses) mean_lengths += pose.r / poses.size();
  const BodyShape mean_shape = meanShape(poses);

  cycle.frames.reserve(kGaitCycleFrames);
  for (int frame = 1; frame <= kGaitCycleFrames; ++frame) {
    // The representative pose alpha at or before this frame and the next one, beta (s4 -> s1).
    const int alpha = (frame - 1) / 5;
    const int beta = (alpha + 1) % 4;
    const BodyModel& from = poses[alpha];
    const BodyModel& to = poses[beta];
    const double t = double(frame - kRepresentativeFrames[alpha]) / 5.0;  // (f-a)/(b-a)
    BodyModel model;
    model.q = from.q + t * (to.q - from.q);  // eq 5.12
    model.r = mean_lengths;
    model.shape = mean_shape;
    // Eq 5.11: the root walks v per frame, on top of the fits' own sway between alpha and beta.
    model.p.head<3>() =
        from.p.head<3>() + t * (to.p.head<3>() - from.p.head<3>()) + (frame - 1) * cycle.velocity;
    // p's angles as q, the short way round (the heading may cross +-pi).
    for (int i = 3; i < 6; ++i)
      model.p[i] = from.p[i] + t * std::remainder(to.p[i] - from.p[i], 2 * kPi);
    cycle.frames.push_back(model);
  }
  return cycle;
}

}  // namespace body_gait_model
