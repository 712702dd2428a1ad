// plan_timing_groups: the timing groups of a calibrated rig (thesis sec. 4.2.4, Fig 4.7), offline.
// Reads each pair's calibration file and its world pose (the file's world_alignment section, else
// the rig file's pose), prints the groups and the conflicts and writes them as a YAML report.
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/rig_layout.h>
#include <body_scan_driver/tools/command_line.h>
#include <body_scan_merge/timing_groups.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <iostream>
#include <optional>
#include <sstream>

using namespace body_scan_merge;
using namespace body_scan_driver;

namespace {

std::string fileStem(const std::string& pair_id) {
  std::string stem = pair_id;
  std::replace(stem.begin(), stem.end(), '/', '_');
  return stem;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Computes the timing groups of a calibrated rig: pairs whose light reaches another pair's "
      "view never share a group, with as few groups as possible (an exact minimum colouring of "
      "the conflict graph).",
      "plan_timing_groups");
  std::string calibration_dir, suffix, rig_path, report;
  double group_seconds = 0;
  int pattern_bits = 8;
  bool inverse_frames = true;
  GroupTiming timing;
  InterferenceProxy proxy;
  app.add_option("--calibration-dir", calibration_dir,
                 "pair calibrations <pole>_<pair><suffix>.yaml")
      ->required()
      ->check(CLI::ExistingDirectory);
  app.add_option("--suffix", suffix, "file name suffix, e.g. _factory (default: none)");
  app.add_option("--rig", rig_path,
                 "rig file: the pair ids and, for files without a world_alignment section, the "
                 "pair poses")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--group-seconds", group_seconds,
                 "acquisition time of one group (default: the pattern frames at the camera "
                 "frame rate, 0.5 s for the thesis's 18 frames at 36 Hz)")
      ->check(body_scan_driver::tools::positive());
  app.add_option("--pattern-bits", pattern_bits, "Gray code bits of the pairs' pattern sets")
      ->capture_default_str()
      ->check(CLI::Range(body_scan_driver::kMinBits, body_scan_driver::kMaxBits));
  app.add_option("--inverse-frames", inverse_frames, "pattern sets carry inverse frames")
      ->capture_default_str();
  app.add_option("--camera-fps", timing.camera_fps, "camera frame rate (Hz)")
      ->capture_default_str()
      ->check(body_scan_driver::tools::positive());
  app.add_option("--settle-frames", timing.settle_frames,
                 "camera frames discarded after each pattern change (the usb pair's "
                 "settle_frames)")
      ->capture_default_str()
      ->check(body_scan_driver::tools::atLeast(0));
  app.add_option("--light-margin", proxy.light_margin,
                 "grow each sweep this many metres beyond its first and last calibrated stripe "
                 "planes")
      ->capture_default_str()
      ->check(body_scan_driver::tools::atLeast(0));
  app.add_option("--min-overlap-area", proxy.min_overlap_area,
                 "m^2 of lit-and-seen proxy surface tolerated")
      ->capture_default_str()
      ->check(body_scan_driver::tools::atLeast(0));
  app.add_option("--report", report, "also write the plan as YAML (atomically)");
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  try {
    timing.pattern_frames =
        body_scan_driver::PatternLayout(pattern_bits, inverse_frames).frameCount();
    if (group_seconds <= 0) group_seconds = timing.seconds();
    const body_scan_driver::RigLayout rig = body_scan_driver::loadRigLayout(rig_path);
    std::vector<PairGeometry> pairs;
    int aligned = 0;
    for (const body_scan_driver::RigPairLayout& config : rig.pairs) {
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
