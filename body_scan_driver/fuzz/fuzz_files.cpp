// The driver's file readers on arbitrary bytes: a pair calibration (YAML), a scene, a rig file
// (its layout as the coordinator and the usb backend read it, and the simulator's rig), a
// virtual pair file. Each must load or throw a std::exception naming the problem.
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/fuzz_target.h>
#include <body_scan_driver/rig_layout.h>
#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/sim/scene.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <body_scan_driver/triangulation.h>

#include <stdexcept>

using namespace body_scan_driver;

BODY_SCAN_FUZZ_TARGET(calibration_yaml) {
  try {
    const PairCalibration calibration =
        loadCalibration(fuzz::inputFile("calibration_yaml", data, size, ".yaml"));
    Triangulator triangulator(calibration);  // a calibration that loads must be usable
  } catch (const std::exception&) {
  }
  return 0;
}

BODY_SCAN_FUZZ_TARGET(scene) {
  try {
    sim::parseScene(std::string(reinterpret_cast<const char*>(data), size));
  } catch (const std::exception&) {
  }
  return 0;
}

BODY_SCAN_FUZZ_TARGET(rig) {
  const std::string path = fuzz::inputFile("rig", data, size, ".yaml");
  try {
    loadRigLayout(path);
  } catch (const std::exception&) {
  }
  try {
    sim::loadRig(path);
  } catch (const std::exception&) {
  }
  return 0;
}

BODY_SCAN_FUZZ_TARGET(pair) {
  const std::string path = fuzz::inputFile("pair", data, size, ".yaml");
  try {
    sim::loadVirtualPairConfig(path);
  } catch (const std::exception&) {
  }
  try {
    loadPairFilePose(path);
  } catch (const std::exception&) {
  }
  return 0;
}
