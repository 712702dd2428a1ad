#include <body_scan_driver/pair_device.h>
#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/sim/virtual_pair.h>

#include <map>

namespace body_scan {
namespace {

class SimulatedPairDevice : public PairDevice {
 public:
  explicit SimulatedPairDevice(sim::VirtualPair pair) : pair_(std::move(pair)) {}

  PatternCapture capture(uint32_t scan_id) override {
    sim::RenderedPatternSet rendered = pair_.render(scan_id);
    return {std::move(rendered.frames), std::move(rendered.texture)};
  }
  const PatternLayout& layout() const override { return pair_.layout(); }
  PinholeCamera camera() const override { return pair_.config().camera; }
  std::optional<PairCalibration> factoryCalibration() const override {
    return pair_.factoryCalibration();
  }
  std::optional<Eigen::Isometry3d> factoryPose() const override {
    return pair_.config().world_from_camera;
  }
  void replaceScene(const std::string& scene_yaml) override {
    // Parse first: a bad scene leaves the current one in place.
    auto scene = std::make_shared<sim::Scene>(sim::parseScene(scene_yaml));
    pair_ = sim::VirtualPair(pair_.config(), std::move(scene));
  }
  DeviceStatus status() const override {
    DeviceStatus status;
    status.hardware_id = "simulator " + pair_.config().pair_id;
    status.state = "STREAMING";
    status.message = "simulated pair: always available";
    return status;
  }

 private:
  sim::VirtualPair pair_;
};

// A pair of a simulated rig. The other pairs are built when first named active (each holds its
// camera rays and noise table: ~8 MB) and rebuilt with the scene.
class SimulatedRigPairDevice : public PairDevice {
 public:
  SimulatedRigPairDevice(sim::Rig rig, const std::string& pair_id,
                         std::shared_ptr<const sim::Scene> scene)
      : rig_(std::move(rig)), scene_(std::move(scene)), pair_(rig_.pair(pair_id), scene_) {}

  PatternCapture capture(uint32_t scan_id) override {
    std::vector<const sim::VirtualPair*> active;
    for (const std::string& id : active_ids_) active.push_back(&other(id));
    sim::RenderedPatternSet rendered = pair_.render(scan_id, active);
    return {std::move(rendered.frames), std::move(rendered.texture)};
  }
  void setActivePairs(const std::vector<std::string>& pair_ids) override {
    std::vector<std::string> ids;
    for (const std::string& id : pair_ids) {
      rig_.pair(id);  // throws naming the known ids
      if (id != pair_.config().pair_id) ids.push_back(id);
    }
    active_ids_ = std::move(ids);
  }
  const PatternLayout& layout() const override { return pair_.layout(); }
  PinholeCamera camera() const override { return pair_.config().camera; }
  std::optional<PairCalibration> factoryCalibration() const override {
    return pair_.factoryCalibration();
  }
  std::optional<Eigen::Isometry3d> factoryPose() const override {
    return pair_.config().world_from_camera;
  }
  void replaceScene(const std::string& scene_yaml) override {
    // Parse first: a bad scene leaves the current one in place.
    scene_ = std::make_shared<sim::Scene>(sim::parseScene(scene_yaml));
    pair_ = sim::VirtualPair(pair_.config(), scene_);
    others_.clear();
  }
  DeviceStatus status() const override {
    DeviceStatus status;
    status.hardware_id = "simulator " + pair_.config().pair_id + " of rig " + rig_.name;
    status.state = "STREAMING";
    status.message = "simulated rig pair: always available";
    return status;
  }

 private:
  const sim::VirtualPair& other(const std::string& id) {
    auto found = others_.find(id);
    if (found == others_.end())
      found = others_.emplace(id, std::make_unique<sim::VirtualPair>(rig_.pair(id), scene_)).first;
    return *found->second;
  }

  sim::Rig rig_;
  std::shared_ptr<const sim::Scene> scene_;
  sim::VirtualPair pair_;
  std::map<std::string, std::unique_ptr<sim::VirtualPair>> others_;
  std::vector<std::string> active_ids_;
};

}  // namespace

std::unique_ptr<PairDevice> makeSimulatedRigPair(const std::string& rig_file,
                                                 const std::string& pair_id,
                                                 const std::string& scene_file) {
  sim::Rig rig = sim::loadRig(rig_file);
  try {
    rig.pair(pair_id);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(rig_file + ": " + e.what() + " (set pair_id to one of them)");
  }
  auto scene = std::make_shared<sim::Scene>(sim::loadScene(scene_file));
  return std::make_unique<SimulatedRigPairDevice>(std::move(rig), pair_id, std::move(scene));
}

std::unique_ptr<PairDevice> makeSimulatedPair(const std::string& pair_file,
                                              const std::string& scene_file) {
  auto scene = std::make_shared<sim::Scene>(sim::loadScene(scene_file));
  return std::make_unique<SimulatedPairDevice>(
      sim::VirtualPair(sim::loadVirtualPairConfig(pair_file), std::move(scene)));
}

}  // namespace body_scan
