// The layout of a rig (thesis ch. 4, DESIGN.md section 1): poles standing around the subject,
// each holding pairs stacked head to toe, every pair with its id and nominal pose in the world.
// Read from a rig file (config/rigs/thesis_rig.yaml documents the format) by the product (the
// ScanCoordinator, plan_timing_groups) without the simulator; the simulator's loadRig
// (sim/rig.h) adds the virtual pairs' models to the same layout. Also the pose of a pair file.
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace body_scan_driver {

struct RigPairLayout {
  std::string pair_id;  // "<pole>/<pair>"
  Eigen::Isometry3d world_from_camera = Eigen::Isometry3d::Identity();
  YAML::Node device;  // the pair's `device:` map as written (null without one): the real
                      // pair's ids, checked and read by the usb backend (hw/rig_device_ids.h)
};

struct RigLayout {
  std::string name;
  std::vector<std::string> poles;    // in file order
  std::vector<RigPairLayout> pairs;  // pole by pole, top pair first (file order)

  std::vector<std::string> pairIds() const;
  // Throws std::invalid_argument naming the id and the rig's ids when it is not in the rig.
  const RigPairLayout& pair(const std::string& pair_id) const;
};

// Throws std::runtime_error naming the file, the pole or pair and the bad key. The keys of the
// simulator (pair_defaults, a pair's seed) and of the hardware (a pair's device map) are
// accepted and left to their readers.
RigLayout loadRigLayout(const std::string& path);

// The world pose of a pair file's pair (its `pose:` map: position, yaw_deg, pitch_deg;
// config/pairs/default_pair.yaml), identity without one: where the simulator places it. The
// other keys are the simulator's (sim::loadVirtualPairConfig checks them). Throws
// std::runtime_error naming the file and the bad key.
Eigen::Isometry3d loadPairFilePose(const std::string& path);

// Camera pose from a position and the heading of the optical axis (yaw about world z, 0 = +x;
// pitch > 0 looks down); image x stays horizontal.
Eigen::Isometry3d cameraPose(const Eigen::Vector3d& position, double yaw, double pitch);

}  // namespace body_scan_driver
