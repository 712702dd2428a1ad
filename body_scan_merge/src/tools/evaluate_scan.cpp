// evaluate_scan: accuracy of a scanned cloud against the simulator's true surface
// (scan_accuracy.h; issue 4: mean distance <= 2 mm, coverage >= 95 %, hard regions >= 80 %).
//   evaluate_scan --cloud cloud.ply|cloud.pcd --scene SCENE.yaml [--report report.yaml]
//                 [--spacing M] [--coverage-radius M] [--outlier M]
#include <body_scan_driver/sim/scene.h>
#include <body_scan_merge/cloud_reader.h>
#include <body_scan_merge/scan_accuracy.h>

#include <iostream>
#include <map>

using namespace body_scan;

namespace {
int usage(const std::string& problem) {
  std::cerr << "evaluate_scan: " << problem
            << "\nusage: evaluate_scan --cloud cloud.ply|.pcd --scene SCENE.yaml "
               "[--report report.yaml] [--spacing M] [--coverage-radius M] [--outlier M]\n";
  return 2;
}
}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args;
  for (int i = 1; i < argc; ++i) {
    const std::string key = argv[i];
    if (key == "-h" || key == "--help") return usage("help");
    if (key != "--cloud" && key != "--scene" && key != "--report" && key != "--spacing" &&
        key != "--coverage-radius" && key != "--outlier")
      return usage("unknown argument '" + key + "'");
    if (i + 1 >= argc) return usage(key + " needs a value");
    args[key] = argv[++i];
  }
  for (const char* required : {"--cloud", "--scene"})
    if (!args.count(required)) return usage(std::string("missing ") + required);
  try {
    ScanAccuracyOptions options;
    if (args.count("--spacing")) options.sample_spacing = std::stod(args["--spacing"]);
    if (args.count("--coverage-radius"))
      options.coverage_radius = std::stod(args["--coverage-radius"]);
    if (args.count("--outlier")) options.outlier_distance = std::stod(args["--outlier"]);
    const auto cloud = readPointCloud(args["--cloud"]);
    const sim::Scene scene = sim::loadScene(args["--scene"]);
    const ScanAccuracy accuracy = evaluateScan(cloud, scene, options);
    const std::string yaml = scanAccuracyYaml(accuracy, options, &scene);
    std::cout << yaml;
    if (args.count("--report"))
      writeScanAccuracyReport(args["--report"], accuracy, options, &scene);
  } catch (const std::exception& e) {
    std::cerr << "evaluate_scan: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
