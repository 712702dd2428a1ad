// What only a simulated pair can do, next to its PairDevice interface: change the scene in
// front of it, render the light of the rig's other pairs, and tell its true geometry. The
// PairDriver finds it with dynamic_cast; a real pair does not implement it.
#pragma once

#include <body_scan_driver/pair_model.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace body_scan_driver {

class SimulatorControl {
 public:
  virtual ~SimulatorControl() = default;
  // The calibration the pair was built with (its true geometry).
  virtual PairCalibration factoryCalibration() const = 0;
  // The camera's true pose in the world.
  virtual Eigen::Isometry3d factoryPose() const = 0;
  // Replaces the scene in front of the pair (scene file text). Throws std::runtime_error naming
  // the problem; the current scene then stays.
  virtual void replaceScene(const std::string& scene_yaml) = 0;
  // The other pairs that project at the same time as the next capture(s) (the coordinator's
  // timing group): their light is rendered into this pair's frames. Throws
  // std::invalid_argument for an id the pair's rig does not know.
  virtual void setActivePairs(const std::vector<std::string>& pair_ids) = 0;
};

}  // namespace body_scan_driver
