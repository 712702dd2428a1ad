// Whole-body clouds from the full scanner simulation (tests and evaluation only).
#include <body_gait_model/eval/full_scanner_body.h>
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/sim/scene.h>
#include <body_scan_merge/simulated_scan.h>

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace body_gait_model::eval {

namespace sim = body_scan_driver::sim;

namespace {

struct PlannedRig {
  sim::Rig rig;
  body_scan_merge::TimingGroupList groups;
};

// Loading a rig and planning its timing groups takes a while: once per rig file.
const PlannedRig& plannedRig(const std::string& path) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<PlannedRig>> rigs;
  std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<PlannedRig>& planned = rigs[path];
  if (!planned) {
    auto loaded = std::make_unique<PlannedRig>();
    loaded->rig = sim::loadRig(path);
    loaded->groups = body_scan_merge::plannedTimingGroups(loaded->rig);
    planned = std::move(loaded);
  }
  return *planned;
}

}  // namespace

double fullScannerHeading(int index) { return 0.4 * (index % 5) - 0.8; }

SampledBody scanBodyWithFullScanner(const sim::HumanBodySpec& spec,
                                    const FullScannerOptions& options) {
  const PlannedRig& planned =
      plannedRig(options.rig_file.empty() ? sim::driverConfigDir() + "/rigs/thesis_rig.yaml"
                                          : options.rig_file);
  sim::Rig rig = planned.rig;
  body_scan_merge::TimingGroupList groups = planned.groups;
  for (const std::string& missing : options.missing_pairs) {
    rig.pair(missing);  // throws naming the id and the rig's ids
    rig.pairs.erase(std::remove_if(rig.pairs.begin(), rig.pairs.end(),
                                   [&](const auto& pair) { return pair.pair_id == missing; }),
                    rig.pairs.end());
    for (auto& group : groups)
      group.erase(std::remove(group.begin(), group.end(), missing), group.end());
  }
  groups.erase(
      std::remove_if(groups.begin(), groups.end(), [](const auto& g) { return g.empty(); }),
      groups.end());

  auto scene = std::make_shared<sim::Scene>();
  sim::Material floor;
  floor.albedo = options.floor_albedo;
  floor.color = Eigen::Vector3d::Constant(options.floor_albedo);
  scene->add(
      std::make_unique<sim::Plane>(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), floor, 2.0));
  SampledBody body;
  body.spec = addSimulatedBody(spec, options.body, *scene);
  body.skeleton = scene->skeleton();
  const body_scan_merge::SimulatedScan scan = body_scan_merge::simulateScan(rig, scene, groups);
  const std::vector<float>& xyzrgb = scan.cloud.xyzrgb;
  body.points.reserve(xyzrgb.size() / 4);
  for (size_t i = 0; i < xyzrgb.size(); i += 4)
    body.points.emplace_back(xyzrgb[i], xyzrgb[i + 1], xyzrgb[i + 2]);
  return body;
}

}  // namespace body_gait_model::eval
