// The sections of a pair file that a rig's pair_defaults shares (camera, pattern, sensor,
// projector): one reader for both file kinds.
#pragma once

#include <body_scan_driver/sim/virtual_pair.h>
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

namespace body_scan::sim {

inline const std::vector<std::string> kPairSections = {"camera", "pattern", "sensor", "projector"};

// Reads the sections present in `map` over `config` (absent keys keep their value); throws
// std::runtime_error naming `where`, the section and the bad key. Other keys of `map` are the
// caller's to check.
void readPairSections(const YAML::Node& map, const std::string& where, VirtualPairConfig& config);

}  // namespace body_scan::sim
