// The keys of a pair file, shared by pair files and rig files (whose pair_defaults hold them).
#pragma once

#include <body_scan_driver/sim/virtual_pair.h>
#include <yaml-cpp/yaml.h>

#include <string>

namespace body_scan_driver::sim {

// Applies the pair-file keys present in root (camera, pattern, sensor, projector; and pair_id,
// pose when allow_pose) over config. Throws std::runtime_error naming path and the bad key.
void applyPairKeys(const YAML::Node& root, const std::string& path, VirtualPairConfig& config,
                   bool allow_pose);

}  // namespace body_scan_driver::sim
