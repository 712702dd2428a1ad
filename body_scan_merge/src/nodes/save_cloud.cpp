// Saves the next PointCloud2 on a topic to a PLY file (and a PCD file) and exits (make demo).
//   rosrun body_scan_merge save_cloud _topic:=/body_scan/cloud _output:=cloud.ply
//       [_pcd_output:=cloud.pcd]
#include <body_scan_merge/ply_writer.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "save_cloud", ros::init_options::AnonymousName);
  ros::NodeHandle pnh("~");
  const std::string topic = pnh.param<std::string>("topic", "/pole_a/pair_1/points");
  const std::string output = pnh.param<std::string>("output", "cloud.ply");
  const std::string pcd_output = pnh.param<std::string>("pcd_output", "");
  const double timeout = pnh.param("timeout", 30.0);
  const auto cloud =
      ros::topic::waitForMessage<sensor_msgs::PointCloud2>(topic, ros::Duration(timeout));
  if (!cloud) {
    ROS_ERROR("no cloud on %s within %.0f s: is the scanner running?", topic.c_str(), timeout);
    return 1;
  }
  int rgb_offset = -1;
  bool xyz_float = cloud->fields.size() >= 3;
  for (size_t i = 0; i < cloud->fields.size(); ++i) {
    const auto& field = cloud->fields[i];
    if (i < 3) xyz_float &= field.offset == 4 * i && field.datatype == field.FLOAT32;
    if (field.name == "rgb") rgb_offset = static_cast<int>(field.offset / 4);
  }
  if (!xyz_float || cloud->point_step % 4 != 0) {
    ROS_ERROR("%s: expected float32 x, y, z as the first fields", topic.c_str());
    return 1;
  }
  try {
    const auto* points = reinterpret_cast<const float*>(cloud->data.data());
    const size_t count = static_cast<size_t>(cloud->width) * cloud->height;
    const size_t written =
        body_scan_merge::writePly(output, points, count, cloud->point_step / 4, rgb_offset);
    std::printf("%zu points (frame %s) written to %s\n", written, cloud->header.frame_id.c_str(),
                output.c_str());
    if (!pcd_output.empty()) {
      body_scan_merge::writePcd(pcd_output, points, count, cloud->point_step / 4, rgb_offset);
      std::printf("and to %s\n", pcd_output.c_str());
    }
  } catch (const std::exception& e) {
    ROS_ERROR("%s", e.what());
    return 1;
  }
  return 0;
}
