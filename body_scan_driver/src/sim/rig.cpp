#include <body_scan_driver/sim/rig.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <stdexcept>

#include "pair_sections.h"
#include "yaml_file.h"

namespace body_scan::sim {
namespace {

constexpr double kDegree = M_PI / 180.0;

// A name used in a pair id: non-empty, no '/'.
std::string readName(const YAML::Node& node, const std::string& where) {
  std::string name;
  readRequired(node, "name", name, where);
  if (name.empty() || name.find('/') != std::string::npos)
    throw std::runtime_error(where + ": 'name' must be non-empty and without '/'");
  return name;
}

// A non-empty list under node[key].
YAML::Node readSequence(const YAML::Node& node, const char* key, const std::string& where) {
  if (!node[key]) throw std::runtime_error(where + ": missing key '" + key + "'");
  const YAML::Node list = node[key];
  if (!list.IsSequence() || list.size() == 0)
    throw std::runtime_error(where + ": '" + key + "' must be a non-empty list");
  return list;
}

}  // namespace

const VirtualPairConfig& Rig::pair(const std::string& pair_id) const {
  std::string known;
  for (const VirtualPairConfig& config : pairs) {
    if (config.pair_id == pair_id) return config;
    known += (known.empty() ? "" : ", ") + config.pair_id;
  }
  throw std::runtime_error("rig '" + name + "' has no pair '" + pair_id + "'; known: " + known);
}

Rig loadRig(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "rig");
  if (!root.IsMap()) throw std::runtime_error(path + ": a rig file must be a map of key: value");
  requireKnownKeys(root, {"name", "pair_defaults", "poles"}, path);
  Rig rig;
  readRequired(root, "name", rig.name, path);

  VirtualPairConfig defaults;
  const YAML::Node pair_defaults = root["pair_defaults"];
  const std::string defaults_where = path + ": pair_defaults";
  if (pair_defaults) {  // (an absent key is an invalid node: no operator[] on it)
    requireKnownKeys(pair_defaults, kPairSections, defaults_where);
    readPairSections(pair_defaults, defaults_where, defaults);
  }

  std::set<std::string> pair_ids;
  const YAML::Node poles = readSequence(root, "poles", path);
  for (size_t i = 0; i < poles.size(); ++i) {
    const YAML::Node pole = poles[i];
    std::string where = path + ": poles[" + std::to_string(i) + "]";
    requireKnownKeys(pole, {"name", "position", "heading_deg", "pairs"}, where);
    const std::string pole_name = readName(pole, where);
    where += " (" + pole_name + ")";
    for (const std::string& other : rig.poles)
      if (other == pole_name) throw std::runtime_error(where + ": duplicate pole name");
    rig.poles.push_back(pole_name);
    std::vector<double> position;
    if (!pole["position"]) throw std::runtime_error(where + ": missing key 'position'");
    readList(pole, "position", 2, position, "[x, y] (floor point, m)", where);
    double heading_deg = 0;
    readRequired(pole, "heading_deg", heading_deg, where);

    const YAML::Node pairs = readSequence(pole, "pairs", where);
    for (size_t j = 0; j < pairs.size(); ++j) {
      const YAML::Node pair = pairs[j];
      std::string pair_where = where + ": pairs[" + std::to_string(j) + "]";
      requireKnownKeys(pair, {"name", "height", "pitch_deg", "yaw_offset_deg", "seed"}, pair_where);
      VirtualPairConfig config = defaults;
      config.pair_id = pole_name + "/" + readName(pair, pair_where);
      pair_where += " (" + config.pair_id + ")";
      if (!pair_ids.insert(config.pair_id).second)
        throw std::runtime_error(pair_where + ": duplicate pair name");
      double height = 0, pitch_deg = 0, yaw_offset_deg = 0;
      readRequired(pair, "height", height, pair_where);
      readRequired(pair, "pitch_deg", pitch_deg, pair_where);
      readOptional(pair, "yaw_offset_deg", yaw_offset_deg, pair_where);
      readRequired(pair, "seed", config.sensor.seed, pair_where);
      if (!(height > 0)) throw std::runtime_error(pair_where + ": 'height' must be > 0 (m)");
      if (!(std::abs(pitch_deg) < 90))
        throw std::runtime_error(pair_where + ": 'pitch_deg' must be within (-90, 90)");
      config.world_from_camera =
          cameraPose({position[0], position[1], height}, (heading_deg + yaw_offset_deg) * kDegree,
                     pitch_deg * kDegree);
      rig.pairs.push_back(std::move(config));
    }
  }
  return rig;
}

}  // namespace body_scan::sim
