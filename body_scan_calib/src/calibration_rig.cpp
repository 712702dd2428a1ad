#include <body_scan_calib/calibration_rig.h>

#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

namespace body_scan_calib {
namespace {

// Full precision: the scene the driver parses must be the rig's scene to the last bit.
std::string yamlVector(const Eigen::Vector3d& v) {
  char text[96];
  std::snprintf(text, sizeof(text), "[%.17g, %.17g, %.17g]", v.x(), v.y(), v.z());
  return text;
}

std::string yamlNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

}  // namespace

std::string boardSceneYaml(const Checkerboard& board,
                           const Eigen::Isometry3d& board_center_in_camera,
                           const Eigen::Isometry3d& world_from_camera) {
  // The printed side faces the camera (normal = the board's -z). It is mounted on a larger white
  // panel 3 mm behind it: the light border a checker detector needs (only the board's own
  // pixels are lifted by the calibration).
  const Eigen::Isometry3d world_from_board = world_from_camera * board_center_in_camera;
  const Eigen::Vector3d normal = -world_from_board.linear().col(2);
  const double panel_half_extent = 0.5 * (board.inner_cols + 1) * board.square_size + 0.1;
  std::ostringstream yaml;
  yaml << "# reference board of the calibration rig (body_scan_calib calibration_capture.h)\n"
       << "objects:\n"
       << "  - type: checkerboard\n"
       << "    name: reference_board\n"
       << "    center: " << yamlVector(world_from_board.translation()) << "\n"
       << "    normal: " << yamlVector(normal) << "\n"
       << "    axis_u: " << yamlVector(world_from_board.linear().col(0)) << "\n"
       << "    cols: " << board.inner_cols + 1 << "\n"
       << "    rows: " << board.inner_rows + 1 << "\n"
       << "    square_size: " << yamlNumber(board.square_size) << "\n"
       << "    light_albedo: " << yamlNumber(rig::kBoardLightAlbedo) << "\n"
       << "    dark_albedo: " << yamlNumber(rig::kBoardDarkAlbedo) << "\n"
       << "  - type: plane\n"
       << "    name: board_panel\n"
       << "    point: " << yamlVector(world_from_board * Eigen::Vector3d(0, 0, 0.003)) << "\n"
       << "    normal: " << yamlVector(normal) << "\n"
       << "    albedo: " << yamlNumber(rig::kBoardLightAlbedo) << "\n"
       << "    color: [0.9, 0.9, 0.9]\n"
       << "    half_extent: " << yamlNumber(panel_half_extent) << "\n";
  return yaml.str();
}

std::string sphereSceneYaml(const std::vector<Eigen::Vector3d>& centers_in_camera, double radius,
                            const Eigen::Isometry3d& world_from_camera) {
  std::ostringstream yaml;
  yaml << "# evaluation spheres of the calibration rig (thesis sec. 3.4.2, Fig 3.7)\n"
       << "objects:\n";
  for (size_t i = 0; i < centers_in_camera.size(); ++i)
    yaml << "  - type: sphere\n"
         << "    name: sphere_" << i + 1 << "\n"
         << "    center: " << yamlVector(world_from_camera * centers_in_camera[i]) << "\n"
         << "    radius: " << yamlNumber(radius) << "\n"
         << "    albedo: 0.7\n"
         << "    color: [0.8, 0.8, 0.8]\n";
  return yaml.str();
}

std::vector<cv::Mat> averageCaptures(const std::vector<std::vector<cv::Mat>>& captures) {
  if (captures.empty()) throw std::invalid_argument("no captures to average");
  if (captures.size() == 1) return captures.front();
  const std::vector<cv::Mat>& first = captures.front();
  std::vector<cv::Mat> sums(first.size());
  for (size_t c = 0; c < captures.size(); ++c) {
    if (captures[c].size() != first.size())
      throw std::invalid_argument("capture " + std::to_string(c) + " has " +
                                  std::to_string(captures[c].size()) + " frames, capture 0 has " +
                                  std::to_string(first.size()) +
                                  ": repeated captures of one placement must use one pattern set");
    for (size_t f = 0; f < first.size(); ++f) {
      const cv::Mat& frame = captures[c][f];
      if (frame.size() != first[f].size() || frame.type() != CV_8UC1)
        throw std::invalid_argument("capture " + std::to_string(c) + " frame " + std::to_string(f) +
                                    " is not an 8-bit grey image of the first capture's size");
      if (sums[f].empty()) sums[f] = cv::Mat::zeros(frame.size(), CV_32F);
      cv::accumulate(frame, sums[f]);
    }
  }
  std::vector<cv::Mat> frames(sums.size());
  for (size_t f = 0; f < sums.size(); ++f)
    sums[f].convertTo(frames[f], CV_8U, 1.0 / static_cast<double>(captures.size()));
  return frames;
}

// Removes FOLDER/pose_NN and FOLDER/spheres (only the capture layout's own folders).
}  // namespace body_scan_calib

namespace body_scan_calib::rig {
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

std::shared_ptr<body_scan_driver::sim::Scene> boardScene(
    const Checkerboard& board, const Eigen::Isometry3d& board_center_in_camera,
    const Eigen::Isometry3d& world_from_camera) {
  return std::make_shared<body_scan_driver::sim::Scene>(body_scan_driver::sim::parseScene(
      boardSceneYaml(board, board_center_in_camera, world_from_camera)));
}

std::vector<Eigen::Vector3d> defaultSphereCenters() {
  return {{-0.30, -0.22, 1.00},
          {0.30, -0.22, 1.00},
          {0.0, 0.0, 0.95},
          {-0.30, 0.22, 1.00},
          {0.30, 0.22, 1.00}};
}

std::shared_ptr<body_scan_driver::sim::Scene> sphereScene(
    const std::vector<Eigen::Vector3d>& centers_in_camera, double radius,
    const Eigen::Isometry3d& world_from_camera) {
  return std::make_shared<body_scan_driver::sim::Scene>(body_scan_driver::sim::parseScene(
      sphereSceneYaml(centers_in_camera, radius, world_from_camera)));
}

std::vector<cv::Mat> captureAveraged(const body_scan_driver::sim::VirtualPair& pair, int exposures,
                                     uint32_t first_scan_id) {
  if (exposures < 1)
    throw std::invalid_argument("exposures must be >= 1 (got " + std::to_string(exposures) + ")");
  std::vector<std::vector<cv::Mat>> captures;
  for (int exposure = 0; exposure < exposures; ++exposure)
    captures.push_back(pair.render(first_scan_id + exposure).frames);
  return averageCaptures(captures);
}

}  // namespace body_scan_calib::rig
