// The capture side of the calibration workflow (issue 3 item 7): the targets of the rig
// (calibration_rig.h) as scene files for the simulated pair's ~set_scene service, averaging of
// repeated captures of a static target, and the image-folder layout calibrate_pair reads:
//   FOLDER/pose_NN/frame_MM.png    one folder per reference-plane pose (>= 3)
//   FOLDER/spheres/frame_MM.png    optional: the five evaluation spheres (sec. 3.4.2)
// with frames in PatternLayout order (capture_folder.h). ROS-agnostic.
#pragma once

#include <body_scan_calib/pair_calibration_pipeline.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace body_scan::calib {

// Scene-file text (body_scan_driver/config/scenes format) of the rig's board scene: the same
// surfaces as rig::boardScene (the printed board on its white panel), world frame.
std::string boardSceneYaml(const Checkerboard& board,
                           const Eigen::Isometry3d& board_center_in_camera,
                           const Eigen::Isometry3d& world_from_camera);
// Likewise for rig::sphereScene (the evaluation spheres).
std::string sphereSceneYaml(const std::vector<Eigen::Vector3d>& centers_in_camera, double radius,
                            const Eigen::Isometry3d& world_from_camera);

// Per-pattern mean of repeated captures of a static target (8-bit, rounded): sensor noise
// down by sqrt(count), the protocol of rig::captureAveraged. Throws std::invalid_argument if
// the captures are empty or differ in frame count, size or type.
std::vector<cv::Mat> averageCaptures(const std::vector<std::vector<cv::Mat>>& captures);

// The folder of the evaluation spheres beside the pose_NN folders (capture_folder.h writes
// and reads the frames: savePatternFrames, loadPatternFrames).
constexpr const char* kSphereFolderName = "spheres";

// Removes FOLDER/pose_NN and FOLDER/spheres, the layout's own folders, so that an earlier
// run's captures (more poses, spheres) are not read with a new run's. Returns how many.
int removeOldCaptures(const std::string& folder);

// Splits captures, in recording order, into the runs of consecutive scan ids (id = previous
// id + 1): one run per target placement; any other id starts the next placement. Returns the
// indices of each run.
std::vector<std::vector<size_t>> groupConsecutiveScanIds(const std::vector<uint32_t>& scan_ids);

}  // namespace body_scan::calib
