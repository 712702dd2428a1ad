// Command-line options that the calibration tools share: the output files of a product tool and
// its simulated twin (calibrate_pair / calibrate_simulated_pair, align_world /
// align_simulated_rig), the printed board, and the capture layout of recorded folders.
#pragma once

#include <body_scan_calib/camera_calibration.h>
#include <body_scan_calib/capture_layout.h>
#include <body_scan_calib/pair_calibration_run.h>
#include <body_scan_calib/world_alignment_run.h>
#include <body_scan_driver/tools/command_line.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

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

// --ideal-optics of the simulated calibration tools (body_scan_driver sim/virtual_pair.h
// RealCaptureOptics).
inline void addIdealOpticsFlag(CLI::App& app, bool& ideal_optics) {
  app.add_flag("--ideal-optics", ideal_optics,
               "render with the pair file's optics as they are (default: add the optics of real "
               "captures where the pair leaves them off: a 2.5-stripe projected line, blooming, "
               "stray light, shot noise)");
}

// --board-cols, --board-rows (inner corners) and --square (metres); `board` holds the defaults.
inline void addBoardOptions(CLI::App& app, Checkerboard& board) {
  app.add_option("--board-cols,--cols", board.inner_cols,
                 "INNER corners of the board across (where four squares meet)")
      ->capture_default_str()
      ->check(CLI::Range(2, 1000));
  app.add_option("--board-rows,--rows", board.inner_rows, "INNER corners of the board down")
      ->capture_default_str()
      ->check(CLI::Range(2, 1000));
  app.add_option("--square", board.square_size, "side of one square in METRES, e.g. 0.025")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            double metres = 0;
            return CLI::detail::lexical_cast(text, metres) && metres > 0 && metres <= 1
                       ? std::string()
                       : "the side of one square in METRES (e.g. 0.025), got " + text;
          },
          "METRES"));
}

// --layout, --bits, --projector-width, --projector-height of a recorded capture folder.
struct CaptureOptions {
  std::string layout = "project";
  int bits = 8;                                      // project layout: stripe bits
  int projector_width = 1024, projector_height = 0;  // opencv layout: column / row bits
  const CaptureLayout& captureLayout() const { return body_scan_calib::captureLayout(layout); }
  CaptureBits captureBits() const {
    if (layout == "project") return {bits, 0};
    return {bitsForPixels(projector_width),
            projector_height > 0 ? bitsForPixels(projector_height) : 0};
  }
};

// --decoding standard|robust (capture_decoding.h). Unless given, robust for images like real
// captures and standard for the project's own (the images the standard decoder is tuned on).
struct DecodingChoice {
  enum class Kind { kByImages, kStandard, kRobust } kind = Kind::kByImages;
  bool robust(bool real_like_images) const {
    return kind == Kind::kRobust || (kind == Kind::kByImages && real_like_images);
  }
  bool robust(const CaptureOptions& capture) const { return robust(capture.layout != "project"); }
};

// default_text: when the tool decodes robustly without --decoding.
inline void addDecodingOption(
    CLI::App& app, DecodingChoice& choice,
    const std::string& default_text = "robust except for --layout project") {
  body_scan_driver::tools::addChoice<DecodingChoice::Kind>(
      app, "--decoding", choice.kind,
      {{"standard", DecodingChoice::Kind::kStandard}, {"robust", DecodingChoice::Kind::kRobust}},
      "standard: the driver's decoder as is (tuned on the simulator); robust: real captures "
      "(dark albedo decoded, codes inconsistent with their neighbours or the row code "
      "rejected, a contrast-weighted local plane fit of the coordinate). Default: " +
          default_text);
}

inline void addCaptureOptions(CLI::App& app, CaptureOptions& capture) {
  std::vector<std::string> names;
  std::string help = "capture layout:";
  for (const CaptureLayout& layout : captureLayouts()) {
    names.push_back(layout.name);
    help += " " + layout.name + " = " + layout.description + ";";
  }
  app.add_option("--layout", capture.layout, help)
      ->capture_default_str()
      ->check(CLI::IsMember(names));
  app.add_option("--bits", capture.bits, "Gray code bits of the captures (project layout)")
      ->capture_default_str()
      ->check(CLI::Range(body_scan_driver::kMinBits, body_scan_driver::kMaxBits));
  app.add_option("--projector-width", capture.projector_width,
                 "projector columns: ceil(log2) column bits, the stripes (opencv layout)")
      ->capture_default_str()
      ->check(CLI::Range(2, 1 << body_scan_driver::kMaxBits));
  app.add_option("--projector-height", capture.projector_height,
                 "projector rows: ceil(log2) row bits, recorded after the column bits and used "
                 "to check the decoding (opencv layout; 0 = none recorded)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1 << body_scan_driver::kMaxBits));
}

}  // namespace body_scan_calib::tools
