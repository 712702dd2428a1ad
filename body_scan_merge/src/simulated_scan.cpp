#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>
#include <body_scan_merge/simulated_scan.h>
#include <body_scan_merge/timing_groups.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <stdexcept>

namespace body_scan_merge {

TimingGroupList eachPairAlone(const body_scan_driver::sim::Rig& rig) {
  TimingGroupList groups;
  for (const auto& id : rig.pairIds()) groups.push_back({id});
  return groups;
}

TimingGroupList allPairsTogether(const body_scan_driver::sim::Rig& rig) { return {rig.pairIds()}; }

std::vector<PairGeometry> rigFactoryGeometry(const body_scan_driver::sim::Rig& rig) {
  auto empty = std::make_shared<body_scan_driver::sim::Scene>();
  std::vector<PairGeometry> pairs;
  for (const auto& config : rig.pairs)
    pairs.push_back(
        {config.pair_id,
         body_scan_driver::sim::VirtualPair::projectorOnly(config, empty).factoryCalibration(),
         config.world_from_camera});
  return pairs;
}

TimingGroupList plannedTimingGroups(const body_scan_driver::sim::Rig& rig) {
  return planTimingGroups(rigFactoryGeometry(rig)).groups;
}

TimingGroupList loadTimingGroups(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("timing groups '" + path + "': " + e.what());
  }
  if (!root.IsSequence())
    throw std::runtime_error("timing groups '" + path +
                             "': expected a list of groups, each a list of pair ids, e.g. "
                             "[[pole_a/pair_1, pole_b/pair_3], [pole_c/pair_2]]");
  TimingGroupList groups;
  for (const auto& group : root) {
    if (!group.IsSequence())
      throw std::runtime_error("timing groups '" + path + "': every group must be a list of ids");
    groups.emplace_back();
    for (const auto& id : group) groups.back().push_back(id.as<std::string>());
  }
  return groups;
}

SimulatedScan simulateScan(const body_scan_driver::sim::Rig& rig,
                           const std::shared_ptr<const body_scan_driver::sim::Scene>& scene,
                           const TimingGroupList& groups, uint32_t scan_id,
                           const MergeOptions& merge) {
  std::map<std::string, int> seen;
  for (const auto& group : groups)
    for (const auto& id : group) {
      rig.pair(id);  // throws naming the id if the rig has no such pair
      if (seen[id]++)
        throw std::invalid_argument("timing groups: pair '" + id + "' is in two groups");
    }
  for (const auto& id : rig.pairIds())
    if (!seen.count(id))
      throw std::invalid_argument("timing groups: pair '" + id +
                                  "' is in no group; every rig pair must be triggered once");

  std::vector<body_scan_driver::sim::VirtualPair> projectors;
  projectors.reserve(rig.pairs.size());
  for (const auto& config : rig.pairs)
    projectors.push_back(body_scan_driver::sim::VirtualPair::projectorOnly(config, scene));
  auto projector = [&](const std::string& id) -> const body_scan_driver::sim::VirtualPair* {
    for (const auto& p : projectors)
      if (p.config().pair_id == id) return &p;
    return nullptr;
  };

  // Each pair's organized cloud (x y z, NaN = none), kept until the merge, in rig order.
  std::map<std::string, std::vector<float>> clouds;
  for (const auto& group : groups) {
    std::vector<const body_scan_driver::sim::VirtualPair*> members;
    for (const auto& id : group) members.push_back(projector(id));
    for (const auto& id : group) {
      const body_scan_driver::sim::VirtualPair pair(rig.pair(id), scene);
      std::vector<const body_scan_driver::sim::VirtualPair*> others;
      for (const auto* m : members)
        if (m->config().pair_id != id) others.push_back(m);
      const body_scan_driver::sim::RenderedPatternSet set = pair.render(scan_id, others);
      body_scan_driver::StripeImage decoded;
      body_scan_driver::StripeDecoder(pair.layout()).decode(set.frames, decoded);
      std::vector<float>& xyz = clouds[id];
      xyz.resize(3 * decoded.coordinate.total());
      body_scan_driver::Triangulator(pair.factoryCalibration())
          .triangulate(decoded.coordinate, xyz.data(), 3);
    }
  }
  std::vector<CloudView> views;
  for (const auto& config : rig.pairs) {
    const std::vector<float>& xyz = clouds.at(config.pair_id);
    views.push_back(CloudView{xyz.data(), xyz.size() / 3, 3, -1, config.world_from_camera});
  }
  SimulatedScan scan;
  scan.cloud = mergeClouds(views, merge);
  for (size_t i = 0; i < rig.pairs.size(); ++i)
    scan.per_pair.emplace_back(rig.pairs[i].pair_id, scan.cloud.valid_per_part[i]);
  return scan;
}

}  // namespace body_scan_merge
