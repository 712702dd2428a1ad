#include <body_scan_calib/cylinder_target.h>
#include <body_scan_calib/world_alignment.h>
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/ros/conversions.h>
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/test_time_scale.h>
#include <body_scan_driver/tools/package_file.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <opencv2/imgproc.hpp>

using body_scan_driver::scaledSeconds;

using namespace body_scan_driver;
using namespace body_scan_calib;

namespace {

const std::string kAlignmentConfig =
    body_scan_driver::tools::packageDir("body_scan_calib") + "/config/alignment/";
const std::string kCylinderScene =
    body_scan_driver::sim::driverConfigDir() + "/scenes/calibration_cylinder.yaml";

Eigen::Isometry3d toEigen(const geometry_msgs::TransformStamped& message) {
  const auto& t = message.transform.translation;
  const auto& r = message.transform.rotation;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Quaterniond(r.w, r.x, r.y, r.z).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(t.x, t.y, t.z);
  return pose;
}

class WorldAlignmentNode : public testing::Test {
 protected:
  void SetUp() override {
    directory_ = ros::NodeHandle("~").param<std::string>("calibration_dir", "");
    ASSERT_FALSE(directory_.empty());
  }

  std::optional<Eigen::Isometry3d> lookup(const std::string& frame, double wait) {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(scaledSeconds(wait));
    while (ros::WallTime::now() < deadline) {
      try {
        return toEigen(buffer_.lookupTransform("world", frame, ros::Time(0)));
      } catch (const tf2::TransformException&) {
        ros::WallDuration(0.05).sleep();
      }
    }
    return std::nullopt;
  }

  std::string directory_;
  tf2_ros::Buffer buffer_;
  tf2_ros::TransformListener listener_{buffer_};
};

body_scan_driver::PairCalibration someCalibration(const std::string& pair_id) {
  body_scan_driver::PairCalibration calibration;
  calibration.pair_id = pair_id;
  calibration.projector.planes = {{0, 1, 0.1, 0.3}, {0, 1, 0.2, 0.3}};
  return calibration;
}

TEST_F(WorldAlignmentNode, PublishesAlignedPairsAndPicksUpNewFiles) {
  body_scan_driver::PairCalibration pair_a = someCalibration("test/pair_a");
  Eigen::Matrix<double, 3, 4> affine;
  affine << Eigen::AngleAxisd(2.5, Eigen::Vector3d(0.2, 0.3, 1).normalized()).toRotationMatrix() *
                Eigen::Vector3d(1.003, 0.998, 1.001).asDiagonal(),
      Eigen::Vector3d(0.9, 0.42, 1.15);
  pair_a.alignment = body_scan_driver::WorldAlignment::fromAffine(affine);
  saveCalibration(directory_ + "/test_pair_a.yaml", pair_a);
  saveCalibration(directory_ + "/test_pair_b.yaml", someCalibration("test/pair_b"));  // unaligned

  const auto published = lookup("test/pair_a_camera_optical_frame", 10.0);
  ASSERT_TRUE(published) << "no transform world -> test/pair_a_camera_optical_frame";
  EXPECT_LT((published->matrix() - pair_a.alignment->world_from_camera.matrix()).norm(), 1e-6);
  EXPECT_FALSE(lookup("test/pair_b_camera_optical_frame", 1.0)) << "unaligned pair published";

  // Aligning pair b while the node runs: published without a restart, pair a kept.
  body_scan_driver::PairCalibration pair_b = someCalibration("test/pair_b");
  pair_b.alignment = body_scan_driver::WorldAlignment::fromAffine(
      affine + Eigen::Matrix<double, 3, 4>::Constant(0.01));
  saveCalibration(directory_ + "/test_pair_b.yaml", pair_b);
  const auto published_b = lookup("test/pair_b_camera_optical_frame", 10.0);
  ASSERT_TRUE(published_b);
  EXPECT_LT((published_b->matrix() - pair_b.alignment->world_from_camera.matrix()).norm(), 1e-6);
  EXPECT_TRUE(lookup("test/pair_a_camera_optical_frame", 1.0));
}

// A pair whose calibration scales every range by 2% (a baseline measured 2% long): the
// cylinder alignment absorbs the scale in its residual linear part L, Triangulate applies L and
// the publisher's rigid part puts the cloud of a sphere on the true sphere in the world frame.
TEST_F(WorldAlignmentNode, AlignedCloudLandsOnTheTrueSurface) {
  body_scan_driver::sim::VirtualPairConfig config =
      body_scan_driver::sim::loadVirtualPairConfig(kAlignmentConfig + "pole_a_pair_1.yaml");
  config.pair_id = "test/aligned";
  const auto cylinder_scene = std::make_shared<body_scan_driver::sim::Scene>(
      body_scan_driver::sim::loadScene(kCylinderScene));
  const body_scan_driver::sim::VirtualPair cylinder_pair(config, cylinder_scene);
  body_scan_driver::PairCalibration calibration = cylinder_pair.factoryCalibration();
  constexpr double kScale = 1.02;
  for (Eigen::Vector4d& plane : calibration.projector.planes) plane[3] *= kScale;

  const body_scan_driver::sim::RenderedPatternSet cylinder = cylinder_pair.render(1);
  body_scan_driver::StripeImage stripes;
  body_scan_driver::StripeDecoder(cylinder_pair.layout()).decode(cylinder.frames, stripes);
  cv::Mat gray;
  cv::cvtColor(cylinder.texture, gray, cv::COLOR_RGB2GRAY);
  const body_scan_driver::CalibrationCylinderLayout layout;
  const CylinderObservation observation =
      observeCylinder(gray, stripes.coordinate, calibration, layout);
  std::vector<Eigen::Vector3d> camera, world;
  for (const TriangulatedGridPoint& point : observation.points) {
    camera.push_back(point.camera_point);
    world.push_back(cylinderGridPoint(layout, point.id));
  }
  const AffineFit fit = fitWorldAffine(camera, world);
  calibration.alignment = fit.alignment;
  EXPECT_NEAR(fit.alignment.residual_linear.determinant(), std::pow(1 / kScale, 3), 0.01);
  saveCalibration(directory_ + "/test_aligned.yaml", calibration);

  // A sphere in front of the pair (world frame = cylinder frame).
  const Eigen::Vector3d center(0, 0, 1.15);
  constexpr double kRadius = 0.15;
  auto sphere_scene = std::make_shared<body_scan_driver::sim::Scene>();
  sphere_scene->add(std::make_unique<body_scan_driver::sim::Sphere>(
      center, kRadius, body_scan_driver::sim::Material{}));
  const body_scan_driver::sim::VirtualPair sphere_pair(config, sphere_scene);
  const body_scan_driver::sim::RenderedPatternSet rendered = sphere_pair.render(2);
  std_msgs::Header header;
  header.frame_id = "test/aligned_camera_optical_frame";
  header.stamp = ros::Time::now();
  const body_scan_msgs::PatternSetPtr set =
      toPatternSet({rendered.frames, rendered.texture}, sphere_pair.layout(), config.camera, header,
                   config.pair_id, 2);

  ros::NodeHandle nh;
  std::mutex mutex;
  sensor_msgs::PointCloud2::ConstPtr cloud;
  ros::Subscriber subscriber = nh.subscribe<sensor_msgs::PointCloud2>(
      "aligned/points", 1, [&](const sensor_msgs::PointCloud2::ConstPtr& message) {
        std::lock_guard<std::mutex> lock(mutex);
        cloud = message;
      });
  ros::Publisher publisher = nh.advertise<body_scan_msgs::PatternSet>("aligned/pattern_set", 1);
  for (int i = 0; i < 100 && publisher.getNumSubscribers() == 0; ++i)
    ros::WallDuration(0.1).sleep();
  ASSERT_GT(publisher.getNumSubscribers(), 0u) << "Triangulate did not subscribe";
  const auto world_from_camera = lookup(header.frame_id, 10.0);
  ASSERT_TRUE(world_from_camera) << "the publisher did not announce the aligned pair";
  for (int i = 0; i < 200; ++i) {
    if (i % 50 == 0) publisher.publish(set);
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (cloud) break;
    }
    ros::WallDuration(0.05).sleep();
  }
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_TRUE(cloud) << "no cloud from Triangulate";
  const Eigen::Matrix3d undo_residual = fit.alignment.residual_linear.inverse();
  double aligned_error = 0, rigid_only_error = 0;
  long valid = 0;
  for (sensor_msgs::PointCloud2ConstIterator<float> it(*cloud, "x"); it != it.end(); ++it) {
    if (!std::isfinite(it[2])) continue;
    const Eigen::Vector3d point(it[0], it[1], it[2]);
    aligned_error += std::abs(((*world_from_camera * point) - center).norm() - kRadius);
    rigid_only_error +=
        std::abs(((*world_from_camera * (undo_residual * point)) - center).norm() - kRadius);
    ++valid;
  }
  ASSERT_GT(valid, 20000);
  std::printf(
      "[ figure ] aligned sphere cloud: %ld points, mean distance to the true surface %.3f mm "
      "aligned, %.3f mm "
      "with the rigid part alone\n",
      valid, 1000 * aligned_error / valid, 1000 * rigid_only_error / valid);
  EXPECT_LT(1000 * aligned_error / valid, 1.0);
  EXPECT_GT(1000 * rigid_only_error / valid, 5.0);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_world_alignment_node");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
