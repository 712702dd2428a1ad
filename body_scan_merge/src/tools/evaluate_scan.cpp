// Accuracy of a scanned cloud against the simulator's true surface (evaluation only):
//   evaluate_scan --cloud build/demo/full_scan.ply --scene SCENE.yaml [--report report.yaml]
// Prints the mean distance, the coverage of the body (soles excluded) and of the regions under
// the chin, the armpits, the groin and the sides of the torso; writes them as YAML, and the
// points farther than 20 mm from every true surface as a PLY (--outliers) to look at.
#include <body_scan_merge/eval/scan_accuracy.h>
#include <body_scan_merge/ply_writer.h>

#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>

namespace {
constexpr const char* kUsage =
    "usage: evaluate_scan --cloud CLOUD.ply --scene SCENE.yaml [--report REPORT.yaml] "
    "[--outliers OUTLIERS.ply]\n";
}  // namespace

int main(int argc, char** argv) {
  std::string cloud_path, scene_path, report_path, outliers_path;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    try {
      if (arg == "--cloud")
        cloud_path = value();
      else if (arg == "--scene")
        scene_path = value();
      else if (arg == "--report")
        report_path = value();
      else if (arg == "--outliers")
        outliers_path = value();
      else
        throw std::invalid_argument("unknown argument " + arg);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n%s", e.what(), kUsage);
      return 2;
    }
  }
  if (cloud_path.empty() || scene_path.empty()) {
    std::fprintf(stderr, "%s", kUsage);
    return 2;
  }
  try {
    const std::vector<float> cloud = body_scan_merge::readPly(cloud_path);
    const body_scan_driver::sim::Scene scene = body_scan_driver::sim::loadScene(scene_path);
    const auto accuracy = body_scan_merge::eval::evaluateScan(cloud, scene);
    const std::string yaml =
        body_scan_merge::eval::accuracyReportYaml(accuracy, cloud_path + " vs " + scene_path);
    std::cout << yaml;
    if (!outliers_path.empty()) {
      std::vector<float> outliers;
      for (size_t k : accuracy.outlier_indices)
        outliers.insert(outliers.end(), cloud.begin() + 4 * k, cloud.begin() + 4 * k + 4);
      body_scan_merge::writePly(outliers_path, outliers.data(), outliers.size() / 4, 4, 3);
      std::cout << accuracy.outliers << " outliers written to " << outliers_path << "\n";
    }
    if (!report_path.empty()) {
      body_scan_merge::eval::writeAccuracyReport(report_path, accuracy,
                                                 cloud_path + " vs " + scene_path);
      std::cout << "report written to " << report_path << "\n";
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "evaluate_scan: %s\n", e.what());
    return 1;
  }
  return 0;
}
