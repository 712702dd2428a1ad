// Runs the ScanCoordinator nodelet as a standalone node.
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "scan_coordinator");
  nodelet::Loader loader;
  nodelet::M_string remappings(ros::names::getRemappings());
  nodelet::V_string arguments(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), "body_scan_merge/ScanCoordinator", remappings,
                   arguments))
    return 1;
  ros::spin();
  return 0;
}
