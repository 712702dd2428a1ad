// Data files of tools and tests: found in the ROS package that ships them (roslib's
// ros::package::getPath), never through a source path compiled in. Header-only, so the libraries
// stay free of ROS: whoever includes it links roslib.
#pragma once

#include <ros/package.h>

#include <stdexcept>
#include <string>

namespace body_scan_driver::tools {

// The folder of ROS package `package` (source or install space); throws naming the package
// and how to make it findable (`fix`: e.g. " or pass --map").
inline std::string packageDir(const std::string& package, const std::string& fix = "") {
  const std::string folder = ros::package::getPath(package);
  if (folder.empty())
    throw std::runtime_error("cannot find the ROS package " + package +
                             ": source the workspace's setup.bash" + fix);
  return folder;
}

// `relative` inside ROS package `package` (e.g. "config/bvh/cmu_joint_map.yaml"), the default of
// `option`; throws naming the option when the package cannot be found.
inline std::string packageFile(const std::string& package, const std::string& relative,
                               const std::string& option) {
  return packageDir(package, " or pass " + option) + "/" + relative;
}

}  // namespace body_scan_driver::tools
