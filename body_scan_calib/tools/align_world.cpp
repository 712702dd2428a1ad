// align_world: aligns every pair to the world frame with the calibration cylinder (thesis
// sec. 4.3.2) and reports E_h (eq 4.2, Table 4.2), from a folder of the pairs' captures.
// align_simulated_rig runs the same on captures rendered by the virtual pairs.
#include <body_scan_calib/world_alignment_run.h>
#include <body_scan_driver/tools/command_line.h>

#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>

#include "calibration_outputs.h"

namespace {

struct Options {
  std::string images, calibration_in;
  body_scan_calib::WorldAlignmentFiles files;
};

// Returns the exit status when the tool should stop (--help, a usage error).
std::optional<int> parseOptions(int argc, char** argv, Options& options) {
  CLI::App app(
      "Aligns each projector-camera pair to the world frame defined by the calibration cylinder "
      "(thesis sec. 4.3.2): detects and triangulates the cylinder's grid points, fits the affine "
      "of eq 4.1 per pair, writes each pair's calibration file with its world_alignment section "
      "and a YAML report with E_h (eq 4.2) over the points seen by two pairs. Reads the pairs' "
      "captures from a folder; align_simulated_rig renders them with the virtual pairs instead.",
      "align_world");
  app.add_option("--images", options.images,
                 "one folder per pair as written by align_simulated_rig --save-images: "
                 "frame_NN.png in pattern order, texture.png, capture.yaml (pair_id, bits, "
                 "inverse_frames)")
      ->required();
  app.add_option("--calibration-in", options.calibration_in,
                 "pair calibrations to align, <pole>_<pair>.yaml (one per pair folder)");
  body_scan_calib::tools::addWorldAlignmentOutputs(app, options.files);
  return body_scan_driver::tools::parseCommandLine(app, argc, argv);
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (const auto status = parseOptions(argc, argv, options)) return *status;
  try {
    const auto captures =
        body_scan_calib::loadCylinderCaptures(options.images, options.calibration_in);
    return body_scan_calib::alignWorld(captures, "offline (" + options.images + ")",
                                       options.files) == 0
               ? 0
               : 1;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
