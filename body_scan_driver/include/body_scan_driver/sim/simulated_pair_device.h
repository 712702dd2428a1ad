// The virtual pair behind the driver's interfaces: a PairDevice that is also a
// SimulatorControl (scene, interference of the rig's other pairs, true geometry).
#pragma once

#include <body_scan_driver/pair_device.h>
#include <body_scan_driver/simulator_control.h>

#include <memory>
#include <string>

namespace body_scan_driver::sim {

class SimulatedPairDevice : public PairDevice, public SimulatorControl {};

// The virtual pair: renders the scene file seen by the pair file's camera.
// Throws std::runtime_error naming the file and the problem.
std::unique_ptr<SimulatedPairDevice> makeSimulatedPair(const std::string& pair_file,
                                                       const std::string& scene_file);
// One pair of a simulated rig (rig.h): it knows every pair of the rig, so the light of the
// pairs named by setActivePairs() interferes with its frames. Throws std::runtime_error naming
// the file, or std::invalid_argument naming the pair id and the rig's ids.
std::unique_ptr<SimulatedPairDevice> makeSimulatedRigPair(const std::string& rig_file,
                                                          const std::string& pair_id,
                                                          const std::string& scene_file);

}  // namespace body_scan_driver::sim
