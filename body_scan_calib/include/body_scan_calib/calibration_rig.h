// The calibration and evaluation targets of a pair, placed in the virtual pair's scene (DESIGN.md
// section 4): the printed reference board in its poses (sec. 3.3.2) and the five evaluation
// spheres (sec. 3.4.2, Fig 3.7). Everything is given in the pair's camera optical frame and
// converted to the world with the pair's pose. Only the live CLI and tests use this file.
#pragma once

#include <body_scan_calib/pair_calibration_pipeline.h>
#include <body_scan_driver/sim/virtual_pair.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace body_scan_calib {

// Scene-file text (body_scan_driver/config/scenes format) of the rig's board scene: the one
// definition of the rig's board scene (rig::boardScene parses it), world frame; also what the
// simulated pair's ~set_scene service receives.
std::string boardSceneYaml(const Checkerboard& board,
                           const Eigen::Isometry3d& board_center_in_camera,
                           const Eigen::Isometry3d& world_from_camera);
// Likewise for the evaluation spheres (rig::sphereScene).
std::string sphereSceneYaml(const std::vector<Eigen::Vector3d>& centers_in_camera, double radius,
                            const Eigen::Isometry3d& world_from_camera);

// Per-pattern mean of repeated captures of a static target (8-bit, rounded): sensor noise
// down by sqrt(count); rig::captureAveraged uses it. Throws std::invalid_argument if
// the captures are empty or differ in frame count, size or type.
std::vector<cv::Mat> averageCaptures(const std::vector<std::vector<cv::Mat>>& captures);

}  // namespace body_scan_calib

namespace body_scan_calib::rig {

// Poses (board centre, camera frame) that together see every stripe a 0.8-1.2 m scene needs on
// >= 3 poses (stripes 53-249 of the default pair: the spheres, the body, the calibration
// cylinder), tilted for a well-conditioned camera calibration, the whole board inside the image.
std::vector<Eigen::Isometry3d> defaultBoardPoses();

// How the reference board (pair_calibration_pipeline.h referenceBoard()) is printed: light and
// dark squares' albedos; the panel it is mounted on is as white as its light squares.
constexpr double kBoardLightAlbedo = 0.85, kBoardDarkAlbedo = 0.3;

// A scene with the printed board at `board_center_in_camera` (board x along the pose's x, the
// board facing the camera), mounted on a larger white panel (the light border a checker detector
// needs around the board).
std::shared_ptr<body_scan_driver::sim::Scene> boardScene(
    const Checkerboard& board, const Eigen::Isometry3d& board_center_in_camera,
    const Eigen::Isometry3d& world_from_camera);

// Five spheres (radius 25 mm) about 1 m in front of the pair, numbered top left to bottom right
// (Fig 3.7), the outer four toward the image corners where the models differ most.
std::vector<Eigen::Vector3d> defaultSphereCenters();
std::shared_ptr<body_scan_driver::sim::Scene> sphereScene(
    const std::vector<Eigen::Vector3d>& centers_in_camera, double radius,
    const Eigen::Isometry3d& world_from_camera);

// The capture protocol for static targets: `exposures` renders with independent sensor noise,
// averaged per pattern frame (noise down by sqrt(exposures)), rounded back to 8 bits.
std::vector<cv::Mat> captureAveraged(const body_scan_driver::sim::VirtualPair& pair, int exposures,
                                     uint32_t first_scan_id);

}  // namespace body_scan_calib::rig
