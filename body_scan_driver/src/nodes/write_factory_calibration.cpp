// Writes the virtual pair's factory calibration (its true geometry) to a calibration file.
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/sim/simulated_pair_device.h>
#include <body_scan_driver/tools/command_line.h>

#include <iostream>

int main(int argc, char** argv) {
  CLI::App app("Writes the simulated pair's true geometry as a calibration file.",
               "write_factory_calibration");
  std::string pair_file, scene_file, output;
  app.add_option("PAIR_FILE", pair_file, "virtual pair file")->required()->check(CLI::ExistingFile);
  app.add_option("SCENE_FILE", scene_file, "scene file")->required()->check(CLI::ExistingFile);
  app.add_option("OUTPUT", output, "calibration file to write (YAML)")->required();
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  try {
    const auto device = body_scan_driver::sim::makeSimulatedPair(pair_file, scene_file);
    body_scan_driver::saveCalibration(output, device->factoryCalibration());
    std::cout << "wrote " << output << "\n";
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
