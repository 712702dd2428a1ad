// A simulated scanner rig: poles of projector-camera pairs placed around the subject (thesis
// ch. 4.2, Fig. 4.6: three poles of four pairs). The default is config/rigs/thesis_rig.yaml.
#pragma once

#include <body_scan_driver/sim/virtual_pair.h>

#include <string>
#include <vector>

namespace body_scan::sim {

struct Rig {
  std::string name;
  std::vector<VirtualPairConfig> pairs;  // pole by pole in file order, each pole's pair_1 first
  std::vector<std::string> poles;        // pole names in file order
  // The pair with id "<pole>/<pair>"; throws std::runtime_error naming the known ids.
  const VirtualPairConfig& pair(const std::string& pair_id) const;
};

// Reads a rig file. Format (every pair gets pair_defaults, then its pose and seed):
//   name: thesis_rig
//   pair_defaults:          # any sections of a pair file (camera, pattern, sensor, projector),
//     sensor: {noise_sigma: 2.0}   # applied to every pair; absent keys keep the pair defaults
//   poles:
//     - name: pole_a
//       position: [0.85, 0.6]    # world floor point of the pole (m)
//       heading_deg: -144.8      # direction its pairs look: yaw about world z, 0 = world +x
//       pairs:                   # top to bottom
//         - name: pair_1         # pair id "pole_a/pair_1"
//           height: 1.80         # camera height above the floor (m)
//           pitch_deg: 12        # > 0 looks down
//           yaw_offset_deg: 0    # optional, added to the pole's heading
//           seed: 11             # sensor noise seed of this pair
// Each pair's world_from_camera = cameraPose([x, y, height], heading + yaw_offset, pitch).
// Strict: an unknown or missing key, a wrong type or a duplicate name throws
// std::runtime_error naming the file and the key.
Rig loadRig(const std::string& path);

}  // namespace body_scan::sim
