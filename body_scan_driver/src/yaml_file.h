// Reading the driver's YAML files (rigs, device maps, scenes, pairs) with clear error messages
// that name the file, the key and the fix. Private to the package's libraries.
#pragma once

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace body_scan_driver {

// Throws std::runtime_error naming the kind of file, its path and the fix.
inline YAML::Node loadYamlFile(const std::string& path, const std::string& kind) {
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("cannot read " + kind + " file '" + path + "': " + e.what() +
                             " (check the path and the YAML syntax)");
  }
}

// Throws std::runtime_error naming `where`, the unknown key and the accepted ones: a typo in a
// file must not be silently ignored. An absent map is fine (every key is optional).
inline void requireKnownKeys(const YAML::Node& map, const std::vector<std::string>& accepted,
                             const std::string& where) {
  if (!map) return;
  if (!map.IsMap()) throw std::runtime_error(where + " must be a map of key: value");
  for (const auto& entry : map) {
    const std::string key = entry.first.as<std::string>();
    if (std::find(accepted.begin(), accepted.end(), key) != accepted.end()) continue;
    std::string list;
    for (const std::string& name : accepted) list += (list.empty() ? "" : ", ") + name;
    throw std::runtime_error(where + ": unknown key '" + key + "'; accepted: " + list);
  }
}

// node[key] as T; throws naming `where` and the key when it is missing or of the wrong type.
template <typename T>
T required(const YAML::Node& node, const char* key, const std::string& where) {
  if (!node[key]) throw std::runtime_error(where + ": '" + key + "' is missing");
  try {
    return node[key].as<T>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(where + ": '" + key + "' has the wrong type");
  }
}

// node[key] as T, or `fallback` when the key is absent.
template <typename T>
T optionalOr(const YAML::Node& node, const char* key, T fallback, const std::string& where) {
  return node[key] ? required<T>(node, key, where) : fallback;
}

}  // namespace body_scan_driver
