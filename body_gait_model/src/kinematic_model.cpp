// Kinematic model of thesis 5.4: segment table, Table 5.2 bounds, forward kinematics and the
// tapered-cylinder distance.
#include <body_gait_model/kinematic_model.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;

const SegmentInfo kSegments[kSegmentCount] = {
    {"upper_torso", kWholeBody, true, false},
    {"neck", kUpperTorso, true, true},
    {"head", kNeck, true, false},
    {"right_upper_arm", kUpperTorso, false, false},
    {"right_lower_arm", kRightUpperArm, false, false},
    {"left_upper_arm", kUpperTorso, false, false},
    {"left_lower_arm", kLeftUpperArm, false, false},
    {"lower_torso", kWholeBody, false, false},
    {"right_upper_leg", kLowerTorso, false, false},
    {"right_lower_leg", kRightUpperLeg, false, false},
    {"left_upper_leg", kLowerTorso, false, false},
    {"left_lower_leg", kLeftUpperLeg, false, false},
};

// Table 5.2, X_r and Z_r columns (the Y_r column is zero for every segment: no twist).
JointLimits symmetric(double x, double z) { return {-x, x, -z, z}; }

void checkSegment(int segment) {
  if (segment < 0 || segment >= kSegmentCount)
    throw std::out_of_range("body model: segment index " + std::to_string(segment) +
                            " out of range [0, 11] (thesis part ID - 1)");
}

Eigen::Matrix3d jointRotation(double theta_x, double theta_z) {
  return (Eigen::AngleAxisd(theta_x, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(theta_z, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

Eigen::Isometry3d transform(const Eigen::Vector3d& translation,
                            const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity()) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = translation;
  return pose;
}

}  // namespace

const SegmentInfo& segmentInfo(int segment) {
  checkSegment(segment);
  return kSegments[segment];
}

JointLimits jointLimits(int segment) {
  checkSegment(segment);
  switch (segment) {
    case kUpperTorso:
    case kHead:
    case kLowerTorso:
      return symmetric(kPi / 2, kPi / 2);
    case kNeck:
      return symmetric(0, 0);
    case kRightUpperArm:
    case kLeftUpperArm:
    case kRightLowerLeg:
    case kLeftLowerLeg:
      return symmetric(kPi / 6, kPi / 18);
    case kRightLowerArm:
    case kLeftLowerArm:
    case kRightUpperLeg:
    case kLeftUpperLeg:
      return symmetric(kPi / 4, kPi / 18);
  }
  return symmetric(0, 0);
}

const JointLimitSet& thesisJointLimits() {
  static const JointLimitSet limits = [] {
    JointLimitSet table;
    for (int segment = 0; segment < kSegmentCount; ++segment) table[segment] = jointLimits(segment);
    return table;
  }();
  return limits;
}

const JointLimitSet& walkingJointLimits() {
  // Values and sources: config/body_fitter.yaml (joint_limits); degrees here.
  static const JointLimitSet limits = [] {
    auto degrees = [](double x_min, double x_max, double z_min, double z_max) {
      constexpr double k = kPi / 180;
      return JointLimits{k * x_min, k * x_max, k * z_min, k * z_max};
    };
    JointLimitSet table;
    table[kUpperTorso] = table[kHead] = degrees(-90, 90, -90, 90);
    table[kLowerTorso] = degrees(-90, 90, 0, 0);  // level across: see config/body_fitter.yaml
    table[kNeck] = degrees(0, 0, 0, 0);
    table[kRightUpperArm] = table[kLeftUpperArm] = degrees(-50, 50, -20, 20);
    table[kRightLowerArm] = table[kLeftLowerArm] = degrees(-90, 10, -30, 30);
    table[kRightUpperLeg] = table[kLeftUpperLeg] = degrees(-50, 35, -15, 15);
    table[kRightLowerLeg] = table[kLeftLowerLeg] = degrees(-10, 80, -10, 10);
    return table;
  }();
  return limits;
}

int jointAngleIndex(int segment) {
  checkSegment(segment);
  if (segment == kNeck) return -1;
  // q skips the neck (eq 5.2): parts 1, 3, 4, ..., 12.
  return segment == kUpperTorso ? 0 : 2 * (segment - 1);
}

double BodyModel::thetaX(int segment) const {
  const int index = jointAngleIndex(segment);
  return index < 0 ? 0.0 : q[index];
}

double BodyModel::thetaZ(int segment) const {
  const int index = jointAngleIndex(segment);
  return index < 0 ? 0.0 : q[index + 1];
}

void BodyModel::setJointAngles(int segment, double theta_x, double theta_z) {
  const int index = jointAngleIndex(segment);
  if (index < 0) {
    if (theta_x != 0 || theta_z != 0)
      throw std::invalid_argument("body model: the neck is fixed (thesis 5.4); its angles are 0");
    return;
  }
  q[index] = theta_x;
  q[index + 1] = theta_z;
}

BodyModel standingModel(double stature) {
  if (!(stature > 0))
    throw std::invalid_argument("body model: stature must be > 0 m, got " +
                                std::to_string(stature));
  const double h = stature;
  const double s = h / 1.75;  // radii of a 1.75 m adult, scaled
  BodyModel model;
  // Heights as fractions of stature (Drillis & Contini): waist (root) 0.58, neck base 0.83,
  // chin 0.87, shoulder 0.818, hip 0.53, crotch 0.47, knee 0.285.
  model.r << 0.25 * h, 0.04 * h, 0.13 * h, 0.186 * h, 0.254 * h, 0.186 * h, 0.254 * h, 0.11 * h,
      0.245 * h, 0.285 * h, 0.245 * h, 0.285 * h;
  const double proximal[kSegmentCount] = {0.15,  0.055, 0.09,  0.048, 0.043, 0.048,
                                          0.043, 0.155, 0.085, 0.055, 0.085, 0.055};
  const double distal[kSegmentCount] = {0.16, 0.055, 0.08,  0.04,  0.03,  0.04,
                                        0.03, 0.14,  0.055, 0.035, 0.055, 0.035};
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    model.shape.proximal_radius[segment] = proximal[segment] * s;
    model.shape.distal_radius[segment] = distal[segment] * s;
  }
  model.shape.shoulder_half_width = 0.10 * h;
  model.shape.shoulder_drop = 0.012 * h;
  model.shape.hip_half_width = 0.05 * h;
  model.shape.hip_rise = 0.06 * h;
  // 40 % of the pelvis's depth from the back (the fitter's hip_depth_fraction) on a round
  // lower torso.
  model.shape.hip_back = 0.2 * model.shape.distal_radius[kLowerTorso];
  model.p[2] = 0.58 * h;
  return model;
}

Eigen::Matrix3d wholeBodyRotation(const PoseVector& p) {
  // Columns: where X_m, Y_m, Z_m point in the world when all angles are zero.
  Eigen::Matrix3d upright;
  upright << 0, 0, 1,  //
      1, 0, 0,         //
      0, 1, 0;
  return upright * Eigen::AngleAxisd(p[4], Eigen::Vector3d::UnitY()).toRotationMatrix() *
         jointRotation(p[3], p[5]);
}

Eigen::Vector2d jointAnglesForDirection(const Eigen::Vector3d& direction, bool points_up) {
  const Eigen::Vector3d d = direction.normalized();
  // Rx(x) Rz(z) (0, +-1, 0) = +-(-sin z, cos z cos x, cos z sin x).
  if (points_up) return {std::atan2(d.z(), d.y()), -std::asin(std::clamp(d.x(), -1.0, 1.0))};
  return {std::atan2(-d.z(), -d.y()), std::asin(std::clamp(d.x(), -1.0, 1.0))};
}

PoseVector poseVectorFromFrame(const Eigen::Vector3d& origin, const Eigen::Matrix3d& rotation) {
  // rotation = upright * Ry(a) Rx(b) Rz(c); M = Ry Rx Rz has row 1 = (cb sc, cb cc, -sb) and
  // column 2 = (sa cb, -sb, ca cb).
  const Eigen::Matrix3d m = wholeBodyRotation(PoseVector::Zero()).transpose() * rotation;
  PoseVector p;
  p.head<3>() = origin;
  p[3] = std::asin(std::clamp(-m(1, 2), -1.0, 1.0));
  p[4] = std::atan2(m(0, 2), m(2, 2));
  p[5] = std::atan2(m(1, 0), m(1, 1));
  return p;
}

Eigen::Vector3d jointOffset(const BodyModel& model, int segment) {
  checkSegment(segment);
  const BodyShape& shape = model.shape;
  const SegmentLengths& r = model.r;
  // The parent's cylinder runs along +-Y of its frame.
  switch (segment) {
    case kNeck:
      return {0, r[kUpperTorso], 0};
    case kHead:
      return {0, r[kNeck], 0};
    case kRightUpperArm:
    case kLeftUpperArm: {
      const double side = segment == kLeftUpperArm ? 1.0 : -1.0;  // +X_m is the left
      return {side * shape.shoulder_half_width, r[kUpperTorso] - shape.shoulder_drop, 0};
    }
    case kRightUpperLeg:
    case kLeftUpperLeg: {
      const double side = segment == kLeftUpperLeg ? 1.0 : -1.0;
      return {side * shape.hip_half_width, -(r[kLowerTorso] - shape.hip_rise), -shape.hip_back};
    }
    case kRightLowerArm:
    case kLeftLowerArm:
    case kRightLowerLeg:
    case kLeftLowerLeg:
      return {0, -r[segment - 1], 0};
    default:
      return Eigen::Vector3d::Zero();  // the torso joints sit on the root
  }
}

PosedModel forwardKinematics(const BodyModel& model) {
  PosedModel posed;
  posed.whole_body = transform(model.p.head<3>(), wholeBodyRotation(model.p));
  // Parents precede children in the segment order except the lower-torso subtree, which only
  // depends on the root; one pass in index order is therefore enough.
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    const SegmentInfo& info = kSegments[segment];
    const Eigen::Isometry3d& parent =
        info.parent == kWholeBody ? posed.whole_body : posed.segments[info.parent].frame;
    PosedSegment& out = posed.segments[segment];
    out.frame = parent * transform(jointOffset(model, segment),
                                   jointRotation(model.thetaX(segment), model.thetaZ(segment)));
    const double direction = info.points_up ? 1.0 : -1.0;
    out.proximal = out.frame.translation();
    out.distal = out.frame * Eigen::Vector3d(0, direction * model.r[segment], 0);
    out.proximal_radius = model.shape.proximal_radius[segment];
    out.distal_radius = model.shape.distal_radius[segment];
  }
  return posed;
}

Eigen::Vector3d PosedModel::joint(const std::string& name) const {
  if (name == "waist") return whole_body.translation();
  if (name == "neck_base") return segments[kNeck].proximal;
  if (name == "head_base") return segments[kHead].proximal;
  if (name == "head_top") return segments[kHead].distal;
  for (const char* side : {"right", "left"}) {
    const std::string prefix = std::string(side) + "_";
    const bool left = prefix == "left_";
    const int upper_arm = left ? kLeftUpperArm : kRightUpperArm;
    const int upper_leg = left ? kLeftUpperLeg : kRightUpperLeg;
    if (name == prefix + "shoulder") return segments[upper_arm].proximal;
    if (name == prefix + "elbow") return segments[upper_arm + 1].proximal;
    if (name == prefix + "hand_tip") return segments[upper_arm + 1].distal;
    if (name == prefix + "hip") return segments[upper_leg].proximal;
    if (name == prefix + "knee") return segments[upper_leg + 1].proximal;
    if (name == prefix + "sole") return segments[upper_leg + 1].distal;
  }
  throw std::invalid_argument("body model: no joint named '" + name +
                              "'; use waist, neck_base, head_base, head_top or right_/left_ + "
                              "shoulder, elbow, hand_tip, hip, knee, sole");
}

bool withinJointLimits(const BodyModel& model, const JointLimitSet& table) {
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    const JointLimits& limits = table[segment];
    const double x = model.thetaX(segment), z = model.thetaZ(segment);
    if (x < limits.x_min || x > limits.x_max || z < limits.z_min || z > limits.z_max) return false;
  }
  return true;
}

BodyModel clampToJointLimits(BodyModel model, const JointLimitSet& table) {
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    if (segment == kNeck) continue;
    const JointLimits& limits = table[segment];
    model.setJointAngles(segment, std::clamp(model.thetaX(segment), limits.x_min, limits.x_max),
                         std::clamp(model.thetaZ(segment), limits.z_min, limits.z_max));
  }
  // Whole body (part 0): each angle within [-pi, pi], wrapped rather than clamped.
  for (int i = 3; i < 6; ++i) model.p[i] = std::remainder(model.p[i], 2 * kPi);
  return model;
}

std::vector<std::string> jointLimitsReached(const BodyModel& model, const JointLimitSet& table,
                                            double tolerance) {
  std::vector<std::string> reached;
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    if (segment == kNeck) continue;
    const JointLimits& limits = table[segment];
    for (const auto& [axis, angle, low, high] :
         {std::tuple{"theta_x", model.thetaX(segment), limits.x_min, limits.x_max},
          std::tuple{"theta_z", model.thetaZ(segment), limits.z_min, limits.z_max}}) {
      if (low == high) continue;  // a fixed axis is no limit reached
      for (const auto& [bound, name] : {std::pair{low, "min"}, std::pair{high, "max"}})
        if (std::abs(angle - bound) <= tolerance)
          reached.push_back(std::string(segmentInfo(segment).name) + " " + axis + " at its " +
                            name + " " + std::to_string(int(std::lround(bound * 180 / kPi))) +
                            " deg");
    }
  }
  return reached;
}

TaperedCylinder::TaperedCylinder(const Eigen::Vector3d& proximal, const Eigen::Vector3d& distal,
                                 double r0, double r1)
    : proximal_(proximal), r0_(r0), r1_(r1) {
  const Eigen::Vector3d axis = distal - proximal;
  length_ = axis.norm();
  if (length_ > 0) {
    unit_ = axis / length_;
    slope_ = (r1 - r0) / length_;
    inverse_profile_squared_ = 1.0 / (length_ * length_ + (r1 - r0) * (r1 - r0));
  }
}

double TaperedCylinder::distance(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d offset = point - proximal_;
  if (!(length_ > 0)) return offset.norm() - std::max(r0_, r1_);
  const double axial = offset.dot(unit_);
  const double radial = std::sqrt(std::max(offset.squaredNorm() - axial * axial, 0.0));
  // Nearest point of the profile segment (0, r0)-(length, r1) in the (axial, radial) plane.
  const double dr = r1_ - r0_, rx = radial - r0_;
  const double t = std::clamp((axial * length_ + rx * dr) * inverse_profile_squared_, 0.0, 1.0);
  const double ex = axial - t * length_, ey = rx - t * dr;
  const double distance = std::sqrt(ex * ex + ey * ey);
  const bool inside = axial >= 0 && axial <= length_ && radial < r0_ + slope_ * axial;
  return inside ? -distance : distance;
}

double taperedCylinderDistance(const Eigen::Vector3d& point, const Eigen::Vector3d& proximal,
                               const Eigen::Vector3d& distal, double r0, double r1) {
  return TaperedCylinder(proximal, distal, r0, r1).distance(point);
}

SegmentSurfaces segmentSurfaces(const PosedModel& posed) {
  SegmentSurfaces surfaces;
  for (int s = 0; s < kSegmentCount; ++s) surfaces[s] = TaperedCylinder(posed.segments[s]);
  return surfaces;
}

NearestSegment nearestSegment(const SegmentSurfaces& surfaces, const Eigen::Vector3d& point) {
  NearestSegment nearest{0, std::numeric_limits<double>::infinity()};
  for (int s = 0; s < kSegmentCount; ++s) {
    const double d = std::abs(surfaces[s].distance(point));
    if (d < nearest.distance) nearest = {s, d};
  }
  return nearest;
}

NearestSegment nearestSegment(const PosedModel& posed, const Eigen::Vector3d& point) {
  return nearestSegment(segmentSurfaces(posed), point);
}

}  // namespace body_gait_model
