#include <body_scan_driver/rig_layout.h>
#include <body_scan_driver/sim/rig.h>

#include <stdexcept>

#include "virtual_pair_keys.h"
#include "../yaml_file.h"

namespace body_scan_driver::sim {

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
  // The layout (ids, poses) is the product's reader's; the simulator adds pair_defaults and seeds.
  const YAML::Node root = loadYamlFile(path, "rig");
  VirtualPairConfig defaults;
  if (root.IsMap())
    if (const YAML::Node pair_defaults = root["pair_defaults"])
      applyPairKeys(pair_defaults, path + ": pair_defaults", defaults, /*allow_pose=*/false);
  const RigLayout layout = loadRigLayout(path);
  Rig rig;
  rig.name = layout.name;
  rig.poles = layout.poles;
  size_t next = 0;  // loadRigLayout keeps the file's order of pairs
  for (const YAML::Node& pole : root["poles"]) {
    for (const YAML::Node& pair : pole["pairs"]) {
      const RigPairLayout& pair_layout = layout.pairs.at(next++);
      VirtualPairConfig config = defaults;
      config.pair_id = pair_layout.pair_id;
      config.world_from_camera = pair_layout.world_from_camera;
      if (const YAML::Node seed = pair["seed"]) {
        try {
          config.sensor.seed = seed.as<uint32_t>();
        } catch (const YAML::Exception&) {
          throw std::runtime_error(path + ": pair " + config.pair_id +
                                   ": 'seed' has the wrong type");
        }
      }
      rig.pairs.push_back(std::move(config));
    }
  }
  return rig;
}

}  // namespace body_scan_driver::sim
