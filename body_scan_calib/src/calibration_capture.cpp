#include <body_scan_calib/calibration_capture.h>
#include <body_scan_calib/calibration_rig.h>

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

namespace body_scan::calib {
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
  // Mirrors rig::boardScene (test_calibration_capture renders both and compares every pixel):
  // the printed side faces the camera (normal = the board's -z), the white panel 3 mm behind.
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
  // Mirrors rig::sphereScene.
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
int removeOldCaptures(const std::string& folder) {
  int removed = 0;
  std::error_code error;
  for (const std::filesystem::directory_entry& entry :
       std::filesystem::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    const bool pose = name.size() == 7 && name.rfind("pose_", 0) == 0 &&
                      std::isdigit(static_cast<unsigned char>(name[5])) &&
                      std::isdigit(static_cast<unsigned char>(name[6]));
    if (entry.is_directory() && (pose || name == calib::kSphereFolderName)) {
      std::filesystem::remove_all(entry.path());
      ++removed;
    }
  }
  return removed;
}

std::vector<std::vector<size_t>> groupConsecutiveScanIds(const std::vector<uint32_t>& scan_ids) {
  std::vector<std::vector<size_t>> groups;
  for (size_t i = 0; i < scan_ids.size(); ++i) {
    if (groups.empty() || scan_ids[i] != scan_ids[i - 1] + 1) groups.emplace_back();
    groups.back().push_back(i);
  }
  return groups;
}

}  // namespace body_scan::calib
