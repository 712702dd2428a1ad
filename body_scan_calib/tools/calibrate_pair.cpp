// Calibrates one projector-camera pair from a capture folder of reference-plane poses (thesis
// sec. 3.3) and evaluates it on five spheres (sec. 3.4.2) beside the pinhole-projector baseline.
// Writes the calibration file, the accuracy report (YAML) and the Fig 3.6 plot (PNG), all
// atomically. calibrate_simulated_pair runs the same on views rendered by the virtual pair.
#include <body_scan_calib/pair_calibration_run.h>
#include <body_scan_calib/pair_validation.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/tools/command_line.h>

#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include "calibration_outputs.h"

namespace {

struct Arguments {
  std::string images, pair_id = "pair", validation_report;
  int exposures = 16;
  body_scan_calib::tools::CaptureOptions capture;
  body_scan_calib::Checkerboard board = body_scan_calib::referenceBoard();
  bool refinement = true;
  body_scan_calib::tools::DecodingChoice decoding;
  std::optional<body_scan_calib::StripePlaneModel> stripe_model;  // unset: by layout
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
  app.add_option("--validate", arguments.validation_report,
                 "also validate leave-one-pose-out (>= 4 poses) beside the OpenCV pinhole-"
                 "projector peer (needs the row frames) and write this YAML");
  app.add_option_function<std::string>(
         "--stripe-model",
         [&arguments](const std::string& name) {
           arguments.stripe_model =
               name == "per-stripe"          ? body_scan_calib::StripePlaneModel::kPerStripe
               : name == "smooth-fills-gaps" ? body_scan_calib::StripePlaneModel::kSmoothFillsGaps
                                             : body_scan_calib::StripePlaneModel::kSmooth;
         },
         "stripe planes: per-stripe (thesis eq 3.5; stripes on < 3 poses are NaN; the swept-"
         "mirror projector), smooth (a pencil of planes with a smooth correction across stripe "
         "index, every stripe a board showed; pinhole DLP/LCD projectors) or smooth-fills-gaps "
         "(per stripe where >= 3 poses, smooth elsewhere). Default: per-stripe for --layout "
         "project, smooth otherwise")
      ->check(CLI::IsMember({"per-stripe", "smooth", "smooth-fills-gaps"}));
  body_scan_calib::tools::addDecodingOption(app, arguments.decoding);
  bool no_refinement = false;
  body_scan_calib::tools::addPairCalibrationOutputs(app, arguments.files, no_refinement);
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv)) return status;
  arguments.refinement = !no_refinement;
  return std::nullopt;
}

void printStatistics(const char* name, const body_scan_calib::PlaneErrorStatistics& s) {
  std::printf("  %-6s %9.2f %10.3f %8.3f %8.3f %9.3f\n", name, 100 * s.coverage, s.median_mm,
              s.rms_mm, s.p95_mm, 100 * s.gross_share);
}

void validate(const body_scan_calib::PairViews& views,
              const body_scan_calib::PairCalibrationOptions& options, const std::string& path) {
  std::cout << "leave-one-pose-out validation" << std::endl;
  const body_scan_calib::PairValidation validation = body_scan_calib::validateLeaveOnePoseOut(
      views, options, {}, [](const std::string& line) { std::cout << "  " << line << std::endl; });
  std::printf("  stripes calibrated: %d of %d on a board\n", validation.stripes_calibrated,
              validation.stripes_on_board);
  std::printf("  model  coverage%% median_mm   rms_mm   p95_mm  gross%%(>%.0f mm)\n",
              validation.gross_mm);
  printStatistics("ours", validation.ours.pooled);
  if (!validation.peer.per_pose.empty()) printStatistics("peer", validation.peer.pooled);
  body_scan_driver::writeFileAtomically(path, body_scan_calib::validationYaml(validation));
  std::cout << "wrote " << path << std::endl;
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
    const bool project_layout = arguments.capture.layout == "project";
    options.projector.model = arguments.stripe_model.value_or(
        project_layout ? body_scan_calib::StripePlaneModel::kPerStripe
                       : body_scan_calib::StripePlaneModel::kSmooth);
    options.decoding.enabled = arguments.decoding.robust(arguments.capture);
    const body_scan_calib::PairViews views =
        body_scan_calib::loadPairViews(arguments.images, arguments.capture.captureLayout(),
                                       arguments.capture.captureBits(), arguments.exposures);
    body_scan_calib::calibratePairToFiles(views, options, arguments.files);
    if (!arguments.validation_report.empty()) validate(views, options, arguments.validation_report);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
