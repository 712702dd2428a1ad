// Publishes a simulated whole-body cloud (body_cloud_sampler: thesis-like rig, gait pose of
// 5.3) on body_scan/cloud in the world frame, latched and repeated every ~period seconds: the
// body fitter's demo input. Parameters: body_gait_model/README.md.
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <body_gait_model/ros/body_model_msg.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "publish_simulated_body");
  ros::NodeHandle nh, pnh("~");
  const int subject = pnh.param("subject", 1), pose = pnh.param("pose", 1);
  const double heading = pnh.param("heading", 0.4), period = pnh.param("period", 2.0);
  if (subject < 0 || subject > 20 || pose < 1 || pose > 4) {
    ROS_ERROR("~subject must be 0..20 and ~pose 1..4 (got %d, %d)", subject, pose);
    return 1;
  }
  auto spec = body_gait_model::eval::simulatedSubjects(subject + 1)[subject];
  spec.pose = body_gait_model::eval::gaitPose(pose, heading);
  body_gait_model::eval::ScanRig rig;
  rig.noise_sigma = 0.002;
  const auto body = body_gait_model::eval::sampleBody(spec, rig);
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>("body_scan/cloud", 1, true);
  std_msgs::Header header;
  header.frame_id = "world";
  ROS_INFO("simulated %s in gait pose %d: %zu points", spec.name.c_str(), pose, body.points.size());
  do {
    header.stamp = ros::Time::now();
    pub.publish(body_gait_model::cloudToMsg(body.points, header));
    ros::spinOnce();
  } while (period > 0 && ros::ok() && ros::Duration(period).sleep());
  if (period <= 0) ros::spin();  // latched: stay up for late subscribers
  return 0;
}
