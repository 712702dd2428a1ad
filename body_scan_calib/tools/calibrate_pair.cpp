// Calibrates one projector-camera pair from a capture folder of reference-plane poses (thesis
// sec. 3.3) and evaluates it on five spheres (sec. 3.4.2) beside the pinhole-projector baseline.
// Writes the calibration file, the accuracy report (YAML) and the Fig 3.6 plot (PNG), all
// atomically. calibrate_simulated_pair runs the same on views rendered by the virtual pair.
#include <body_scan_calib/pair_calibration_run.h>
#include <body_scan_driver/tools/command_line.h>

#include <iostream>
#include <optional>
#include <string>

#include "calibration_outputs.h"

namespace {

struct Arguments {
  std::string images, pair_id = "pair";
  int exposures = 16;
  body_scan_calib::tools::CaptureOptions capture;
  body_scan_calib::Checkerboard board = body_scan_calib::referenceBoard();
  bool refinement = true;
  body_scan_calib::PairCalibrationFiles files;
};

// Returns the exit status when the tool should stop (--help, a usage error).
std::optional<int> parse(int argc, char** argv, Arguments& arguments) {
  CLI::App app(
      "Calibrates one projector-camera pair from a capture folder of reference-plane poses "
      "(thesis sec. 3.3) and evaluates it on five spheres (sec. 3.4.2) beside the "
      "pinhole-projector baseline. calibrate_simulated_pair renders the views with the virtual "
      "pair instead.",
      "calibrate_pair");
  app.add_option("--images", arguments.images,
                 "recorded captures: one folder per board pose (>= 3) in the --layout, e.g. "
                 "FOLDER/pose_NN/frame_MM.png; optional FOLDER/spheres/frame_MM.png to evaluate")
      ->required()
      ->check(CLI::ExistingDirectory);
  app.add_option("--pair-id", arguments.pair_id,
                 "pair id written into the files, e.g. pole_a/pair_1")
      ->capture_default_str();
  app.add_option("--exposures", arguments.exposures,
                 "how many frames the recorded frames average per pattern (for the report)")
      ->capture_default_str()
      ->check(body_scan_driver::tools::atLeast(1));
  body_scan_calib::tools::addCaptureOptions(app, arguments.capture);
  body_scan_calib::tools::addBoardOptions(app, arguments.board);
  bool no_refinement = false;
  body_scan_calib::tools::addPairCalibrationOutputs(app, arguments.files, no_refinement);
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv)) return status;
  arguments.refinement = !no_refinement;
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments arguments;
  if (const auto status = parse(argc, argv, arguments)) return *status;
  try {
    body_scan_calib::PairCalibrationOptions options;
    options.joint_refinement = arguments.refinement;
    options.pair_id = arguments.pair_id;
    options.board = arguments.board;
    const body_scan_calib::PairViews views =
        body_scan_calib::loadPairViews(arguments.images, arguments.capture.captureLayout(),
                                       arguments.capture.captureBits(), arguments.exposures);
    body_scan_calib::calibratePairToFiles(views, options, arguments.files);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
