// The calibration and evaluation targets of a pair (DESIGN.md section 4): the printed reference
// board in its poses (sec. 3.3.2) and the five evaluation spheres (sec. 3.4.2, Fig 3.7), as
// scene-file text for the simulated pair's ~set_scene service, and the averaging of repeated
// captures. Everything is given in the pair's camera optical frame and converted to the world
// with the pair's pose. The scenes rendered in-process are sim/calibration_scenes.h.
#pragma once

#include <body_scan_calib/pair_calibration_pipeline.h>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace body_scan_calib {

// Scene-file text (body_scan_driver/config/scenes format) of the rig's board scene: the one
// definition of the rig's board scene (rig::boardScene, sim/calibration_scenes.h, parses it),
// world frame; also what the simulated pair's ~set_scene service receives.
std::string boardSceneYaml(const Checkerboard& board,
                           const Eigen::Isometry3d& board_center_in_camera,
                           const Eigen::Isometry3d& world_from_camera);
// Likewise for the evaluation spheres (rig::sphereScene).
std::string sphereSceneYaml(const std::vector<Eigen::Vector3d>& centers_in_camera, double radius,
                            const Eigen::Isometry3d& world_from_camera);

// Per-pattern mean of repeated captures of a static target (8-bit, rounded): sensor noise
// down by sqrt(count); rig::captureAveraged (sim/calibration_scenes.h) uses it. Throws
// std::invalid_argument if the captures are empty or differ in frame count, size or type.
std::vector<cv::Mat> averageCaptures(const std::vector<std::vector<cv::Mat>>& captures);

}  // namespace body_scan_calib

namespace body_scan_calib::rig {

// Poses (board centre, camera frame) that together see every stripe a 0.8-1.2 m scene needs on
// >= 3 poses (stripes 53-249 of the default pair: the spheres, the body, the calibration
// cylinder), tilted for a well-conditioned camera calibration, the whole board inside the image.
std::vector<Eigen::Isometry3d> defaultBoardPoses();

// How the reference board (pair_calibration_pipeline.h referenceBoard()) is printed: light and
// dark squares' albedos; the panel it is mounted on is as white as its light squares. Dark as
// black print on paper (3.5% of the light squares): with the real-capture optics
// (body_scan_driver's sim/virtual_pair.h) the finest bit's contrast on both colours is that of real
// captures.
constexpr double kBoardLightAlbedo = 0.85, kBoardDarkAlbedo = 0.03;

// Five spheres (radius 25 mm) about 1 m in front of the pair, numbered top left to bottom right
// (Fig 3.7), the outer four toward the image corners where the models differ most.
std::vector<Eigen::Vector3d> defaultSphereCenters();

}  // namespace body_scan_calib::rig
