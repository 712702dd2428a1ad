#include <body_scan_calib/calibration_rig.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace body_scan::calib::rig {
namespace {

// Board centre (camera frame, metres), tilts about the camera's x and y axes and an in-plane
// roll (degrees). The roll keeps the checker edges off the pixel grid: edges along a pixel row
// alias coherently and bias the corners by up to half a pixel.
Eigen::Isometry3d boardPose(double x, double y, double z, double tilt_x_deg, double tilt_y_deg,
                            double roll_deg) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  pose.linear() = (Eigen::AngleAxisd(tilt_x_deg * M_PI / 180, Eigen::Vector3d::UnitX()) *
                   Eigen::AngleAxisd(tilt_y_deg * M_PI / 180, Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(roll_deg * M_PI / 180, Eigen::Vector3d::UnitZ()))
                      .toRotationMatrix();
  return pose;
}

}  // namespace

std::vector<Eigen::Isometry3d> defaultBoardPoses() {
  return {boardPose(0.0, -0.02, 1.00, 15, 10, 20), boardPose(0.0, 0.02, 1.00, -15, -10, -20),
          boardPose(0.03, -0.12, 1.25, 10, -15, 20), boardPose(-0.03, 0.10, 1.20, -10, 15, -20),
          boardPose(0.0, 0.0, 1.10, 0, 25, 20), boardPose(0.0, -0.20, 1.45, 10, 0, -20),
          boardPose(0.0, 0.18, 1.45, -10, 5, 20), boardPose(0.05, -0.05, 1.30, 20, 0, -15),
          boardPose(-0.05, 0.05, 0.97, -5, -20, 15), boardPose(0.0, 0.0, 0.85, -25, 10, 15),
          boardPose(0.0, 0.02, 0.88, -20, -15, -20),
          // Bottom image rows see stripes > 229 only nearer than ~0.95 m: the two boards at
          // 0.8 m give them 3 poses (calibrated range 55-229 -> 53-249), so the calibration
          // cylinder's bottom grid points (0.8-1 m away, where a pole's upper and lower pairs
          // overlap) triangulate with the estimated calibration; the three boards up at
          // 1.05-1.15 m add the top rows' stripes at that range.
          boardPose(0.0, -0.05, 1.05, -20, 5, 10), boardPose(0.02, -0.05, 1.10, 20, -5, -10),
          boardPose(0.0, 0.02, 0.80, 15, 10, 10), boardPose(0.0, 0.02, 0.80, -15, -10, -10),
          boardPose(0.0, -0.06, 1.15, 0, 15, 12)};
}

std::shared_ptr<sim::Scene> boardScene(const Checkerboard& board,
                                       const Eigen::Isometry3d& board_center_in_camera,
                                       const Eigen::Isometry3d& world_from_camera) {
  const Eigen::Isometry3d world_from_board = world_from_camera * board_center_in_camera;
  auto scene = std::make_shared<sim::Scene>();
  // The board's printed side faces the camera: its normal is the board's -z.
  scene->add(std::make_unique<sim::CheckerboardPlane>(
      world_from_board.translation(), -world_from_board.linear().col(2),
      world_from_board.linear().col(0), board.inner_cols + 1, board.inner_rows + 1,
      board.square_size, kBoardLightAlbedo, kBoardDarkAlbedo));
  // The board is mounted on a larger white panel 3 mm behind it: the light border a checker
  // detector needs (the board's own pixels are the only ones the calibration lifts).
  const double panel_half_extent = 0.5 * (board.inner_cols + 1) * board.square_size + 0.1;
  scene->add(std::make_unique<sim::Plane>(
      world_from_board * Eigen::Vector3d(0, 0, 0.003), -world_from_board.linear().col(2),
      sim::Material{kBoardLightAlbedo, {0.9, 0.9, 0.9}}, panel_half_extent));
  return scene;
}

std::vector<Eigen::Vector3d> defaultSphereCenters() {
  return {{-0.30, -0.22, 1.00},
          {0.30, -0.22, 1.00},
          {0.0, 0.0, 0.95},
          {-0.30, 0.22, 1.00},
          {0.30, 0.22, 1.00}};
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
