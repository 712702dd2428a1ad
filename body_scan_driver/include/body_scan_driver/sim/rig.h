// A whole rig of virtual pairs (thesis ch. 4, DESIGN.md section 1): the rig file's layout
// (rig_layout.h: poles, pair ids, poses) with each pair's simulator model (pair_defaults, seed).
// Read by the simulator, the simulated scans and the evaluation (config/rigs/thesis_rig.yaml
// documents the format); the product reads the layout alone.
#pragma once

#include <body_scan_driver/sim/virtual_pair.h>

#include <string>
#include <vector>

namespace body_scan_driver::sim {

struct Rig {
  std::string name;
  std::vector<std::string> poles;        // in file order
  std::vector<VirtualPairConfig> pairs;  // pair_id "<pole>/<pair>", pole by pole, top pair first

  std::vector<std::string> pairIds() const;
  // Throws std::invalid_argument naming the id and the rig's ids when it is not in the rig.
  const VirtualPairConfig& pair(const std::string& pair_id) const;
};

// Throws std::runtime_error naming the file, the pole or pair and the bad key.
Rig loadRig(const std::string& path);

}  // namespace body_scan_driver::sim
