// plan_timing_groups: the timing groups of a calibrated rig (thesis sec. 4.2.4, Fig 4.7), offline.
// Reads each pair's calibration file and its world pose (the file's world_alignment section, else
// the rig file's pose), prints the groups and the conflicts and writes them as a YAML report.
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/sim/rig.h>
#include <body_scan_merge/timing_groups.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <sstream>

using namespace body_scan_merge;
using namespace body_scan_driver;

namespace {

const char* kUsage = R"(usage: plan_timing_groups --calibration-dir DIR --rig RIG.yaml [options]
Computes the timing groups of a rig: pairs whose light reaches another pair's view never share
a group, with as few groups as possible (an exact minimum colouring of the conflict graph).
  --calibration-dir DIR   pair calibrations <pole>_<pair><suffix>.yaml (required)
  --suffix S              file name suffix, e.g. _factory (default: none)
  --rig FILE              rig file: the pair ids and, for files without a world_alignment
                          section, the pair poses (required)
  --group-seconds T       acquisition time of one group (default 0.5, thesis sec. 4.2.4)
  --light-margin M        grow each sweep M metres beyond its first and last calibrated
                          stripe planes (default 0.02)
  --min-overlap-area A    m^2 of lit-and-seen proxy surface tolerated (default 0)
  --report FILE           also write the plan as YAML (atomically)
)";

std::string fileStem(const std::string& pair_id) {
  std::string stem = pair_id;
  std::replace(stem.begin(), stem.end(), '/', '_');
  return stem;
}

}  // namespace

int main(int argc, char** argv) {
  std::string calibration_dir, suffix, rig_path, report;
  double group_seconds = 0.5;
  InterferenceProxy proxy;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "plan_timing_groups: " << arg << " needs a value\n" << kUsage;
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--calibration-dir")
      calibration_dir = value();
    else if (arg == "--suffix")
      suffix = value();
    else if (arg == "--rig")
      rig_path = value();
    else if (arg == "--report")
      report = value();
    else if (arg == "--group-seconds")
      group_seconds = std::atof(value().c_str());
    else if (arg == "--light-margin")
      proxy.light_margin = std::atof(value().c_str());
    else if (arg == "--min-overlap-area")
      proxy.min_overlap_area = std::atof(value().c_str());
    else if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      return 0;
    } else {
      std::cerr << "plan_timing_groups: unknown option '" << arg << "'\n" << kUsage;
      return 2;
    }
  }
  if (calibration_dir.empty() || rig_path.empty()) {
    std::cerr << "plan_timing_groups: --calibration-dir and --rig are required\n" << kUsage;
    return 2;
  }
  try {
    const body_scan_driver::sim::Rig rig = body_scan_driver::sim::loadRig(rig_path);
    std::vector<PairGeometry> pairs;
    int aligned = 0;
    for (const body_scan_driver::sim::VirtualPairConfig& config : rig.pairs) {
      PairGeometry pair;
      pair.pair_id = config.pair_id;
      pair.calibration = body_scan_driver::loadCalibration(
          calibration_dir + "/" + fileStem(config.pair_id) + suffix + ".yaml");
      if (pair.calibration.alignment) {
        pair.world_from_camera = pair.calibration.alignment->world_from_camera;
        ++aligned;
      } else {
        pair.world_from_camera = config.world_from_camera;
      }
      pairs.push_back(std::move(pair));
    }
    const TimingPlan plan = planTimingGroups(pairs, proxy);
    std::cout << pairs.size() << " pairs (" << aligned << " poses from world_alignment, "
              << pairs.size() - aligned << " from " << rig_path << "), " << plan.conflicts.size()
              << " conflicts (lighting pair -> seeing pair)\n";
    for (const auto& [a, b] : plan.conflicts) std::cout << "  " << a << " -> " << b << "\n";
    std::cout << plan.groups.size() << " timing groups, simulated acquisition "
              << plan.groups.size() * group_seconds << " s:\n";
    YAML::Emitter out;
    out << YAML::BeginMap << YAML::Key << "rig" << YAML::Value << rig_path;
    out << YAML::Key << "calibration_dir" << YAML::Value << calibration_dir;
    out << YAML::Key << "group_count" << YAML::Value << plan.groups.size();
    out << YAML::Key << "group_seconds" << YAML::Value << group_seconds;
    out << YAML::Key << "simulated_acquisition_seconds" << YAML::Value
        << plan.groups.size() * group_seconds;
    out << YAML::Key << "groups" << YAML::Value << YAML::BeginSeq;
    for (const auto& group : plan.groups) {
      std::cout << " ";
      for (const std::string& id : group) std::cout << " " << id;
      std::cout << "\n";
      out << YAML::Flow << group;
    }
    out << YAML::EndSeq << YAML::Key << "conflicts" << YAML::Value << YAML::BeginSeq;
    for (const auto& [a, b] : plan.conflicts) out << YAML::Flow << std::vector<std::string>{a, b};
    out << YAML::EndSeq << YAML::EndMap;
    if (!report.empty()) {
      body_scan_driver::writeFileAtomically(report, std::string(out.c_str()) + "\n");
      std::cout << "report: " << report << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "plan_timing_groups: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
