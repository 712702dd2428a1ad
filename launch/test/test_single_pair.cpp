// Waits for the pair's cloud and counts the points on the person: in the world frame (via the
// tf the driver publishes), within 0.45 m of the person's vertical axis and above the floor.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Geometry>
#include <cmath>

TEST(SinglePair, PublishesACloudOfThePersonWithinTheTimeout) {
  ros::NodeHandle pnh("~");
  const std::string topic = pnh.param<std::string>("points_topic", "/pole_a/pair_1/points");
  const double timeout = pnh.param("timeout", 5.0);
  const int min_points = pnh.param("min_points_on_person", 50000);
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);

  const ros::WallTime start = ros::WallTime::now();
  const auto cloud =
      ros::topic::waitForMessage<sensor_msgs::PointCloud2>(topic, ros::Duration(timeout));
  ASSERT_TRUE(cloud) << "no cloud on " << topic << " within " << timeout << " s";
  std::cout << "[ figure ] first cloud after " << (ros::WallTime::now() - start).toSec() << " s\n";
  const auto transform =
      tf_buffer.lookupTransform("world", cloud->header.frame_id, ros::Time(0), ros::Duration(2.0));
  const auto& t = transform.transform;
  const Eigen::Isometry3d world_from_camera =
      Eigen::Translation3d(t.translation.x, t.translation.y, t.translation.z) *
      Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z);

  int valid = 0, on_person = 0;
  for (sensor_msgs::PointCloud2ConstIterator<float> it(*cloud, "x"); it != it.end(); ++it) {
    if (!std::isfinite(it[2])) continue;
    ++valid;
    const Eigen::Vector3d p = world_from_camera * Eigen::Vector3d(it[0], it[1], it[2]);
    on_person += std::hypot(p.x(), p.y()) < 0.45 && p.z() > 0.02;
  }
  std::cout << "[ figure ] " << valid << " valid points, " << on_person << " on the person\n";
  EXPECT_GE(on_person, min_points);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_single_pair");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
