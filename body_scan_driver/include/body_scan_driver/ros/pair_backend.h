// A driver backend: a pluginlib plugin (base class of pair_backends.xml) that opens one pair
// for the PairDriver nodelet from its parameters. body_scan_driver/sim opens a virtual pair,
// body_scan_driver/usb a real one; the nodelet links neither and loads the one named by
// ~backend.
#pragma once

#include <body_scan_driver/pair_device.h>
#include <ros/node_handle.h>

#include <memory>
#include <string>

namespace body_scan_driver {

class PairBackend {
 public:
  virtual ~PairBackend() = default;
  // nh: the pair's namespace, pnh: the nodelet's private parameters. The device may keep
  // ROS objects of its own (timers, dynamic_reconfigure) until it is destroyed. Throws
  // std::exception naming the problem and the fix when the pair cannot be opened.
  virtual std::unique_ptr<PairDevice> open(ros::NodeHandle& nh, ros::NodeHandle& pnh,
                                           const std::string& pair_id) = 0;
};

}  // namespace body_scan_driver
