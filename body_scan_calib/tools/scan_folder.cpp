// scan_folder: decodes and triangulates one recorded pattern set offline (no ROS master) with a
// pair calibration, writes the cloud (.ply or .pcd, camera optical frame, metres) and prints the
// valid point count.
//
//   scan_folder --calibration pair.yaml --images POSE_FOLDER [--layout opencv
//               --projector-width 1024 --projector-height 768] --output cloud.ply
#include <body_scan_calib/capture_decoding.h>
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/tools/command_line.h>

#include <cstdio>
#include <iostream>

#include "calibration_outputs.h"

int main(int argc, char** argv) {
  CLI::App app(
      "Decodes and triangulates one recorded pattern set (one board pose or scene folder) with a "
      "pair calibration, writes the point cloud (.ply or .pcd) and prints the valid point count.",
      "scan_folder");
  std::string calibration_file, images, output;
  body_scan_calib::tools::CaptureOptions capture;
  app.add_option("--calibration", calibration_file, "pair calibration file (calibrate_pair)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--images", images, "the folder of ONE pattern set in the --layout")
      ->required()
      ->check(CLI::ExistingDirectory);
  app.add_option("--output", output, "point cloud to write: FILE.ply or FILE.pcd")->required();
  body_scan_calib::tools::addCaptureOptions(app, capture);
  body_scan_calib::tools::DecodingChoice decoding;
  body_scan_calib::tools::addDecodingOption(app, decoding);
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  try {
    const body_scan_driver::PairCalibration calibration =
        body_scan_driver::loadCalibration(calibration_file);
    const body_scan_calib::CaptureBits bits = capture.captureBits();
    if (calibration.projector.stripeCount() != (1 << bits.stripe_bits))
      throw std::invalid_argument(
          calibration_file + " has " + std::to_string(calibration.projector.stripeCount()) +
          " stripe planes but the captures have " + std::to_string(bits.stripe_bits) +
          " stripe bits; check --bits or --projector-width");
    body_scan_calib::RobustDecoding robust;
    robust.enabled = decoding.robust(capture);
    const body_scan_calib::CapturedPatternSet set =
        body_scan_calib::loadCapturedPatternSet(images, capture.captureLayout(), bits);
    const body_scan_driver::StripeImage stripes =
        body_scan_calib::decodeCapturedSet(set, bits.stripe_bits, robust);
    const std::vector<Eigen::Vector3f> points =
        body_scan_calib::triangulateStripes(calibration, stripes.coordinate);
    body_scan_calib::writePointCloud(output, points);
    std::printf("%zu valid points of %zu pixels, wrote %s\n", points.size(),
                stripes.coordinate.total(), output.c_str());
  } catch (const std::exception& e) {
    std::cerr << "scan_folder: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
