// Command-line options that a product calibration tool and its simulated twin share
// (calibrate_pair / calibrate_simulated_pair, align_world / align_simulated_rig): the output
// files, so that both tools write the same files under the same names and defaults.
#pragma once

#include <body_scan_calib/pair_calibration_run.h>
#include <body_scan_calib/world_alignment_run.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <string>

namespace body_scan_calib::tools {

// --output, --report, --plot and --no-refinement of a pair calibration.
inline void addPairCalibrationOutputs(CLI::App& app, PairCalibrationFiles& files,
                                      bool& no_refinement) {
  app.add_option("--output", files.calibration, "calibration file")->capture_default_str();
  app.add_option("--report", files.report, "accuracy report")->capture_default_str();
  app.add_option("--plot", files.plot, "projector parameters plot")->capture_default_str();
  app.add_flag("--no-refinement", no_refinement, "skip the joint Ceres refinement");
}

// --calibration-out (default ~/.ros/body_scan/calibration), --report and --plot of a world
// alignment.
inline void addWorldAlignmentOutputs(CLI::App& app, WorldAlignmentFiles& files) {
  const char* home = std::getenv("HOME");
  files.calibration_out = std::string(home ? home : ".") + "/.ros/body_scan/calibration";
  app.add_option("--calibration-out", files.calibration_out, "aligned calibrations")
      ->capture_default_str();
  app.add_option("--report", files.report, "YAML report")->capture_default_str();
  app.add_option("--plot", files.plot,
                 "PNG: the aligned points on the unrolled cylinder, E_h per shared point against "
                 "height (default: the report's path with .png)");
}

}  // namespace body_scan_calib::tools
