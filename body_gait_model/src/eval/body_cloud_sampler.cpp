// Ray-cast whole-body clouds from the simulator's Scene (tests and evaluation only).
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <body_scan_driver/sim/data_paths.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <stdexcept>
#include <tuple>

namespace body_gait_model::eval {

namespace sim = body_scan_driver::sim;

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;
}  // namespace

BodyKind parseBodyKind(const std::string& name) {
  if (name == "ellipsoid") return BodyKind::kEllipsoid;
  if (name == "mesh") return BodyKind::kMesh;
  throw std::invalid_argument("unknown body '" + name + "': use mesh or ellipsoid");
}

const char* bodyKindName(BodyKind kind) { return kind == BodyKind::kMesh ? "mesh" : "ellipsoid"; }

sim::MeshPersonSpec meshPersonOf(const sim::HumanBodySpec& spec) {
  const sim::Anthropometry& b = spec.body;
  const sim::Anthropometry standard = sim::Anthropometry::fromStature(b.stature);
  sim::MeshPersonSpec person;
  person.stature = std::clamp(b.stature, 1.45, 2.05);
  const bool female = b.hip_girth > 1.05 * b.chest_girth;
  person.gender = female ? 0 : 1;
  const double build = b.waist_girth / standard.waist_girth;
  person.bmi = std::clamp((female ? 21.0 : 22.0) * build * build, 17.0, female ? 23.5 : 28.0);
  person.age = 30;
  return person;
}

sim::HumanBodySpec addSimulatedBody(const sim::HumanBodySpec& spec, BodyKind kind,
                                    sim::Scene& scene) {
  if (kind == BodyKind::kEllipsoid) {
    sim::addHumanBody(spec, scene);
    return spec;
  }
  const sim::MeshPersonSpec person = meshPersonOf(spec);
  static std::mutex mutex;
  static std::map<std::tuple<double, double, double>, std::shared_ptr<const sim::MeshHumanRig>>
      rigs;
  std::shared_ptr<const sim::MeshHumanRig> rig;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    auto& cached = rigs[{person.stature, person.gender, person.bmi}];
    if (!cached) cached = sim::meshHumanRig(person, sim::meshHumanFiles());
    rig = cached;
  }
  sim::HumanBodySpec placed = spec;
  if (!placed.segment_frames) placed.body = rig->anthropometry();
  sim::addMeshHuman(*rig, placed, scene);
  return placed;
}

YAML::Node simulatedBodyToYaml(const sim::HumanBodySpec& spec, BodyKind kind) {
  const YAML::Node human = sim::humanBodyToYaml(spec);
  if (kind == BodyKind::kEllipsoid) return human;
  const sim::MeshPersonSpec person = meshPersonOf(spec);
  const sim::MeshHumanFiles files = sim::meshHumanFiles();
  YAML::Node mesh;
  mesh["type"] = "mesh_human";
  mesh["name"] = spec.name;
  mesh["stature"] = person.stature;
  mesh["gender"] = person.gender;
  mesh["age"] = person.age;
  mesh["bmi"] = person.bmi;
  mesh["muscle"] = person.muscle;
  mesh["african"] = person.african;
  mesh["asian"] = person.asian;
  mesh["caucasian"] = person.caucasian;
  for (const char* key : {"position", "pose", "materials"}) mesh[key] = human[key];
  mesh["model"] = files.model;
  mesh["retarget_map"] = files.retarget_map;
  return mesh;
}

SampledBody sampleBody(const sim::HumanBodySpec& spec, const ScanRig& rig) {
  if (rig.poles < 1 || rig.heights.empty() || rig.columns < 2 || rig.rows < 2)
    throw std::invalid_argument(
        "body cloud sampler: the rig needs >= 1 pole, >= 1 height and a ray grid of >= 2 x 2");
  sim::Scene scene;
  SampledBody body;
  body.spec = addSimulatedBody(spec, rig.body, scene);
  body.skeleton = scene.skeleton();
  for (const auto& surface : scene.surfaces()) body.surface_names.push_back(surface->name);

  std::mt19937 random(rig.seed);
  std::normal_distribution<double> noise(0.0, rig.noise_sigma);
  const double tan_h = std::tan(rig.horizontal_fov / 2), tan_v = std::tan(rig.vertical_fov / 2);
  const int heights = static_cast<int>(rig.heights.size());
  for (int pole = 0; pole < rig.poles; ++pole) {
    const double azimuth = rig.pole_angle + 2 * kPi * pole / rig.poles;
    const Eigen::Vector3d outward(std::cos(azimuth), std::sin(azimuth), 0);
    const Eigen::Vector3d forward = -outward;
    const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ());
    for (int level = 0; level < heights; ++level) {
      const int viewpoint = pole * heights + level;
      if (std::count(rig.missing_viewpoints.begin(), rig.missing_viewpoints.end(), viewpoint))
        continue;
      sim::Ray ray;
      ray.origin = Eigen::Vector3d(spec.position.x(), spec.position.y(), 0) +
                   rig.pole_distance * outward + Eigen::Vector3d(0, 0, rig.heights[level]);
      for (int row = 0; row < rig.rows; ++row) {
        const double v = tan_v * (1 - 2.0 * row / (rig.rows - 1));
        for (int column = 0; column < rig.columns; ++column) {
          const double u = tan_h * (2.0 * column / (rig.columns - 1) - 1);
          ray.direction = (forward + u * right + v * Eigen::Vector3d::UnitZ()).normalized();
          sim::Hit hit;
          if (!scene.intersect(ray, hit)) continue;
          const Eigen::Vector3d point = ray.origin + hit.distance * ray.direction;
          if (hit.surface->albedoAtHit(hit, point) < rig.min_albedo) continue;
          const double range_noise = rig.noise_sigma > 0 ? noise(random) : 0.0;
          body.points.push_back(point + range_noise * ray.direction);
          body.surface_of_point.push_back(hit.surface_index);
        }
      }
    }
  }
  return body;
}

sim::BodyPose gaitPose(int index, double heading) {
  if (index < 1 || index > 4)
    throw std::invalid_argument("gaitPose: index must be 1..4 (thesis 5.3), got " +
                                std::to_string(index));
  sim::BodyPose pose;
  pose.heading = heading;
  pose.left_shoulder_abduction = pose.right_shoulder_abduction = 8 * kDegree;
  pose.left_hip_abduction = pose.right_hip_abduction = 2 * kDegree;
  pose.left_elbow_flexion = pose.right_elbow_flexion = 10 * kDegree;
  // Poses 1 and 2 as described; 3 and 4 are their mirror images (left <-> right).
  const bool mirrored = index >= 3;
  double& front_hip = mirrored ? pose.left_hip_flexion : pose.right_hip_flexion;
  double& back_hip = mirrored ? pose.right_hip_flexion : pose.left_hip_flexion;
  double& front_knee = mirrored ? pose.left_knee_flexion : pose.right_knee_flexion;
  double& back_knee = mirrored ? pose.right_knee_flexion : pose.left_knee_flexion;
  double& front_shoulder = mirrored ? pose.right_shoulder_flexion : pose.left_shoulder_flexion;
  double& back_shoulder = mirrored ? pose.left_shoulder_flexion : pose.right_shoulder_flexion;
  double& front_elbow = mirrored ? pose.right_elbow_flexion : pose.left_elbow_flexion;
  if (index == 1 || index == 3) {  // heel strike: longest stride, arms swing opposite
    front_hip = 25 * kDegree;
    front_knee = 5 * kDegree;
    back_hip = -20 * kDegree;
    back_knee = 15 * kDegree;
    front_shoulder = 20 * kDegree;
    front_elbow = 25 * kDegree;
    back_shoulder = -20 * kDegree;
  } else {  // mid-stance: stance leg vertical, the other behind with the knee bent
    front_hip = 0;
    front_knee = 3 * kDegree;
    back_hip = -15 * kDegree;
    back_knee = 25 * kDegree;
  }
  return pose;
}

std::vector<sim::HumanBodySpec> simulatedSubjects(int count) {
  std::vector<sim::HumanBodySpec> subjects;
  std::mt19937 random(20261124);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < count; ++i) {
    sim::HumanBodySpec spec;
    spec.name = "subject_" + std::to_string(i);
    const double stature = 1.55 + 0.40 * (count > 1 ? double(i) / (count - 1) : 0.5);
    spec.body = sim::Anthropometry::fromStature(stature);
    // Girths +-15 %, limb proportions +-5 %: bodies differ beyond a scaled template.
    const double girth = 0.85 + 0.30 * unit(random);
    for (double* field : {&spec.body.chest_girth, &spec.body.waist_girth, &spec.body.hip_girth,
                          &spec.body.upper_arm_girth, &spec.body.forearm_girth,
                          &spec.body.thigh_girth, &spec.body.calf_girth, &spec.body.neck_girth})
      *field *= girth;
    const double arms = 0.95 + 0.10 * unit(random), legs = 0.95 + 0.10 * unit(random);
    spec.body.upper_arm_length *= arms;
    spec.body.forearm_length *= arms;
    spec.body.thigh_length *= legs;
    spec.body.shank_length *= legs;
    spec.position = Eigen::Vector3d(0.1 * (unit(random) - 0.5), 0.1 * (unit(random) - 0.5), 0);
    subjects.push_back(spec);
  }
  return subjects;
}

Eigen::Vector3d trueJoint(const SampledBody& body, const std::string& name) {
  for (const auto& joint : body.skeleton)
    if (joint.name == name) return joint.position;
  throw std::invalid_argument("true skeleton has no joint '" + name + "'");
}

}  // namespace body_gait_model::eval

namespace body_gait_model::eval {

FitErrors compareWithTruth(const BodyModel& model, const SampledBody& body) {
  const PosedModel posed = forwardKinematics(model);
  const sim::Anthropometry& b = body.spec.body;
  auto truth = [&](const std::string& name) { return trueJoint(body, name); };
  // The model's lower leg ends at the sole: ankle_height below the ankle along the shank.
  auto trueSole = [&](const std::string& side) {
    const Eigen::Vector3d knee = truth(side + "_knee"), ankle = truth(side + "_ankle");
    return Eigen::Vector3d(ankle + b.ankle_height * (ankle - knee).normalized());
  };
  const double heading = body.spec.pose.heading;
  const Eigen::Vector3d front(std::cos(heading), std::sin(heading), 0);
  const Eigen::Vector3d left(-std::sin(heading), std::cos(heading), 0);
  FitErrors errors;
  std::vector<Eigen::Vector3d> fitted_joints, true_joints;
  auto addJoint = [&](const std::string& name, const Eigen::Vector3d& true_position) {
    fitted_joints.push_back(posed.joint(name));
    true_joints.push_back(true_position);
    const Eigen::Vector3d offset = posed.joint(name) - true_position;
    errors.joint_error[name] = offset.norm();
    errors.joint_offset[name] = Eigen::Vector3d(offset.dot(front), offset.dot(left), offset.z());
  };
  for (const std::string side : {"left", "right"}) {
    for (const std::string joint : {"shoulder", "elbow", "hand_tip", "hip", "knee"})
      addJoint(side + "_" + joint, truth(side + "_" + joint));
    addJoint(side + "_sole", trueSole(side));
  }
  addJoint("head_top", truth("head_top"));

  auto swing = [&](const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
    const Eigen::Vector3d d = to - from;
    return std::atan2(d.dot(front), -d.z());  // forward swing from hanging straight down
  };
  const struct {
    const char* segment;
    const char* from;
    const char* to;
  } kLimbSegments[] = {{"upper_arm", "shoulder", "elbow"},
                       {"lower_arm", "elbow", "hand_tip"},
                       {"upper_leg", "hip", "knee"},
                       {"lower_leg", "knee", "sole"}};
  for (const std::string side : {"left", "right"}) {
    for (const auto& limb : kLimbSegments) {
      const std::string from = side + "_" + limb.from, to = side + "_" + limb.to;
      const Eigen::Vector3d true_from = truth(from);
      const Eigen::Vector3d true_to = std::string(limb.to) == "sole" ? trueSole(side) : truth(to);
      const double true_length = (true_to - true_from).norm();
      const double fitted_length = (posed.joint(to) - posed.joint(from)).norm();
      const std::string name = side + "_" + limb.segment;
      errors.segment_length_bias[name] = (fitted_length - true_length) / true_length;
      errors.segment_length_error[name] = std::abs(errors.segment_length_bias[name]);
      errors.swing_error[name] = std::abs(std::remainder(
          swing(posed.joint(from), posed.joint(to)) - swing(true_from, true_to), 2 * kPi));
    }
  }
  auto average = [](const std::map<std::string, double>& values) {
    double sum = 0;
    for (const auto& [name, value] : values) sum += value;
    return values.empty() ? 0.0 : sum / values.size();
  };
  errors.mean_joint_error = average(errors.joint_error);
  // Procrustes: the rigid motion (Kabsch) that best lays the fitted joints on the true ones.
  const Eigen::Matrix3Xd fitted_matrix =
      Eigen::Map<const Eigen::Matrix3Xd>(fitted_joints[0].data(), 3, fitted_joints.size());
  const Eigen::Matrix3Xd true_matrix =
      Eigen::Map<const Eigen::Matrix3Xd>(true_joints[0].data(), 3, true_joints.size());
  const Eigen::Matrix4d alignment = Eigen::umeyama(fitted_matrix, true_matrix, false);
  const Eigen::Matrix3Xd aligned = (alignment.topLeftCorner<3, 3>() * fitted_matrix).colwise() +
                                   alignment.topRightCorner<3, 1>();
  errors.procrustes_joint_error = (aligned - true_matrix).colwise().norm().mean();
  errors.mean_length_error = average(errors.segment_length_error);
  errors.mean_swing_error = average(errors.swing_error);
  const Eigen::Matrix3d rotation = posed.whole_body.linear();
  errors.front_right = rotation.col(2).dot(front) > std::cos(kPi / 4);
  errors.left_right = (posed.joint("left_hip") - posed.joint("right_hip")).dot(left) > 0 &&
                      (posed.joint("left_shoulder") - posed.joint("right_shoulder")).dot(left) > 0;
  return errors;
}

}  // namespace body_gait_model::eval
