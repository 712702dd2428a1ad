#include <body_scan_calib/sim/calibration_scenes.h>

#include <stdexcept>
#include <string>

namespace body_scan_calib::rig {

std::shared_ptr<body_scan_driver::sim::Scene> boardScene(
    const Checkerboard& board, const Eigen::Isometry3d& board_center_in_camera,
    const Eigen::Isometry3d& world_from_camera) {
  return std::make_shared<body_scan_driver::sim::Scene>(body_scan_driver::sim::parseScene(
      boardSceneYaml(board, board_center_in_camera, world_from_camera)));
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
