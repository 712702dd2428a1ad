#include <body_scan_calib/calibration_rig.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace body_scan::calib::rig {
namespace {

Eigen::Isometry3d boardPose(double x, double y, double z, double tilt_x_deg, double tilt_y_deg) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  pose.linear() = (Eigen::AngleAxisd(tilt_x_deg * M_PI / 180, Eigen::Vector3d::UnitX()) *
                   Eigen::AngleAxisd(tilt_y_deg * M_PI / 180, Eigen::Vector3d::UnitY()))
                      .toRotationMatrix();
  return pose;
}

}  // namespace

std::vector<Eigen::Isometry3d> defaultBoardPoses() {
  return {boardPose(0.0, -0.06, 1.05, 18, 12),   boardPose(0.0, 0.07, 0.92, -15, -12),
          boardPose(0.02, -0.14, 1.30, 10, -18), boardPose(-0.02, 0.12, 1.00, -8, 20),
          boardPose(0.0, 0.0, 1.15, 0, 25),      boardPose(0.0, -0.20, 1.45, 12, 0),
          boardPose(0.0, 0.14, 0.88, -12, 5)};
}

std::shared_ptr<sim::Scene> boardScene(const ReferenceBoard& board,
                                       const Eigen::Isometry3d& board_center_in_camera,
                                       const Eigen::Isometry3d& world_from_camera) {
  const Eigen::Isometry3d world_from_board = world_from_camera * board_center_in_camera;
  auto scene = std::make_shared<sim::Scene>();
  // The board's printed side faces the camera: its normal is the board's -z.
  scene->add(std::make_unique<sim::CheckerboardPlane>(
      world_from_board.translation(), -world_from_board.linear().col(2),
      world_from_board.linear().col(0), board.inner_cols + 1, board.inner_rows + 1,
      board.square_size, board.light_albedo, board.dark_albedo));
  const Eigen::Vector3d wall_point = world_from_camera * Eigen::Vector3d(0, 0, 2.5);
  scene->add(std::make_unique<sim::Plane>(wall_point, -world_from_camera.linear().col(2),
                                          sim::Material{0.8, {0.9, 0.9, 0.9}}));
  return scene;
}

std::vector<Eigen::Vector3d> defaultSphereCenters() {
  return {{-0.24, -0.16, 1.00},
          {0.24, -0.16, 1.00},
          {0.0, 0.0, 0.95},
          {-0.24, 0.16, 1.00},
          {0.24, 0.16, 1.00}};
}

std::shared_ptr<sim::Scene> sphereScene(const std::vector<Eigen::Vector3d>& centers_in_camera,
                                        double radius, const Eigen::Isometry3d& world_from_camera) {
  auto scene = std::make_shared<sim::Scene>();
  for (const Eigen::Vector3d& center : centers_in_camera)
    scene->add(std::make_unique<sim::Sphere>(world_from_camera * center, radius,
                                             sim::Material{0.7, {0.8, 0.8, 0.8}}));
  return scene;
}

std::vector<cv::Mat> captureAveraged(const sim::VirtualPair& pair, int exposures,
                                     uint32_t first_scan_id) {
  if (exposures < 1)
    throw std::invalid_argument("exposures must be >= 1 (got " + std::to_string(exposures) + ")");
  std::vector<cv::Mat> sums;
  for (int exposure = 0; exposure < exposures; ++exposure) {
    const sim::RenderedPatternSet set = pair.render(first_scan_id + exposure);
    if (exposures == 1) return set.frames;
    sums.resize(set.frames.size());
    for (size_t f = 0; f < set.frames.size(); ++f) {
      if (sums[f].empty()) sums[f] = cv::Mat::zeros(set.frames[f].size(), CV_32F);
      cv::accumulate(set.frames[f], sums[f]);
    }
  }
  std::vector<cv::Mat> frames(sums.size());
  for (size_t f = 0; f < sums.size(); ++f) sums[f].convertTo(frames[f], CV_8U, 1.0 / exposures);
  return frames;
}

}  // namespace body_scan::calib::rig
