// The capture side of the calibration workflow: the targets of the rig
// (calibration_rig.h) as scene files for the simulated pair's ~set_scene service, averaging of
// repeated captures of a static target, and the image-folder layout calibrate_pair reads:
//   FOLDER/pose_NN/frame_MM.png    one folder per reference-plane pose (>= 3)
//   FOLDER/spheres/frame_MM.png    optional: the five evaluation spheres (sec. 3.4.2)
// with frames in PatternLayout order (capture_folder.h). ROS-agnostic.
#pragma once

#include <body_scan_calib/calibration_rig.h>  // the rig's scene text and averaging
#include <body_scan_calib/pair_calibration_pipeline.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace body_scan_calib {

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

}  // namespace body_scan_calib
