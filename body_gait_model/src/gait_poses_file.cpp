#include <body_gait_model/gait_poses_file.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <set>
#include <stdexcept>
#include <vector>

namespace body_gait {
namespace {

const std::set<std::string> kPoseKeys = {"p",
                                         "q",
                                         "r",
                                         "proximal_radius",
                                         "distal_radius",
                                         "shoulder_half_width",
                                         "shoulder_drop",
                                         "hip_half_width",
                                         "hip_rise"};

std::vector<double> numbers(const YAML::Node& node, size_t size, const std::string& where) {
  std::vector<double> values;
  try {
    values = node.as<std::vector<double>>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(where + " must be a list of " + std::to_string(size) + " numbers");
  }
  if (values.size() != size)
    throw std::runtime_error(where + " has " + std::to_string(values.size()) + " numbers, not " +
                             std::to_string(size));
  return values;
}

double number(const YAML::Node& node, const std::string& where) {
  try {
    return node.as<double>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(where + " must be a number");
  }
}

BodyModel readPose(const YAML::Node& node, const std::string& where) {
  if (!node.IsMap()) throw std::runtime_error(where + " must be a map with p, q, r");
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    if (!kPoseKeys.count(key)) {
      std::string known;
      for (const auto& name : kPoseKeys) known += (known.empty() ? "" : ", ") + name;
      throw std::runtime_error(where + ": unknown key '" + key + "'; known keys: " + known);
    }
  }
  for (const char* key : {"p", "q", "r"})
    if (!node[key]) throw std::runtime_error(where + " has no '" + key + "' (eqs 5.1-5.3)");
  BodyModel pose;
  const auto p = numbers(node["p"], 6, where + ".p");
  const auto q = numbers(node["q"], 22, where + ".q");
  const auto r = numbers(node["r"], 12, where + ".r");
  pose.p = Eigen::Map<const PoseVector>(p.data());
  pose.q = Eigen::Map<const JointAngles>(q.data());
  pose.r = Eigen::Map<const SegmentLengths>(r.data());
  // Default shape: a standard adult whose legs are this long (standingModel: legs 0.53 of H).
  const double legs = pose.r[kRightUpperLeg] + pose.r[kRightLowerLeg];
  if (!(legs > 0)) throw std::runtime_error(where + ".r: the leg lengths must be > 0 m");
  pose.shape = standingModel(legs / 0.53).shape;
  if (node["proximal_radius"]) {
    const auto radii = numbers(node["proximal_radius"], 12, where + ".proximal_radius");
    std::copy(radii.begin(), radii.end(), pose.shape.proximal_radius.begin());
  }
  if (node["distal_radius"]) {
    const auto radii = numbers(node["distal_radius"], 12, where + ".distal_radius");
    std::copy(radii.begin(), radii.end(), pose.shape.distal_radius.begin());
  }
  const std::pair<const char*, double BodyShape::*> placements[] = {
      {"shoulder_half_width", &BodyShape::shoulder_half_width},
      {"shoulder_drop", &BodyShape::shoulder_drop},
      {"hip_half_width", &BodyShape::hip_half_width},
      {"hip_rise", &BodyShape::hip_rise}};
  for (const auto& [key, field] : placements)
    if (node[key]) pose.shape.*field = number(node[key], where + "." + key);
  return pose;
}

template <typename Vector>
YAML::Node flow(const Vector& values) {
  YAML::Node node(YAML::NodeType::Sequence);
  for (const double v : values) node.push_back(v);
  node.SetStyle(YAML::EmitterStyle::Flow);
  return node;
}

}  // namespace

RepresentativePoses loadRepresentativePoses(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& error) {
    throw std::runtime_error("gait poses file '" + path + "' cannot be read (" + error.what() +
                             "); give a YAML file with 'poses:' (s1..s4, gait_poses_file.h)");
  }
  const YAML::Node poses = root["poses"];
  if (!poses || !poses.IsSequence() || poses.size() != 4)
    throw std::runtime_error(path +
                             ": 'poses' must be a list of exactly 4 poses (s1..s4 of "
                             "thesis 5.3), each with p, q, r");
  RepresentativePoses result;
  for (int i = 0; i < 4; ++i)
    result[i] = readPose(poses[i], path + ": pose s" + std::to_string(i + 1));
  return result;
}

void saveRepresentativePoses(const std::string& path, const RepresentativePoses& poses) {
  YAML::Node root;
  for (const BodyModel& pose : poses) {
    YAML::Node node;
    node["p"] = flow(pose.p);
    node["q"] = flow(pose.q);
    node["r"] = flow(pose.r);
    node["proximal_radius"] = flow(pose.shape.proximal_radius);
    node["distal_radius"] = flow(pose.shape.distal_radius);
    node["shoulder_half_width"] = pose.shape.shoulder_half_width;
    node["shoulder_drop"] = pose.shape.shoulder_drop;
    node["hip_half_width"] = pose.shape.hip_half_width;
    node["hip_rise"] = pose.shape.hip_rise;
    root["poses"].push_back(node);
  }
  std::ofstream file(path);
  if (!file) throw std::runtime_error("cannot write gait poses file '" + path + "'");
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << root;
  file << "# s1..s4 of thesis 5.3 (body_gait_model/gait_poses_file.h)\n" << out.c_str() << "\n";
  if (!file) throw std::runtime_error("writing gait poses file '" + path + "' failed");
}

}  // namespace body_gait
