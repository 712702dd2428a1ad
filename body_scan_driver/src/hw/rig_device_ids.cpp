#include <body_scan_driver/hw/rig_device_ids.h>
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
  YAML::Node root;
  try {
    root = YAML::LoadFile(rig_file);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("cannot read rig file '" + rig_file + "': " + e.what() +
                             " (check the path and the YAML syntax)");
  }
  const YAML::Node poles = root["poles"];
  if (!poles || !poles.IsSequence())
    throw std::runtime_error(rig_file + ": 'poles' must be a list of poles");
  std::string ids;
  for (const YAML::Node& pole : poles) {
    const std::string pole_name = pole["name"] ? pole["name"].as<std::string>() : "";
    if (!pole["pairs"] || !pole["pairs"].IsSequence()) continue;
    for (const YAML::Node& pair : pole["pairs"]) {
      const std::string id = pole_name + "/" + (pair["name"] ? pair["name"].as<std::string>() : "");
      ids += (ids.empty() ? "" : ", ") + id;
      if (id != pair_id) continue;
      const YAML::Node device = pair["device"];
      return device ? readDevice(device, rig_file + ": pair " + id + ", device") : PairDeviceIds{};
    }
  }
  throw std::runtime_error("pair '" + pair_id + "' is not in rig file '" + rig_file +
                           "'; its pairs: " + ids);
}

}  // namespace body_scan_driver::hw
