// BVH motion -> the simulator's body: joint map, placement in the scanner, gait-pose picking.
#include <body_scan_driver/sim/bvh_body.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "../yaml_file.h"

namespace body_scan_driver::sim {

namespace {

// Which joint's BVH rotation orients each segment across its bone (BVH: a joint's rotation
// turns the bone to its child).
const std::pair<const char*, const char*> kSegmentJoint[] = {
    {"pelvis", "pelvis"},
    {"torso", "chest"},
    {"neck", "head"},
    {"left_upper_arm", "left_shoulder"},
    {"left_forearm", "left_elbow"},
    {"left_hand", "left_wrist"},
    {"left_thigh", "left_hip"},
    {"left_shank", "left_knee"},
    {"left_foot", "left_ankle"},
    {"right_upper_arm", "right_shoulder"},
    {"right_forearm", "right_elbow"},
    {"right_hand", "right_wrist"},
    {"right_thigh", "right_hip"},
    {"right_shank", "right_knee"},
    {"right_foot", "right_ankle"},
};
const char* const kRequiredEndSites[] = {"head_top", "left_toe", "right_toe", "left_hand_tip",
                                         "right_hand_tip"};

Eigen::Vector3d axisOf(const YAML::Node& node, const std::string& key, const std::string& where) {
  const std::string usage = "'" + key + "' must be one of +x -x +y -y +z -z";
  if (!node[key]) throw std::runtime_error(where + ": missing " + usage);
  std::string text = node[key].as<std::string>();
  double sign = 1;
  if (!text.empty() && (text[0] == '+' || text[0] == '-')) {
    sign = text[0] == '-' ? -1 : 1;
    text = text.substr(1);
  }
  if (text == "x") return sign * Eigen::Vector3d::UnitX();
  if (text == "y") return sign * Eigen::Vector3d::UnitY();
  if (text == "z") return sign * Eigen::Vector3d::UnitZ();
  throw std::runtime_error(where + ": " + usage + ", got '" + node[key].as<std::string>() + "'");
}

std::map<std::string, std::string> nameMap(const YAML::Node& node, const std::string& key,
                                           const std::string& where) {
  const YAML::Node map = node[key];
  if (!map || !map.IsMap())
    throw std::runtime_error(where + ": '" + key + "' must be a map of simulator name: BVH name");
  std::map<std::string, std::string> names;
  for (const auto& entry : map)
    names[entry.first.as<std::string>()] = entry.second.as<std::string>();
  return names;
}

}  // namespace

BvhJointMap bvhJointMapFromYaml(const YAML::Node& node, const std::string& where) {
  requireKnownKeys(node,
                   {"scheme", "unit_scale_m", "up_axis", "forward_axis", "joints", "end_sites",
                    "far_ends_from_body"},
                   where);
  BvhJointMap map;
  try {
    map.scheme = node["scheme"] ? node["scheme"].as<std::string>() : "";
    if (!node["unit_scale_m"]) throw std::runtime_error(where + ": missing 'unit_scale_m'");
    map.unit_scale = node["unit_scale_m"].as<double>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(where + ": 'scheme' must be a name and 'unit_scale_m' a number");
  }
  if (!(map.unit_scale > 0) || !std::isfinite(map.unit_scale))
    throw std::runtime_error(where + ": 'unit_scale_m' must be > 0 (metres per BVH unit)");
  const Eigen::Vector3d up = axisOf(node, "up_axis", where);
  const Eigen::Vector3d forward = axisOf(node, "forward_axis", where);
  if (std::abs(up.dot(forward)) > 0.5)
    throw std::runtime_error(where + ": 'up_axis' and 'forward_axis' must differ");
  map.to_world.row(0) = forward.transpose();
  map.to_world.row(1) = up.cross(forward).transpose();  // the subject's left
  map.to_world.row(2) = up.transpose();
  if (const YAML::Node far_ends = node["far_ends_from_body"]) {
    const std::string usage = where + ": 'far_ends_from_body' must be a list of hand_tip, head_top";
    if (!far_ends.IsSequence()) throw std::runtime_error(usage);
    for (const auto& item : far_ends) {
      const std::string name = item.as<std::string>();
      if (name == "hand_tip")
        map.hand_length_from_body = true;
      else if (name == "head_top")
        map.head_height_from_body = true;
      else
        throw std::runtime_error(usage + ", got '" + name + "'");
    }
  }
  map.joints = nameMap(node, "joints", where);
  map.end_sites = nameMap(node, "end_sites", where);
  for (const auto& [segment, joint] : kSegmentJoint)
    if (!map.joints.count(joint))
      throw std::runtime_error(where + ": 'joints' needs '" + std::string(joint) + "' (the " +
                               segment + " segment)");
  for (const char* site : kRequiredEndSites)
    if (!map.end_sites.count(site))
      throw std::runtime_error(where + ": 'end_sites' needs '" + std::string(site) + "'");
  return map;
}

BvhJointMap loadBvhJointMap(const std::string& path) {
  return bvhJointMapFromYaml(loadYamlFile(path, "BVH joint map"), "BVH joint map '" + path + "'");
}

BvhSubject::BvhSubject(BvhMotion motion, BvhJointMap map, std::string name)
    : motion_(std::move(motion)), map_(std::move(map)), name_(std::move(name)) {
  auto find = [&](const std::string& ours, const std::string& bvh) {
    const int index = motion_.jointIndex(bvh);
    if (index < 0)
      throw std::invalid_argument("BVH subject '" + name_ + "': the joint map (scheme '" +
                                  map_.scheme + "') maps '" + ours + "' to '" + bvh +
                                  "', which the motion does not have (use the map of its scheme)");
    return index;
  };
  for (const auto& [ours, bvh] : map_.joints) joint_index_[ours] = find(ours, bvh);
  for (const auto& [ours, bvh] : map_.end_sites) end_site_index_[ours] = find(ours, bvh);
}

std::map<std::string, Eigen::Vector3d> BvhSubject::joints(int frame) const {
  const BvhPose pose = poseBvhFrame(motion_, frame);
  const Eigen::Matrix3d scale = map_.unit_scale * map_.to_world;
  std::map<std::string, Eigen::Vector3d> joints;
  for (const auto& [ours, index] : joint_index_) joints[ours] = scale * pose.position[index];
  for (const auto& [ours, index] : end_site_index_) {
    const bool has_end = motion_.joints[index].has_end_site;
    joints[ours] = scale * (has_end ? pose.end_site[index] : pose.position[index]);
  }
  return joints;
}

SkeletonPose BvhSubject::skeleton(int frame, const Anthropometry& body) const {
  const BvhPose pose = poseBvhFrame(motion_, frame);
  SkeletonPose skeleton;
  skeleton.joints = joints(frame);
  auto& j = skeleton.joints;
  auto extend = [&](const std::string& far_end, const Eigen::Vector3d& from, double length) {
    j[far_end] = from + length * (j.at(far_end) - from).normalized();
  };
  if (map_.hand_length_from_body)
    for (const std::string side : {"left_", "right_"})
      extend(side + "hand_tip", j.at(side + "wrist"), body.hand_length);
  if (map_.head_height_from_body)
    extend("head_top", (j.at("left_shoulder") + j.at("right_shoulder")) / 2,
           body.neck_length + body.head_height);
  // A segment's rest orientation is the identity in simulator axes: W R W^T.
  for (const auto& [segment, joint] : kSegmentJoint)
    skeleton.orientations[segment] =
        map_.to_world * pose.rotation[joint_index_.at(joint)] * map_.to_world.transpose();
  return skeleton;
}

double BvhSubject::estimatedStature() const {
  const auto j = joints(0);
  double legs = 0;
  for (const std::string side : {"left_", "right_"})
    legs += 0.5 * ((j.at(side + "knee") - j.at(side + "hip")).norm() +
                   (j.at(side + "ankle") - j.at(side + "knee")).norm());
  return legs / (0.530 - 0.039);
}

HumanBodySpec BvhSubject::body(int frame) const {
  return body(frame, Anthropometry::fromStature(estimatedStature()));
}

HumanBodySpec BvhSubject::body(int frame, const Anthropometry& girths) const {
  SkeletonPose skeleton = this->skeleton(frame, girths);
  const auto& j = skeleton.joints;
  const Eigen::Vector3d hip_mid = (j.at("left_hip") + j.at("right_hip")) / 2;
  const Eigen::Vector3d left = j.at("left_hip") - j.at("right_hip");
  // Turn about z so the hip line's normal (the front) is +x; the pelvis over the origin; the
  // lower ankle ankle_height above the floor.
  const double heading = std::atan2(-left.x(), left.y());
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(-heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const double floor =
      std::min(j.at("left_ankle").z(), j.at("right_ankle").z()) - girths.ankle_height;
  const Eigen::Vector3d shift(hip_mid.x(), hip_mid.y(), floor);
  for (auto& [name, position] : skeleton.joints) position = turn * (position - shift);
  for (auto& [segment, orientation] : skeleton.orientations) orientation = turn * orientation;
  HumanBodySpec spec;
  spec.name = name_;
  spec.body = girths;
  spec.pose.heading = 0;
  spec.position = Eigen::Vector3d::Zero();
  poseBodyOnSkeleton(skeleton, spec);
  return spec;
}

BvhWalkFile parseBvhWalkFile(const std::string& item) {
  const std::size_t equals = item.find('=');
  BvhWalkFile walk;
  walk.file = equals == std::string::npos ? item : item.substr(equals + 1);
  walk.walk = std::filesystem::path(walk.file).stem().string();
  walk.person = equals == std::string::npos ? walk.walk.substr(0, walk.walk.find('_'))
                                            : item.substr(0, equals);
  return walk;
}

GaitPoseFrames pickGaitPoses(const BvhSubject& subject) {
  const int frames = subject.frameCount();
  const double dt = subject.motion().frame_time;
  const auto where = "gait poses of '" + subject.name() + "'";
  if (frames < 10) throw std::runtime_error(where + ": the clip has fewer than 10 frames");
  std::vector<std::map<std::string, Eigen::Vector3d>> joints(frames);
  for (int f = 0; f < frames; ++f) joints[f] = subject.joints(f);
  auto hipMid = [&](int f) {
    return Eigen::Vector3d((joints[f].at("left_hip") + joints[f].at("right_hip")) / 2);
  };
  Eigen::Vector3d walked = hipMid(frames - 1) - hipMid(0);
  walked.z() = 0;
  GaitPoseFrames result;
  result.walking_speed = walked.norm() / ((frames - 1) * dt);
  if (result.walking_speed < 0.2)
    throw std::runtime_error(where + ": the pelvis moves " + std::to_string(result.walking_speed) +
                             " m/s; not a walk");
  const Eigen::Vector3d direction = walked.normalized();

  // Per side (0 = right, 1 = left, in the order of the poses): planted frames, heel strikes and
  // mid-stances.
  std::vector<int> strikes[2], mid_stances[2];
  const char* const kSide[2] = {"right_", "left_"};
  for (int side = 0; side < 2; ++side) {
    const std::string ankle = std::string(kSide[side]) + "ankle";
    const std::string hip = std::string(kSide[side]) + "hip";
    std::vector<double> height(frames), speed(frames);
    for (int f = 0; f < frames; ++f) {
      height[f] = joints[f].at(ankle).z();
      // Central difference over +-2 frames: steadier than one frame at 120 fps.
      const int a = std::max(0, f - 2), b = std::min(frames - 1, f + 2);
      Eigen::Vector3d moved = joints[b].at(ankle) - joints[a].at(ankle);
      moved.z() = 0;
      speed[f] = moved.norm() / ((b - a) * dt);
    }
    std::vector<double> sorted = height;
    std::sort(sorted.begin(), sorted.end());
    const double stance_height = sorted[sorted.size() / 10];
    auto planted = [&](int f) {
      return height[f] < stance_height + 0.03 && speed[f] < 0.5 * result.walking_speed;
    };
    bool swung = false;
    for (int f = 1; f < frames; ++f) {
      if (speed[f] > result.walking_speed) swung = true;
      if (swung && planted(f) && !planted(f - 1)) {
        strikes[side].push_back(f);
        swung = false;
      }
    }
    for (int strike : strikes[side]) {
      for (int f = strike; f < frames; ++f) {
        if ((joints[f].at(ankle) - joints[f].at(hip)).dot(direction) <= 0) {
          mid_stances[side].push_back(f);
          break;
        }
      }
      if (mid_stances[side].size() < strikes[side].size()) mid_stances[side].push_back(-1);
    }
  }
  // The earliest complete set: a strike of `first` side, its mid-stance, then the next strike of
  // the other side and its mid-stance. Right first (poses 1, 2, 3, 4), else left first.
  for (int first = 0; first < 2; ++first) {
    const int second = 1 - first;
    for (size_t i = 0; i < strikes[first].size(); ++i) {
      if (mid_stances[first][i] < 0) continue;
      for (size_t k = 0; k < strikes[second].size(); ++k) {
        if (strikes[second][k] <= strikes[first][i] || mid_stances[second][k] < 0) continue;
        result.frame[2 * first] = strikes[first][i];
        result.frame[2 * first + 1] = mid_stances[first][i];
        result.frame[2 * second] = strikes[second][k];
        result.frame[2 * second + 1] = mid_stances[second][k];
        return result;
      }
    }
  }
  throw std::runtime_error(where + ": no heel strike and mid-stance of both feet in " +
                           std::to_string(frames) +
                           " frames (a walk needs about one gait cycle, ~1.1 s)");
}

void moveBody(HumanBodySpec& spec, double heading, const Eigen::Vector3d& position) {
  if (!spec.segment_frames)
    throw std::invalid_argument("moveBody: the body has no segment frames (use BvhSubject::body)");
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d shift(position.x(), position.y(), 0);
  const Eigen::Vector3d old_position = spec.position;
  auto move = [&](SegmentFrame& frame) {
    frame.origin = turn * (frame.origin - old_position) + shift;
    frame.rotation = turn * frame.rotation;
  };
  BodySegmentFrames& frames = *spec.segment_frames;
  for (SegmentFrame* frame : {&frames.pelvis, &frames.torso, &frames.neck}) move(*frame);
  for (int side = 0; side < 2; ++side)
    for (SegmentFrame* frame : {&frames.upper_arm[side], &frames.forearm[side], &frames.hand[side],
                                &frames.thigh[side], &frames.shank[side], &frames.foot[side]})
      move(*frame);
  spec.pose.heading += heading;
  spec.position = shift;
}

HumanBodySpec bvhHumanFromYaml(const YAML::Node& object, const std::string& where,
                               const std::string& base_dir,
                               const std::function<Anthropometry(double)>& body_for) {
  requireKnownKeys(object,
                   {"type", "name", "bvh", "joint_map", "frame", "gait_pose", "stature", "position",
                    "heading_deg", "materials"},
                   where);
  auto file = [&](const char* key) {
    if (!object[key])
      throw std::runtime_error(where + ": bvh_human needs '" + key + "' (a file name)");
    const std::filesystem::path path = object[key].as<std::string>();
    return (path.is_relative() && !base_dir.empty() ? std::filesystem::path(base_dir) / path : path)
        .string();
  };
  // name, stature, position, heading and materials as for a human (one reader of those keys).
  YAML::Node human(YAML::NodeType::Map);
  for (const char* key : {"name", "stature", "position", "heading_deg", "materials"})
    if (object[key]) human[key] = object[key];
  const HumanBodySpec looks = humanBodyFromYaml(human);
  const std::string name = object["name"] ? looks.name : "walker";
  HumanBodySpec spec;
  try {
    const BvhSubject subject(loadBvh(file("bvh")), loadBvhJointMap(file("joint_map")), name);
    if (object["frame"].IsDefined() == object["gait_pose"].IsDefined())
      throw std::runtime_error("give either 'frame' (1-based) or 'gait_pose' (1-4)");
    int frame = 0;
    if (object["frame"]) {
      frame = object["frame"].as<int>() - 1;
      if (frame < 0 || frame >= subject.frameCount())
        throw std::runtime_error("'frame' must be 1.." + std::to_string(subject.frameCount()));
    } else {
      const int pose = object["gait_pose"].as<int>();
      if (pose < 1 || pose > 4) throw std::runtime_error("'gait_pose' must be 1..4 (thesis 5.3)");
      frame = pickGaitPoses(subject).frame[pose - 1];
    }
    const Anthropometry body = body_for ? body_for(subject.estimatedStature())
                               : object["stature"]
                                   ? looks.body
                                   : Anthropometry::fromStature(subject.estimatedStature());
    spec = subject.body(frame, body);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(where + ": " + e.what());
  } catch (const std::exception& e) {
    throw std::runtime_error(where + ": " + e.what());
  }
  spec.name = name;
  spec.materials = looks.materials;
  moveBody(spec, looks.pose.heading, looks.position);
  return spec;
}

}  // namespace body_scan_driver::sim
