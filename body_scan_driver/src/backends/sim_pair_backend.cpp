// backend:=sim: the virtual pair of ~rig_file (with the interference of the rig's other pairs)
// or of ~pair_file, in front of ~scene_file.
#include <body_scan_driver/ros/pair_backend.h>
#include <body_scan_driver/sim/simulated_pair_device.h>

#include <pluginlib/class_list_macros.hpp>

namespace body_scan_driver {

class SimPairBackend : public PairBackend {
 public:
  std::unique_ptr<PairDevice> open(ros::NodeHandle& /*nh*/, ros::NodeHandle& pnh,
                                   const std::string& pair_id) override {
    const std::string rig_file = pnh.param<std::string>("rig_file", "");
    const std::string scene_file = pnh.param<std::string>("scene_file", "");
    if (rig_file.empty())
      return sim::makeSimulatedPair(pnh.param<std::string>("pair_file", ""), scene_file);
    return sim::makeSimulatedRigPair(rig_file, pair_id, scene_file);
  }
};

}  // namespace body_scan_driver

PLUGINLIB_EXPORT_CLASS(body_scan_driver::SimPairBackend, body_scan_driver::PairBackend)
