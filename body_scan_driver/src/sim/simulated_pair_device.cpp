#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/sim/simulated_pair_device.h>
#include <body_scan_driver/sim/virtual_pair.h>

#include <algorithm>
#include <mutex>

namespace body_scan_driver::sim {
namespace {

// A simulated pair; with a rig, also the projectors of the rig's other pairs (interference).
class RenderedPairDevice : public SimulatedPairDevice {
 public:
  RenderedPairDevice(VirtualPairConfig config, std::vector<VirtualPairConfig> others,
                     std::shared_ptr<const Scene> scene)
      : pair_(std::move(config), scene), other_configs_(std::move(others)) {
    buildOthers(scene);
  }

  PatternCapture capture(uint32_t scan_id) override {
    std::vector<const VirtualPair*> active;
    {
      std::lock_guard<std::mutex> lock(active_mutex_);
      for (const std::string& id : active_ids_)
        for (const VirtualPair& other : others_)
          if (other.config().pair_id == id) active.push_back(&other);
    }
    RenderedPatternSet rendered = pair_.render(scan_id, active);
    return {std::move(rendered.frames), std::move(rendered.texture)};
  }
  const PatternLayout& layout() const override { return pair_.layout(); }
  PinholeCamera camera() const override { return pair_.config().camera; }
  PairCalibration factoryCalibration() const override { return pair_.factoryCalibration(); }
  Eigen::Isometry3d factoryPose() const override { return pair_.config().world_from_camera; }
  void replaceScene(const std::string& scene_yaml) override {
    // Parse first: a bad scene leaves the current one in place.
    auto scene = std::make_shared<Scene>(parseScene(scene_yaml));
    pair_ = VirtualPair(pair_.config(), scene);
    buildOthers(scene);
  }
  void setActivePairs(const std::vector<std::string>& pair_ids) override {
    std::vector<std::string> ids;
    for (const std::string& id : pair_ids) {
      if (id == pair_.config().pair_id) continue;  // itself: always active
      const bool known = std::any_of(other_configs_.begin(), other_configs_.end(),
                                     [&](const auto& config) { return config.pair_id == id; });
      if (!known) {
        std::string list;
        for (const auto& config : other_configs_)
          list += (list.empty() ? "" : ", ") + config.pair_id;
        throw std::invalid_argument(
            "active pair '" + id + "' is not in this simulated pair's rig" +
            (list.empty() ? std::string(" (a single pair: start it with ~rig_file to simulate "
                                        "interference)")
                          : "; the rig's other pairs: " + list));
      }
      ids.push_back(id);
    }
    std::lock_guard<std::mutex> lock(active_mutex_);
    active_ids_ = std::move(ids);
  }
  DeviceStatus status() const override {
    DeviceStatus status;
    status.hardware_id = "simulator " + pair_.config().pair_id;
    status.state = "STREAMING";
    status.message = "simulated pair: always available";
    return status;
  }

 private:
  void buildOthers(const std::shared_ptr<const Scene>& scene) {
    others_.clear();
    for (const VirtualPairConfig& config : other_configs_)
      others_.push_back(VirtualPair::projectorOnly(config, scene));
  }

  VirtualPair pair_;
  std::vector<VirtualPairConfig> other_configs_;
  std::vector<VirtualPair> others_;  // projector-only copies of the rig's other pairs
  std::mutex active_mutex_;
  std::vector<std::string> active_ids_;
};

}  // namespace

std::unique_ptr<SimulatedPairDevice> makeSimulatedPair(const std::string& pair_file,
                                                       const std::string& scene_file) {
  auto scene = std::make_shared<Scene>(loadScene(scene_file));
  return std::make_unique<RenderedPairDevice>(loadVirtualPairConfig(pair_file),
                                              std::vector<VirtualPairConfig>{}, std::move(scene));
}

std::unique_ptr<SimulatedPairDevice> makeSimulatedRigPair(const std::string& rig_file,
                                                          const std::string& pair_id,
                                                          const std::string& scene_file) {
  const Rig rig = loadRig(rig_file);
  VirtualPairConfig own = rig.pair(pair_id);
  std::vector<VirtualPairConfig> others;
  for (const VirtualPairConfig& config : rig.pairs)
    if (config.pair_id != pair_id) others.push_back(config);
  auto scene = std::make_shared<Scene>(loadScene(scene_file));
  return std::make_unique<RenderedPairDevice>(std::move(own), std::move(others), std::move(scene));
}

}  // namespace body_scan_driver::sim
