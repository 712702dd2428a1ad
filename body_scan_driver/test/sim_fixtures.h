// Scenes used by several tests: a pair at the world origin looking along +x.
#pragma once

#include <body_scan_driver/sim/virtual_pair.h>

#include <memory>

namespace body_scan_driver::test {

inline sim::VirtualPairConfig pairLookingAlongX(double noise_sigma = 2.0) {
  sim::VirtualPairConfig config;
  config.sensor.noise_sigma = noise_sigma;
  config.world_from_camera = sim::cameraPose({0, 0, 0}, 0, 0);
  return config;
}

// A matte plane facing the camera at `distance` metres.
inline std::shared_ptr<sim::Scene> planeScene(double distance, double albedo = 0.8) {
  auto scene = std::make_shared<sim::Scene>();
  scene->add(std::make_unique<sim::Plane>(Eigen::Vector3d(distance, 0, 0),
                                          Eigen::Vector3d(-1, 0, 0),
                                          sim::Material{albedo, {0.8, 0.8, 0.8}}));
  return scene;
}

}  // namespace body_scan_driver::test
