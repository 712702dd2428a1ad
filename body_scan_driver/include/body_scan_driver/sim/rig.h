// A whole rig of virtual pairs (thesis ch. 4, DESIGN.md section 1): poles standing around the
// subject, each holding pairs stacked head to toe. Read from a rig file by the simulator, the
// ScanCoordinator and the tools alike (config/rigs/thesis_rig.yaml documents the format).
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
