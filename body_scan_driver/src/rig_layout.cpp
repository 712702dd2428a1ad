#include <body_scan_driver/rig_layout.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "pair_pose_yaml.h"
#include "yaml_file.h"

namespace body_scan_driver {
namespace {

constexpr double kDegree = M_PI / 180.0;

}  // namespace

std::vector<std::string> RigLayout::pairIds() const {
  std::vector<std::string> ids;
  for (const RigPairLayout& pair : pairs) ids.push_back(pair.pair_id);
  return ids;
}

const RigPairLayout& RigLayout::pair(const std::string& pair_id) const {
  for (const RigPairLayout& pair : pairs)
    if (pair.pair_id == pair_id) return pair;
  std::string ids;
  for (const std::string& id : pairIds()) ids += (ids.empty() ? "" : ", ") + id;
  throw std::invalid_argument("pair '" + pair_id + "' is not in rig '" + name +
                              "'; its pairs: " + ids);
}

RigLayout loadRigLayout(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "rig");
  requireKnownKeys(root, {"name", "pair_defaults", "poles"}, path);
  RigLayout rig;
  rig.name = optionalOr<std::string>(root, "name", "rig", path);
  const YAML::Node poles = root["poles"];
  if (!poles || !poles.IsSequence() || poles.size() == 0)
    throw std::runtime_error(path + ": 'poles' must be a non-empty list of poles");
  std::set<std::string> ids;
  for (const YAML::Node& pole : poles) {
    const std::string pole_name = required<std::string>(pole, "name", path + ": a pole");
    const std::string pole_where = path + ": pole " + pole_name;
    requireKnownKeys(pole, {"name", "position", "heading_deg", "pairs"}, pole_where);
    const auto xy = required<std::vector<double>>(pole, "position", pole_where);
    if (xy.size() != 2) throw std::runtime_error(pole_where + ": 'position' must be [x, y]");
    // By default the pole faces the subject's vertical axis (the world z axis).
    const double heading_deg =
        optionalOr<double>(pole, "heading_deg", std::atan2(-xy[1], -xy[0]) / kDegree, pole_where);
    const YAML::Node pairs = pole["pairs"];
    if (!pairs || !pairs.IsSequence() || pairs.size() == 0)
      throw std::runtime_error(pole_where + ": 'pairs' must be a non-empty list of pairs");
    rig.poles.push_back(pole_name);
    for (const YAML::Node& pair : pairs) {
      const std::string pair_name = required<std::string>(pair, "name", pole_where + ": a pair");
      const std::string pair_where = pole_where + ", pair " + pair_name;
      // seed: the simulator's sensor noise; device: the real pair's ids (hw/rig_device_ids.h).
      requireKnownKeys(pair, {"name", "height", "pitch_deg", "yaw_offset_deg", "seed", "device"},
                       pair_where);
      RigPairLayout layout;
      layout.pair_id = pole_name + "/" + pair_name;
      if (!ids.insert(layout.pair_id).second)
        throw std::runtime_error(pair_where + ": pair id '" + layout.pair_id + "' repeats");
      const double height = required<double>(pair, "height", pair_where);
      if (!(height > 0 && height < 5))
        throw std::runtime_error(pair_where + ": 'height' must be in (0, 5) m");
      const double pitch_deg = optionalOr<double>(pair, "pitch_deg", 0.0, pair_where);
      const double yaw_deg =
          heading_deg + optionalOr<double>(pair, "yaw_offset_deg", 0.0, pair_where);
      layout.world_from_camera =
          cameraPose({xy[0], xy[1], height}, yaw_deg * kDegree, pitch_deg * kDegree);
      if (const YAML::Node device = pair["device"]) layout.device = YAML::Clone(device);
      rig.pairs.push_back(std::move(layout));
    }
  }
  return rig;
}

Eigen::Isometry3d pairPoseFromYaml(const YAML::Node& pose, const std::string& where) {
  if (!pose) return Eigen::Isometry3d::Identity();
  requireKnownKeys(pose, {"position", "yaw_deg", "pitch_deg"}, where);
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  if (pose["position"]) {
    const auto xyz = required<std::vector<double>>(pose, "position", where);
    if (xyz.size() != 3) throw std::runtime_error(where + ": 'position' must be [x, y, z]");
    position = {xyz[0], xyz[1], xyz[2]};
  }
  const double yaw_deg = optionalOr<double>(pose, "yaw_deg", 0.0, where);
  const double pitch_deg = optionalOr<double>(pose, "pitch_deg", 0.0, where);
  return cameraPose(position, yaw_deg * kDegree, pitch_deg * kDegree);
}

Eigen::Isometry3d loadPairFilePose(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "pair");
  if (!root.IsMap()) throw std::runtime_error(path + " must be a map of key: value");
  return pairPoseFromYaml(root["pose"], path + ": pose");
}

Eigen::Isometry3d cameraPose(const Eigen::Vector3d& position, double yaw, double pitch) {
  const Eigen::Vector3d forward(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                                -std::sin(pitch));
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << right, down, forward;  // columns: optical x, y, z in the world
  pose.translation() = position;
  return pose;
}

}  // namespace body_scan_driver
