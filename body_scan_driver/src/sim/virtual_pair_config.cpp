#include <body_scan_driver/sim/virtual_pair.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <stdexcept>

#include "../pair_pose_yaml.h"
#include "../yaml_file.h"
#include "virtual_pair_keys.h"

namespace body_scan_driver::sim {
namespace {

constexpr double kDegree = M_PI / 180.0;

// Reads node[key] into value when present; a wrong type names the key.
template <typename T>
void optional(const YAML::Node& node, const char* key, T& value, const std::string& where) {
  if (!node || !node[key]) return;
  try {
    value = node[key].as<T>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(where + ": '" + key + "' has the wrong type");
  }
}

void optionalVector(const YAML::Node& node, const char* key, Eigen::Vector3d& value,
                    const std::string& where) {
  if (!node || !node[key]) return;
  std::vector<double> v;
  optional(node, key, v, where);
  if (v.size() != 3) throw std::runtime_error(where + ": '" + key + "' must be [x, y, z]");
  value = {v[0], v[1], v[2]};
}

}  // namespace

void applyPairKeys(const YAML::Node& root, const std::string& path, VirtualPairConfig& config,
                   bool allow_pose) {
  std::vector<std::string> keys = {"camera", "pattern", "sensor", "projector"};
  if (allow_pose) keys.insert(keys.end(), {"pair_id", "pose"});
  requireKnownKeys(root, keys, path);
  requireKnownKeys(root["camera"],
                   {"width", "height", "alpha", "beta", "gamma", "u0", "v0", "k1", "k2"},
                   path + ": camera");
  requireKnownKeys(root["pattern"], {"bits", "inverse_frames"}, path + ": pattern");
  requireKnownKeys(root["sensor"],
                   {"noise_sigma", "shot_noise_gain", "blur_sigma", "ambient", "bloom_share",
                    "bloom_sigma", "stray_light", "projector_level", "seed"},
                   path + ": sensor");
  requireKnownKeys(
      root["projector"],
      {"mirror_axis_point", "mirror_axis", "mirror_offset", "laser_origin", "laser_direction",
       "first_mirror_angle_deg", "last_mirror_angle_deg", "fan_half_angle_deg", "line_width"},
      path + ": projector");
  optional(root, "pair_id", config.pair_id, path);

  const YAML::Node camera = root["camera"];
  const std::string camera_where = path + ": camera";
  PinholeCamera& c = config.camera;
  optional(camera, "width", c.width, camera_where);
  optional(camera, "height", c.height, camera_where);
  for (auto [key, field] : {std::pair{"alpha", &c.alpha},
                            {"beta", &c.beta},
                            {"gamma", &c.gamma},
                            {"u0", &c.u0},
                            {"v0", &c.v0},
                            {"k1", &c.k1},
                            {"k2", &c.k2}})
    optional(camera, key, *field, camera_where);
  if (c.width <= 0 || c.height <= 0 || c.alpha <= 0 || c.beta <= 0)
    throw std::runtime_error(camera_where + ": width, height, alpha and beta must be > 0");

  if (const YAML::Node pose = root["pose"])
    config.world_from_camera = pairPoseFromYaml(pose, path + ": pose");

  const YAML::Node pattern = root["pattern"];
  optional(pattern, "bits", config.bits, path + ": pattern");
  optional(pattern, "inverse_frames", config.inverse_frames, path + ": pattern");
  PatternLayout(config.bits, config.inverse_frames);  // validates the bit count

  const YAML::Node sensor = root["sensor"];
  const std::string sensor_where = path + ": sensor";
  SensorModel& s = config.sensor;
  optional(sensor, "noise_sigma", s.noise_sigma, sensor_where);
  optional(sensor, "shot_noise_gain", s.shot_noise_gain, sensor_where);
  if (s.noise_sigma < 0 || s.shot_noise_gain < 0)
    throw std::runtime_error(sensor_where + ": noise_sigma and shot_noise_gain must be >= 0");
  optional(sensor, "blur_sigma", s.blur_sigma, sensor_where);
  optional(sensor, "ambient", s.ambient, sensor_where);
  optional(sensor, "bloom_share", s.bloom_share, sensor_where);
  optional(sensor, "bloom_sigma", s.bloom_sigma, sensor_where);
  optional(sensor, "stray_light", s.stray_light, sensor_where);
  if (s.bloom_share < 0 || s.bloom_share > 1 || s.bloom_sigma < 0 || s.stray_light < 0)
    throw std::runtime_error(sensor_where +
                             ": bloom_share must be in [0, 1], bloom_sigma and stray_light >= 0");
  optional(sensor, "projector_level", s.projector_level, sensor_where);
  optional(sensor, "seed", s.seed, sensor_where);

  const YAML::Node projector = root["projector"];
  const std::string projector_where = path + ": projector";
  SweptLaserProjector& p = config.projector;
  optionalVector(projector, "mirror_axis_point", p.mirror_axis_point, projector_where);
  optionalVector(projector, "mirror_axis", p.mirror_axis, projector_where);
  optional(projector, "mirror_offset", p.mirror_offset, projector_where);
  optionalVector(projector, "laser_origin", p.laser_origin, projector_where);
  optionalVector(projector, "laser_direction", p.laser_direction, projector_where);
  double first_deg = p.first_mirror_angle / kDegree, last_deg = p.last_mirror_angle / kDegree;
  double fan_deg = p.fan_half_angle / kDegree;
  optional(projector, "first_mirror_angle_deg", first_deg, projector_where);
  optional(projector, "last_mirror_angle_deg", last_deg, projector_where);
  optional(projector, "fan_half_angle_deg", fan_deg, projector_where);
  optional(projector, "line_width", p.line_width, projector_where);
  if (p.line_width < 0 || p.line_width > 3)
    throw std::runtime_error(projector_where + ": line_width must be in [0, 3] stripes");
  p.first_mirror_angle = first_deg * kDegree;
  p.last_mirror_angle = last_deg * kDegree;
  p.fan_half_angle = fan_deg * kDegree;
}

VirtualPairConfig loadVirtualPairConfig(const std::string& path) {
  VirtualPairConfig config;
  applyPairKeys(loadYamlFile(path, "pair"), path, config, /*allow_pose=*/true);
  return config;
}

}  // namespace body_scan_driver::sim
