// Loading the simulator's YAML files (scenes, pairs) with one clear error message.
#pragma once

#include <yaml-cpp/yaml.h>

#include <stdexcept>
#include <string>

namespace body_scan::sim {

// Throws std::runtime_error naming the kind of file, its path and the fix.
inline YAML::Node loadYamlFile(const std::string& path, const std::string& kind) {
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("cannot read " + kind + " file '" + path + "': " + e.what() +
                             " (check the path and the YAML syntax)");
  }
}

}  // namespace body_scan::sim
