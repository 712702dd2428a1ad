// Which hardware a pair of a rig is: the optional `device:` map of a pair in a rig file
// (config/rigs/thesis_rig.yaml documents the format), found through the rig layout
// (rig_layout.h), not the simulator; the node's private parameters override every id.
#pragma once

#include <optional>
#include <string>

namespace body_scan_driver::hw {

struct PairDeviceIds {
  std::optional<std::string> camera_id;  // vendor:product in hex
  std::optional<std::string> camera_serial;
  std::optional<std::string> projector_id;  // a vendor projector's vendor:product
  std::optional<std::string> projector_serial;
  std::optional<std::string> projector_display;  // X display, e.g. ":0"
  std::optional<int> projector_screen;           // X screen of that display
};

// The device ids of pair `pair_id` ("<pole>/<pair>"); all empty when the pair has no `device:`
// map. Throws std::runtime_error naming the file and the problem: unreadable, the pair not in
// the rig (with the rig's ids), an unknown key (with the known ones) or a wrong type.
PairDeviceIds loadPairDeviceIds(const std::string& rig_file, const std::string& pair_id);

}  // namespace body_scan_driver::hw
