// simulate_scan: a whole-body scan of a simulated rig without ROS (simulated_scan.h).
//   simulate_scan --rig RIG.yaml --scene SCENE.yaml [--groups planned|all|alone|FILE.yaml]
//                 [--scan-id N] --output cloud.ply|cloud.pcd
// planned (default): the timing groups planTimingGroups computes for the rig; all: every pair
// at once (interference); alone: one pair at a time; FILE: a YAML list of lists of pair ids.
#include <body_scan_driver/sim/rig.h>
#include <body_scan_merge/ply_writer.h>
#include <body_scan_merge/simulated_scan.h>

#include <chrono>
#include <iostream>
#include <map>

using namespace body_scan_merge;
using namespace body_scan_driver;

namespace {
int usage(const std::string& problem) {
  std::cerr << "simulate_scan: " << problem
            << "\nusage: simulate_scan --rig RIG.yaml --scene SCENE.yaml "
               "[--groups planned|all|alone|FILE.yaml] [--scan-id N] --output cloud.ply|.pcd\n";
  return 2;
}
}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args = {{"--groups", "planned"}, {"--scan-id", "1"}};
  for (int i = 1; i < argc; ++i) {
    const std::string key = argv[i];
    if (key == "-h" || key == "--help") return usage("help");
    if (key != "--rig" && key != "--scene" && key != "--groups" && key != "--output" &&
        key != "--scan-id")
      return usage("unknown argument '" + key + "'");
    if (i + 1 >= argc) return usage(key + " needs a value");
    args[key] = argv[++i];
  }
  for (const char* required : {"--rig", "--scene", "--output"})
    if (!args.count(required)) return usage(std::string("missing ") + required);
  try {
    const body_scan_driver::sim::Rig rig = body_scan_driver::sim::loadRig(args["--rig"]);
    auto scene = std::make_shared<const body_scan_driver::sim::Scene>(
        body_scan_driver::sim::loadScene(args["--scene"]));
    const std::string& g = args["--groups"];
    const TimingGroupList groups = g == "planned" ? plannedTimingGroups(rig)
                                   : g == "all"   ? allPairsTogether(rig)
                                   : g == "alone" ? eachPairAlone(rig)
                                                  : loadTimingGroups(g);
    const auto start = std::chrono::steady_clock::now();
    const SimulatedScan scan =
        simulateScan(rig, scene, groups, static_cast<uint32_t>(std::stoul(args["--scan-id"])));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string& out = args["--output"];
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
