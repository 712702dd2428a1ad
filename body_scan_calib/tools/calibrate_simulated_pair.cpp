// Calibrates one virtual projector-camera pair as calibrate_pair calibrates a real one: the
// simulator places the board in the rig's poses and the five evaluation spheres, the pair
// renders them, and the same calibration run (pair_calibration_run.h) writes the calibration
// file, the accuracy report (with the simulator's truth) and the Fig 3.6 plot.
#include <body_scan_calib/pair_calibration_run.h>
#include <body_scan_calib/sim/simulated_captures.h>
#include <body_scan_driver/tools/command_line.h>

#include <chrono>
#include <iostream>
#include <optional>
#include <string>

#include "calibration_outputs.h"

namespace {

struct Arguments {
  std::string pair, pair_id, save_images;
  int exposures = 16;
  bool refinement = true, ideal_optics = false;
  body_scan_calib::tools::DecodingChoice decoding;
  body_scan_calib::PairCalibrationFiles files;
};

// Returns the exit status when the tool should stop (--help, a usage error).
std::optional<int> parse(int argc, char** argv, Arguments& arguments) {
  CLI::App app(
      "Calibrates one virtual projector-camera pair: the simulator places the board in the "
      "rig's poses and the five evaluation spheres, the pair renders them, and calibrate_pair's "
      "calibration and sphere evaluation (thesis secs. 3.3, 3.4.2) run on those views.",
      "calibrate_simulated_pair");
  app.add_option("--pair", arguments.pair,
                 "virtual pair file (default: the built-in default pair); its pair_id names the "
                 "calibration (camera_name) and the report")
      ->check(CLI::ExistingFile);
  app.add_option("--pair-id", arguments.pair_id,
                 "pair id written into the files (default: the pair file's), e.g. pole_a/pair_1");
  app.add_option("--exposures", arguments.exposures,
                 "frames averaged per pattern for the static targets")
      ->capture_default_str()
      ->check(body_scan_driver::tools::atLeast(1));
  app.add_option("--save-images", arguments.save_images,
                 "also write the captures in the layout of calibrate_pair --images");
  body_scan_calib::tools::addIdealOpticsFlag(app, arguments.ideal_optics);
  body_scan_calib::tools::addDecodingOption(
      app, arguments.decoding,
      "robust, as for real captures; standard with --ideal-optics (calibrate_pair --decoding "
      "reads --save-images back the same way)");
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
    const auto start = std::chrono::steady_clock::now();
    body_scan_driver::sim::VirtualPairConfig config =
        arguments.pair.empty() ? body_scan_driver::sim::VirtualPairConfig{}
                               : body_scan_driver::sim::loadVirtualPairConfig(arguments.pair);
    if (!arguments.ideal_optics) config = body_scan_driver::sim::withRealCaptureOptics(config);
    body_scan_calib::PairCalibrationOptions options;
    options.joint_refinement = arguments.refinement;
    options.decoding.enabled = arguments.decoding.robust(!arguments.ideal_optics);
    options.pair_id = arguments.pair_id.empty() ? config.pair_id : arguments.pair_id;
    const body_scan_calib::PairViews views = body_scan_calib::sim::captureSimulatedPairViews(
        config, options.board, arguments.exposures, arguments.save_images);
    body_scan_calib::calibratePairToFiles(views, options, arguments.files);
    std::cout << "done in "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
              << " s" << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
