// Writes the virtual pair's factory calibration (its true geometry) to a calibration file.
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/pair_device.h>

#include <iostream>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: write_factory_calibration PAIR_FILE SCENE_FILE OUTPUT.yaml\n"
                 "  Writes the simulated pair's true geometry as a calibration file.\n";
    return 2;
  }
  try {
    const auto device = body_scan_driver::makeSimulatedPair(argv[1], argv[2]);
    body_scan_driver::saveCalibration(argv[3], *device->factoryCalibration());
    std::cout << "wrote " << argv[3] << "\n";
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
