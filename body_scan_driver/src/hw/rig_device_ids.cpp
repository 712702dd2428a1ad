#include <body_scan_driver/hw/rig_device_ids.h>
#include <body_scan_driver/rig_layout.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "../yaml_file.h"

namespace body_scan_driver::hw {
namespace {

const std::vector<std::string> kDeviceKeys = {"camera_id",         "camera_serial",
                                              "projector_id",      "projector_serial",
                                              "projector_display", "projector_screen"};

template <typename T>
std::optional<T> optionalValue(const YAML::Node& device, const std::string& key,
                               const std::string& where) {
  if (!device[key]) return std::nullopt;
  try {
    return device[key].as<T>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(where + ": '" + key + "' has the wrong type");
  }
}

PairDeviceIds readDevice(const YAML::Node& device, const std::string& where) {
  requireKnownKeys(device, kDeviceKeys, where);
  PairDeviceIds ids;
  ids.camera_id = optionalValue<std::string>(device, "camera_id", where);
  ids.camera_serial = optionalValue<std::string>(device, "camera_serial", where);
  ids.projector_id = optionalValue<std::string>(device, "projector_id", where);
  ids.projector_serial = optionalValue<std::string>(device, "projector_serial", where);
  ids.projector_display = optionalValue<std::string>(device, "projector_display", where);
  ids.projector_screen = optionalValue<int>(device, "projector_screen", where);
  return ids;
}

}  // namespace

PairDeviceIds loadPairDeviceIds(const std::string& rig_file, const std::string& pair_id) {
  const RigLayout rig = loadRigLayout(rig_file);  // the one reader of the rig file's layout
  for (const RigPairLayout& pair : rig.pairs) {
    if (pair.pair_id != pair_id) continue;
    return !pair.device.IsNull()
               ? readDevice(pair.device, rig_file + ": pair " + pair_id + ", device")
               : PairDeviceIds{};
  }
  std::string ids;
  for (const std::string& id : rig.pairIds()) ids += (ids.empty() ? "" : ", ") + id;
  throw std::runtime_error("pair '" + pair_id + "' is not in rig file '" + rig_file +
                           "'; its pairs: " + ids);
}

}  // namespace body_scan_driver::hw
