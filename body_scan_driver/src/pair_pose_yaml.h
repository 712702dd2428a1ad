// The `pose:` map of a pair file (position, yaw_deg, pitch_deg), read in one place for the
// product (loadPairFilePose) and the simulator (sim::loadVirtualPairConfig).
#pragma once

#include <body_scan_driver/rig_layout.h>
#include <yaml-cpp/yaml.h>

#include <string>

namespace body_scan_driver {

// The pose of `pose` (a pair file's `pose:` map, `where` names it in errors); identity when the
// map is absent. Throws std::runtime_error naming `where` and the bad key.
Eigen::Isometry3d pairPoseFromYaml(const YAML::Node& pose, const std::string& where);

}  // namespace body_scan_driver
