#include <body_scan_driver/pair_device.h>
#include <body_scan_driver/sim/virtual_pair.h>

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

}  // namespace

std::unique_ptr<PairDevice> makeSimulatedPair(const std::string& pair_file,
                                              const std::string& scene_file) {
  auto scene = std::make_shared<sim::Scene>(sim::loadScene(scene_file));
  return std::make_unique<SimulatedPairDevice>(
      sim::VirtualPair(sim::loadVirtualPairConfig(pair_file), std::move(scene)));
}

}  // namespace body_scan
