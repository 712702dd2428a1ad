// align_simulated_rig: align_world on the simulator's rig. The cylinder scene is loaded, each
// virtual pair renders its pattern set, and the same alignment run (world_alignment_run.h)
// writes the aligned calibrations and the E_h report, with each pair's error against the truth.
#include <body_scan_calib/sim/simulated_captures.h>
#include <body_scan_calib/world_alignment_run.h>
#include <body_scan_driver/tools/command_line.h>
#include <body_scan_driver/tools/package_file.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "calibration_outputs.h"

namespace fs = std::filesystem;

namespace {

struct Options {
  std::string scene, save_images, calibration_in;
  std::vector<std::string> pairs;
  bool ideal_optics = false;
  body_scan_calib::WorldAlignmentFiles files;
};

// Returns the exit status when the tool should stop (--help, a usage error).
std::optional<int> parseOptions(int argc, char** argv, Options& options) {
  CLI::App app(
      "Aligns each virtual projector-camera pair to the world frame defined by the calibration "
      "cylinder (thesis sec. 4.3.2) as align_world aligns real ones: the pairs render the "
      "cylinder scene, then align_world's fit (eq 4.1) and E_h report (eq 4.2) run on those "
      "captures, with each pair's error against the simulator's truth.",
      "align_simulated_rig");
  app.add_option("--scene", options.scene,
                 "cylinder scene (default: body_scan_driver's "
                 "config/scenes/calibration_cylinder.yaml)")
      ->check(CLI::ExistingFile);
  app.add_option("--pair", options.pairs,
                 "a pair file (repeat; default: body_scan_calib's config/alignment/*.yaml)")
      ->check(CLI::ExistingFile);
  app.add_option("--save-images", options.save_images,
                 "also write what each pair captured, for align_world --images");
  app.add_option("--calibration-in", options.calibration_in,
                 "pair calibrations to align, <pole>_<pair>.yaml (the simulator's factory "
                 "calibration for a pair without a file)");
  body_scan_calib::tools::addWorldAlignmentOutputs(app, options.files);
  body_scan_calib::tools::addIdealOpticsFlag(app, options.ideal_optics);
  return body_scan_driver::tools::parseCommandLine(app, argc, argv);
}

// The defaults from the packages that ship them: the cylinder scene, every pair file of the
// alignment rig.
void packageDefaults(Options& options) {
  if (options.scene.empty())
    options.scene = body_scan_driver::tools::packageFile(
        "body_scan_driver", "config/scenes/calibration_cylinder.yaml", "--scene");
  if (options.pairs.empty()) {
    for (const auto& entry : fs::directory_iterator(
             body_scan_driver::tools::packageFile("body_scan_calib", "config/alignment", "--pair")))
      if (entry.path().extension() == ".yaml") options.pairs.push_back(entry.path().string());
    std::sort(options.pairs.begin(), options.pairs.end());
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (const auto status = parseOptions(argc, argv, options)) return *status;
  try {
    packageDefaults(options);
    const auto captures = body_scan_calib::sim::captureSimulatedCylinder(
        options.scene, options.pairs, options.calibration_in, options.save_images,
        options.ideal_optics);
    return body_scan_calib::alignWorld(captures, "live (simulator)", options.files) == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
