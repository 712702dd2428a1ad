// simulate_scan: a whole-body scan of a simulated rig without ROS (simulated_scan.h).
//   simulate_scan --rig RIG.yaml --scene SCENE.yaml [--groups planned|all|alone|FILE.yaml]
//                 [--scan-id N] --output cloud.ply|cloud.pcd
// planned (default): the timing groups planTimingGroups computes for the rig; all: every pair
// at once (interference); alone: one pair at a time; FILE: a YAML list of lists of pair ids.
#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/tools/command_line.h>
#include <body_scan_merge/ply_writer.h>
#include <body_scan_merge/simulated_scan.h>

#include <chrono>
#include <iostream>

using namespace body_scan_merge;
using namespace body_scan_driver;

int main(int argc, char** argv) {
  CLI::App app(
      "A whole-body scan of a simulated rig without ROS: render by timing groups, decode, "
      "triangulate, world frame.",
      "simulate_scan");
  std::string rig_path, scene_path, groups_choice = "planned", output;
  std::uint32_t scan_id = 1;
  app.add_option("--rig", rig_path, "rig file")->required()->check(CLI::ExistingFile);
  app.add_option("--scene", scene_path, "scene file")->required()->check(CLI::ExistingFile);
  app.add_option("--groups", groups_choice,
                 "planned: the rig's timing groups (planTimingGroups); all: every pair at once "
                 "(interference); alone: one pair at a time; else a YAML file of lists of pair ids")
      ->capture_default_str();
  app.add_option("--scan-id", scan_id, "scan id of the rendered pattern sets")
      ->capture_default_str();
  app.add_option("--output", output, "cloud file: .ply, or .pcd")->required();
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  try {
    const body_scan_driver::sim::Rig rig = body_scan_driver::sim::loadRig(rig_path);
    auto scene = std::make_shared<const body_scan_driver::sim::Scene>(
        body_scan_driver::sim::loadScene(scene_path));
    const std::string& g = groups_choice;
    const TimingGroupList groups = g == "planned" ? plannedTimingGroups(rig)
                                   : g == "all"   ? allPairsTogether(rig)
                                   : g == "alone" ? eachPairAlone(rig)
                                                  : loadTimingGroups(g);
    const auto start = std::chrono::steady_clock::now();
    const SimulatedScan scan = simulateScan(rig, scene, groups, scan_id);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string& out = output;
    const bool pcd = out.size() > 4 && out.substr(out.size() - 4) == ".pcd";
    (pcd ? writePcd : writePly)(out, scan.cloud.xyzrgb.data(), scan.cloud.size(), 4, 3);
    std::cout << "timing groups: " << groups.size() << "\n";
    for (const auto& [id, count] : scan.per_pair) std::cout << "  " << id << ": " << count << "\n";
    std::cout << scan.cloud.size() << " points in " << seconds << " s -> " << out << "\n";
  } catch (const std::exception& e) {
    std::cerr << "simulate_scan: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
