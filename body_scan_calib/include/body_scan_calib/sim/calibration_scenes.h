// The calibration rig's targets (calibration_rig.h) rendered in-process by the virtual pair:
// the simulator side of calibrate_simulated_pair and of the tests (library body_scan_calib_sim,
// which links the simulator; product code never does).
#pragma once

#include <body_scan_calib/calibration_rig.h>
#include <body_scan_driver/sim/virtual_pair.h>

#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <vector>

namespace body_scan_calib::rig {

// A scene with the printed board at `board_center_in_camera` (board x along the pose's x, the
// board facing the camera), mounted on a larger white panel (the light border a checker detector
// needs around the board): boardSceneYaml parsed.
std::shared_ptr<body_scan_driver::sim::Scene> boardScene(
    const Checkerboard& board, const Eigen::Isometry3d& board_center_in_camera,
    const Eigen::Isometry3d& world_from_camera);

// The evaluation spheres (radius `radius`) at `centers_in_camera`: sphereSceneYaml parsed.
std::shared_ptr<body_scan_driver::sim::Scene> sphereScene(
    const std::vector<Eigen::Vector3d>& centers_in_camera, double radius,
    const Eigen::Isometry3d& world_from_camera);

// The capture protocol for static targets: `exposures` renders with independent sensor noise,
// averaged per pattern frame (noise down by sqrt(exposures)), rounded back to 8 bits.
std::vector<cv::Mat> captureAveraged(const body_scan_driver::sim::VirtualPair& pair, int exposures,
                                     uint32_t first_scan_id);

}  // namespace body_scan_calib::rig
