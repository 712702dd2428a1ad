// One pole of the scanner in one process: a nodelet manager (it also serves load_nodelet to
// others) that loads the nodelets listed in ~nodelets ("NAME TYPE", NAME relative to the node's
// namespace, e.g. "pair_1/driver body_scan_driver/PairDriver"). With no loader processes there
// are no bonds to time out: a pole whose process died and was respawned has all its nodelets
// back at once.
#include <nodelet/loader.h>
#include <ros/ros.h>

#include <sstream>

int main(int argc, char** argv) {
  ros::init(argc, argv, "manager");
  nodelet::Loader loader;
  std::vector<std::string> nodelets;
  if (!ros::param::get("~nodelets", nodelets) || nodelets.empty()) {
    ROS_FATAL(
        "~nodelets is empty: list the pole's nodelets as \"NAME TYPE\" strings, e.g. "
        "\"pair_1/driver body_scan_driver/PairDriver\"");
    return 1;
  }
  const nodelet::V_string arguments(argv + 1, argv + argc);
  size_t loaded = 0;
  for (const std::string& entry : nodelets) {
    std::istringstream fields(entry);
    std::string name, type;
    if (!(fields >> name >> type)) {
      ROS_ERROR("~nodelets entry '%s' is not \"NAME TYPE\": skipped", entry.c_str());
      continue;
    }
    const std::string resolved = ros::names::append(ros::this_node::getNamespace(), name);
    // One bad entry (an unknown type) must not take the pole's other pairs down.
    if (loader.load(resolved, type, ros::names::getRemappings(), arguments))
      ++loaded;
    else
      ROS_ERROR("could not load nodelet %s of type %s (is its package built and exported?)",
                resolved.c_str(), type.c_str());
  }
  ROS_INFO("%zu of %zu nodelets loaded", loaded, nodelets.size());
  ros::spin();
  return 0;
}
