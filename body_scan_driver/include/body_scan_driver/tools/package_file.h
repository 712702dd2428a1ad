// Default data files of tools: found in the ROS package that ships them (roslib's
// ros::package::getPath), never through a source path compiled in. Header-only; tools only.
#pragma once

#include <ros/package.h>

#include <stdexcept>
#include <string>

namespace body_scan_driver::tools {

// `relative` inside ROS package `package` (e.g. "config/bvh/cmu_joint_map.yaml"), the default of
// `option`; throws naming the option when the package cannot be found.
inline std::string packageFile(const std::string& package, const std::string& relative,
                               const std::string& option) {
  const std::string folder = ros::package::getPath(package);
  if (folder.empty())
    throw std::runtime_error("cannot find the ROS package " + package + " for the default of " +
                             option + ": source the workspace's setup.bash or pass " + option);
  return folder + "/" + relative;
}

}  // namespace body_scan_driver::tools
