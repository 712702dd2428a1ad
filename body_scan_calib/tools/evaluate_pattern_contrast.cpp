// evaluate_pattern_contrast: the finest Gray-code bit's |pattern - inverse| on a checkerboard's
// dark and light squares (eval/pattern_contrast.h), of a recorded capture folder and of the
// simulator's renders of its own board in the rig's poses, side by side: how close the
// simulator's decoding difficulty is to real captures'; the dark squares' lit level near a light
// square (blooming); then the sensor noise against signal level of both
// (eval::sensorNoiseByLevel).
//
//   evaluate_pattern_contrast --images CAPTURES --layout opencv --projector-width 1024
//       --board-cols 9 --board-rows 7 [--pair PAIR_FILE] [--poses 16]
#include <body_scan_calib/calibration_rig.h>
#include <body_scan_calib/eval/pattern_contrast.h>
#include <body_scan_calib/sim/calibration_scenes.h>
#include <body_scan_driver/tools/command_line.h>

#include <iostream>
#include <string>

#include "calibration_outputs.h"

int main(int argc, char** argv) {
  CLI::App app(
      "Prints the distribution (percentiles, histogram) of the finest Gray-code bit's |pattern - "
      "inverse| on a checkerboard's dark and light squares: of the recorded captures (--images) "
      "and of the simulator's renders of its board in the calibration rig's poses; the dark "
      "squares' lit level against the distance to a light square (blooming); then both sets' "
      "sensor noise by signal level.",
      "evaluate_pattern_contrast");
  std::string images, pair;
  int poses = 16;
  double edge_margin = 2.0;
  body_scan_calib::tools::CaptureOptions capture;
  body_scan_calib::Checkerboard board{9, 7, 0.075};
  app.add_option("--images", images, "recorded capture folder (one subfolder per board pose)")
      ->required()
      ->check(CLI::ExistingDirectory);
  body_scan_calib::tools::addCaptureOptions(app, capture);
  body_scan_calib::tools::addBoardOptions(app, board);
  bool ideal_optics = false;
  body_scan_calib::tools::addIdealOpticsFlag(app, ideal_optics);
  app.add_option("--pair", pair, "virtual pair file (default: the built-in default pair)")
      ->check(CLI::ExistingFile);
  app.add_option("--poses", poses, "simulated board poses (the rig's first N, one exposure each)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  app.add_option("--edge-margin", edge_margin,
                 "pixels nearer than this to a square's edge are left out")
      ->capture_default_str()
      ->check(body_scan_driver::tools::atLeast(0));
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  try {
    namespace eval = body_scan_calib::eval;
    const body_scan_calib::CaptureBits bits = capture.captureBits();
    std::vector<std::vector<cv::Mat>> recorded;
    for (body_scan_calib::CapturedPatternSet& set :
         body_scan_calib::loadCapturedPoses(images, capture.captureLayout(), bits))
      recorded.push_back(std::move(set.frames));
    const eval::BoardContrast real = eval::finestBitContrastOnBoard(
        recorded, body_scan_driver::PatternLayout(bits.stripe_bits, true), board, edge_margin);

    body_scan_driver::sim::VirtualPairConfig config =
        pair.empty() ? body_scan_driver::sim::VirtualPairConfig{}
                     : body_scan_driver::sim::loadVirtualPairConfig(pair);
    if (!ideal_optics) config = body_scan_driver::sim::withRealCaptureOptics(config);
    const body_scan_calib::Checkerboard simulated_board = body_scan_calib::referenceBoard();
    const auto board_poses = body_scan_calib::rig::defaultBoardPoses();
    std::vector<std::vector<cv::Mat>> rendered;
    for (int pose = 0; pose < std::min<int>(poses, board_poses.size()); ++pose) {
      const body_scan_driver::sim::VirtualPair virtual_pair(
          config, body_scan_calib::rig::boardScene(simulated_board, board_poses[pose],
                                                   config.world_from_camera));
      rendered.push_back(virtual_pair.render(static_cast<uint32_t>(1000 * pose)).frames);
    }
    const eval::BoardContrast simulated = eval::finestBitContrastOnBoard(
        rendered, body_scan_driver::PatternLayout(config.bits, true), simulated_board, edge_margin);
    std::cout << "finest Gray-code bit on the board: recorded " << real.poses
              << " poses, simulated " << simulated.poses << " poses\n"
              << eval::contrastTable("real", real, "sim", simulated) << "\n"
              << eval::noiseTable(
                     "real",
                     eval::sensorNoiseByLevel(
                         recorded, body_scan_driver::PatternLayout(bits.stripe_bits, true)),
                     "sim",
                     eval::sensorNoiseByLevel(rendered,
                                              body_scan_driver::PatternLayout(config.bits, true)));
  } catch (const std::exception& e) {
    std::cerr << "evaluate_pattern_contrast: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
