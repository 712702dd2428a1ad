// Accuracy of a scanned cloud against the simulator's true surface (evaluation only):
//   evaluate_scan --cloud build/demo/full_scan.ply --scene SCENE.yaml [--report report.yaml]
// Prints the mean distance, the coverage of the body (soles excluded) and of the regions under
// the chin, the armpits, the groin and the sides of the torso; writes them as YAML, and the
// points farther than 20 mm from every true surface as a PLY (--outliers) to look at.
#include <body_scan_driver/tools/command_line.h>
#include <body_scan_merge/eval/scan_accuracy.h>
#include <body_scan_merge/ply_writer.h>

#include <cstdio>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  CLI::App app(
      "Accuracy of a scanned cloud against the simulator's true surface: mean distance, coverage "
      "of the body and of the hard regions (YAML); the points farther than 20 mm from every true "
      "surface as a PLY.",
      "evaluate_scan");
  std::string cloud_path, scene_path, report_path, outliers_path;
  app.add_option("--cloud", cloud_path, "scanned cloud (PLY)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--scene", scene_path, "the simulator's scene file")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--report", report_path, "also write the accuracy as YAML");
  app.add_option("--outliers", outliers_path, "write the outliers (> 20 mm) as PLY");
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
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
