#include <body_scan_driver/sim/virtual_pair.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <stdexcept>

#include "pair_sections.h"
#include "yaml_file.h"

namespace body_scan::sim {
namespace {

constexpr double kDegree = M_PI / 180.0;

void optionalVector(const YAML::Node& node, const char* key, Eigen::Vector3d& value,
                    const std::string& where) {
  std::vector<double> v;
  readList(node, key, 3, v, "[x, y, z]", where);
  if (!v.empty()) value = {v[0], v[1], v[2]};
}

}  // namespace

void readPairSections(const YAML::Node& root, const std::string& path, VirtualPairConfig& config) {
  requireKnownKeys(root["camera"],
                   {"width", "height", "alpha", "beta", "gamma", "u0", "v0", "k1", "k2"},
                   path + ": camera");
  requireKnownKeys(root["pattern"], {"bits", "inverse_frames"}, path + ": pattern");
  requireKnownKeys(root["sensor"],
                   {"noise_sigma", "blur_sigma", "ambient", "projector_level", "seed"},
                   path + ": sensor");
  requireKnownKeys(
      root["projector"],
      {"mirror_axis_point", "mirror_axis", "mirror_offset", "laser_origin", "laser_direction",
       "first_mirror_angle_deg", "last_mirror_angle_deg", "fan_half_angle_deg"},
      path + ": projector");

  const YAML::Node camera = root["camera"];
  const std::string camera_where = path + ": camera";
  PinholeCamera& c = config.camera;
  readOptional(camera, "width", c.width, camera_where);
  readOptional(camera, "height", c.height, camera_where);
  for (auto [key, field] : {std::pair{"alpha", &c.alpha},
                            {"beta", &c.beta},
                            {"gamma", &c.gamma},
                            {"u0", &c.u0},
                            {"v0", &c.v0},
                            {"k1", &c.k1},
                            {"k2", &c.k2}})
    readOptional(camera, key, *field, camera_where);
  if (c.width <= 0 || c.height <= 0 || c.alpha <= 0 || c.beta <= 0)
    throw std::runtime_error(camera_where + ": width, height, alpha and beta must be > 0");

  const YAML::Node pattern = root["pattern"];
  readOptional(pattern, "bits", config.bits, path + ": pattern");
  readOptional(pattern, "inverse_frames", config.inverse_frames, path + ": pattern");
  PatternLayout(config.bits, config.inverse_frames);  // validates the bit count

  const YAML::Node sensor = root["sensor"];
  const std::string sensor_where = path + ": sensor";
  SensorModel& s = config.sensor;
  readOptional(sensor, "noise_sigma", s.noise_sigma, sensor_where);
  readOptional(sensor, "blur_sigma", s.blur_sigma, sensor_where);
  readOptional(sensor, "ambient", s.ambient, sensor_where);
  readOptional(sensor, "projector_level", s.projector_level, sensor_where);
  readOptional(sensor, "seed", s.seed, sensor_where);

  const YAML::Node projector = root["projector"];
  const std::string projector_where = path + ": projector";
  SweptLaserProjector& p = config.projector;
  optionalVector(projector, "mirror_axis_point", p.mirror_axis_point, projector_where);
  optionalVector(projector, "mirror_axis", p.mirror_axis, projector_where);
  readOptional(projector, "mirror_offset", p.mirror_offset, projector_where);
  optionalVector(projector, "laser_origin", p.laser_origin, projector_where);
  optionalVector(projector, "laser_direction", p.laser_direction, projector_where);
  double first_deg = p.first_mirror_angle / kDegree, last_deg = p.last_mirror_angle / kDegree;
  double fan_deg = p.fan_half_angle / kDegree;
  readOptional(projector, "first_mirror_angle_deg", first_deg, projector_where);
  readOptional(projector, "last_mirror_angle_deg", last_deg, projector_where);
  readOptional(projector, "fan_half_angle_deg", fan_deg, projector_where);
  p.first_mirror_angle = first_deg * kDegree;
  p.last_mirror_angle = last_deg * kDegree;
  p.fan_half_angle = fan_deg * kDegree;
}

VirtualPairConfig loadVirtualPairConfig(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "pair");
  std::vector<std::string> accepted = kPairSections;
  accepted.insert(accepted.end(), {"pair_id", "pose"});
  requireKnownKeys(root, accepted, path);
  requireKnownKeys(root["pose"], {"position", "yaw_deg", "pitch_deg"}, path + ": pose");
  VirtualPairConfig config;
  readOptional(root, "pair_id", config.pair_id, path);
  readPairSections(root, path, config);

  const YAML::Node pose = root["pose"];
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw_deg = 0, pitch_deg = 0;
  optionalVector(pose, "position", position, path + ": pose");
  readOptional(pose, "yaw_deg", yaw_deg, path + ": pose");
  readOptional(pose, "pitch_deg", pitch_deg, path + ": pose");
  config.world_from_camera = cameraPose(position, yaw_deg * kDegree, pitch_deg * kDegree);

  return config;
}

}  // namespace body_scan::sim
