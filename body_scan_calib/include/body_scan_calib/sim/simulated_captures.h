// The captures of the calibration tools rendered in-process by the virtual pair (library
// body_scan_calib_sim): calibrate_simulated_pair and align_simulated_rig feed them to the same
// runs as the folder tools (pair_calibration_run.h, world_alignment_run.h), frame for frame.
#pragma once

#include <body_scan_calib/pair_calibration_run.h>
#include <body_scan_calib/world_alignment_run.h>
#include <body_scan_driver/sim/virtual_pair.h>

#include <string>
#include <vector>

namespace body_scan_calib::sim {

// The board in the rig's poses (rig::defaultBoardPoses) and the five evaluation spheres, each
// captured `exposures` times and averaged (rig::captureAveraged), the spheres once more with one
// exposure; the truth (exact sphere centres, factory calibration) for the report. With
// `save_images`, also writes the averaged frames in the capture folder layout (calibrate_pair).
PairViews captureSimulatedPairViews(const body_scan_driver::sim::VirtualPairConfig& config,
                                    const Checkerboard& board, int exposures,
                                    const std::string& save_images = "");

// Every pair file's pair renders the cylinder scene `scene_file` once (with the real-capture
// optics, virtual_pair.h, unless ideal_optics). Each pair aligns its
// calibration from `calibration_in` (calibrationToAlign), else the simulator's factory one.
// With `save_images`, also writes each capture for align_world (saveCylinderCapture). Throws
// std::runtime_error if the scene has no calibration_cylinder object.
std::vector<CylinderCapture> captureSimulatedCylinder(const std::string& scene_file,
                                                      const std::vector<std::string>& pair_files,
                                                      const std::string& calibration_in,
                                                      const std::string& save_images = "",
                                                      bool ideal_optics = false);

}  // namespace body_scan_calib::sim
