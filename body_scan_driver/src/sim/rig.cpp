#include <body_scan_driver/sim/rig.h>

#include <cmath>
#include <set>
#include <stdexcept>

#include "virtual_pair_keys.h"
#include "yaml_file.h"

namespace body_scan_driver::sim {
namespace {

constexpr double kDegree = M_PI / 180.0;

template <typename T>
T required(const YAML::Node& node, const char* key, const std::string& where) {
  if (!node[key]) throw std::runtime_error(where + ": '" + key + "' is missing");
  try {
    return node[key].as<T>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(where + ": '" + key + "' has the wrong type");
  }
}

template <typename T>
T optionalOr(const YAML::Node& node, const char* key, T fallback, const std::string& where) {
  return node[key] ? required<T>(node, key, where) : fallback;
}

}  // namespace

std::vector<std::string> Rig::pairIds() const {
  std::vector<std::string> ids;
  for (const VirtualPairConfig& config : pairs) ids.push_back(config.pair_id);
  return ids;
}

const VirtualPairConfig& Rig::pair(const std::string& pair_id) const {
  for (const VirtualPairConfig& config : pairs)
    if (config.pair_id == pair_id) return config;
  std::string ids;
  for (const std::string& id : pairIds()) ids += (ids.empty() ? "" : ", ") + id;
  throw std::invalid_argument("pair '" + pair_id + "' is not in rig '" + name +
                              "'; its pairs: " + ids);
}

Rig loadRig(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "rig");
  requireKnownKeys(root, {"name", "pair_defaults", "poles"}, path);
  Rig rig;
  rig.name = optionalOr<std::string>(root, "name", "rig", path);
  VirtualPairConfig defaults;
  if (const YAML::Node pair_defaults = root["pair_defaults"])
    applyPairKeys(pair_defaults, path + ": pair_defaults", defaults, /*allow_pose=*/false);

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
      // device: the real pair's ids, read by the usb backend (hw/rig_device_ids.h).
      requireKnownKeys(pair, {"name", "height", "pitch_deg", "yaw_offset_deg", "seed", "device"},
                       pair_where);
      VirtualPairConfig config = defaults;
      config.pair_id = pole_name + "/" + pair_name;
      if (!ids.insert(config.pair_id).second)
        throw std::runtime_error(pair_where + ": pair id '" + config.pair_id + "' repeats");
      const double height = required<double>(pair, "height", pair_where);
      if (!(height > 0 && height < 5))
        throw std::runtime_error(pair_where + ": 'height' must be in (0, 5) m");
      const double pitch_deg = optionalOr<double>(pair, "pitch_deg", 0.0, pair_where);
      const double yaw_deg =
          heading_deg + optionalOr<double>(pair, "yaw_offset_deg", 0.0, pair_where);
      config.sensor.seed = optionalOr<uint32_t>(pair, "seed", config.sensor.seed, pair_where);
      config.world_from_camera =
          cameraPose({xy[0], xy[1], height}, yaw_deg * kDegree, pitch_deg * kDegree);
      rig.pairs.push_back(std::move(config));
    }
  }
  return rig;
}

}  // namespace body_scan_driver::sim
