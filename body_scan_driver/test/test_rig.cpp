// The rig file (rig_layout.h, sim/rig.h) and interference between the pairs of a rig (thesis
// 4.3, Fig 4.7).
#include <body_scan_driver/rig_layout.h>
#include <body_scan_driver/sim/decoding_errors.h>
#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/tools/package_file.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>

using namespace body_scan_driver;

namespace {

const std::string kConfigDir = body_scan_driver::tools::packageDir("body_scan_driver") + "/config";

std::string writeRig(const std::string& text) {
  const std::string path = std::filesystem::temp_directory_path() /
                           ("body_scan_test_rig_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << text;
  return path;
}

std::string loadError(const std::string& text) {
  try {
    sim::loadRig(writeRig(text));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

// The product's reader (no simulator) sees the simulator's pairs in the same order and poses,
// and accepts the simulator's and the hardware's keys it leaves to their readers.
TEST(Rig, TheLayoutIsTheSimulatorRigsIdsAndPoses) {
  const RigLayout layout = loadRigLayout(kConfigDir + "/rigs/thesis_rig.yaml");
  const sim::Rig rig = sim::loadRig(kConfigDir + "/rigs/thesis_rig.yaml");
  EXPECT_EQ(layout.name, rig.name);
  EXPECT_EQ(layout.poles, rig.poles);
  ASSERT_EQ(layout.pairIds(), rig.pairIds());
  for (size_t i = 0; i < layout.pairs.size(); ++i)
    EXPECT_TRUE(layout.pairs[i].world_from_camera.isApprox(rig.pairs[i].world_from_camera, 0))
        << layout.pairs[i].pair_id;
  const RigLayout with_device = loadRigLayout(
      writeRig("pair_defaults: {sensor: {noise_sigma: 1}}\npoles: [{name: a, position: [1, 0], "
               "pairs: [{name: p, height: 1.2, seed: 7, device: {camera_serial: X}}]}]"));
  EXPECT_EQ(with_device.pairIds(), std::vector<std::string>{"a/p"});
  try {
    loadRigLayout(writeRig("poles: [{name: a, position: [1, 0], pairs: [{name: p, hieght: 1}]}]"));
    ADD_FAILURE() << "a typo was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'hieght'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(layout.pair("pole_z/pair_1"), std::invalid_argument);
}

// A pair file's pose without the simulator: the pose the virtual pair is placed with, bit for bit.
TEST(Rig, PairFilePoseIsTheVirtualPairsPose) {
  const std::string shipped = kConfigDir + "/pairs/default_pair.yaml";
  EXPECT_TRUE(
      loadPairFilePose(shipped).isApprox(sim::loadVirtualPairConfig(shipped).world_from_camera, 0));
  const std::string posed = writeRig("pair_id: a/p\npose: {position: [1, 2, 1.5], yaw_deg: 90}\n");
  EXPECT_TRUE(
      loadPairFilePose(posed).isApprox(sim::loadVirtualPairConfig(posed).world_from_camera, 0));
  EXPECT_TRUE(loadPairFilePose(writeRig("pair_id: a/p\n")).isApprox(Eigen::Isometry3d::Identity()));
  try {
    loadPairFilePose(writeRig("pose: {position: [1, 2, 1.5], yaw: 90}\n"));
    ADD_FAILURE() << "a typo was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'yaw'"), std::string::npos) << e.what();
  }
}

TEST(Rig, TheDefaultRigHasThreePolesOfFourPairsLookingAtTheSubject) {
  const sim::Rig rig = sim::loadRig(kConfigDir + "/rigs/thesis_rig.yaml");
  ASSERT_EQ(rig.pairs.size(), 12u);
  EXPECT_EQ(rig.poles, (std::vector<std::string>{"pole_a", "pole_b", "pole_c"}));
  EXPECT_EQ(rig.pairs.front().pair_id, "pole_a/pair_1");
  EXPECT_EQ(rig.pairs.back().pair_id, "pole_c/pair_4");
  double min_x = 1e9, max_x = -1e9, min_y = 1e9, max_y = -1e9;
  for (const sim::VirtualPairConfig& pair : rig.pairs) {
    const Eigen::Vector3d position = pair.world_from_camera.translation();
    const Eigen::Vector3d axis = pair.world_from_camera.linear().col(2);  // optical axis
    // About 1 m from the subject's axis, looking at it (horizontally within 3 degrees).
    const double distance = position.head<2>().norm();
    EXPECT_GT(distance, 0.9) << pair.pair_id;
    EXPECT_LT(distance, 1.2) << pair.pair_id;
    const Eigen::Vector2d toward = -position.head<2>().normalized();
    EXPECT_GT(axis.head<2>().normalized().dot(toward), std::cos(3 * M_PI / 180)) << pair.pair_id;
    min_x = std::min(min_x, position.x()), max_x = std::max(max_x, position.x());
    min_y = std::min(min_y, position.y()), max_y = std::max(max_y, position.y());
  }
  // Footprint about 1200 x 2000 mm (thesis ch. 4).
  EXPECT_NEAR(max_y - min_y, 1.2, 0.15);
  EXPECT_NEAR(max_x - min_x, 1.9, 0.2);
  // Pairs stacked head to toe, pair_1 on top.
  EXPECT_GT(rig.pair("pole_b/pair_1").world_from_camera.translation().z(),
            rig.pair("pole_b/pair_4").world_from_camera.translation().z() + 1.0);
}

TEST(Rig, BadRigFilesNameTheProblem) {
  EXPECT_NE(loadError("poles: []").find("non-empty list of poles"), std::string::npos);
  EXPECT_NE(loadError("poles: [{name: a, position: [1, 0], pairs: [{name: p}]}]").find("'height'"),
            std::string::npos);
  EXPECT_NE(
      loadError("poles: [{name: a, position: [1, 0], pairs: [{name: p, height: 1, tilt: 3}]}]")
          .find("unknown key 'tilt'"),
      std::string::npos);
  EXPECT_NE(loadError("poles: [{name: a, position: [1, 0, 0], pairs: [{name: p, height: 1}]}]")
                .find("[x, y]"),
            std::string::npos);
  EXPECT_NE(loadError("poles: [{name: a, position: [1, 0], pairs: [{name: p, height: 1}, "
                      "{name: p, height: 2}]}]")
                .find("repeats"),
            std::string::npos);
  EXPECT_NE(loadError("pair_defaults: {camera: {focal: 3}}\npoles: []").find("'focal'"),
            std::string::npos);
  const sim::Rig rig = sim::loadRig(kConfigDir + "/rigs/thesis_rig.yaml");
  try {
    rig.pair("pole_z/pair_9");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pole_a/pair_1"), std::string::npos) << e.what();
  }
}

TEST(Rig, PairDefaultsApplyToEveryPair) {
  const sim::Rig rig = sim::loadRig(
      writeRig("pair_defaults: {camera: {alpha: 700, beta: 700}, sensor: {noise_sigma: 0}}\n"
               "poles: [{name: a, position: [1, 0], pairs: [{name: p, height: 1.2, seed: 7}]}]"));
  ASSERT_EQ(rig.pairs.size(), 1u);
  EXPECT_EQ(rig.pairs[0].camera.alpha, 700);
  EXPECT_EQ(rig.pairs[0].sensor.noise_sigma, 0);
  EXPECT_EQ(rig.pairs[0].sensor.seed, 7u);
  EXPECT_NEAR(rig.pairs[0].world_from_camera.translation().z(), 1.2, 1e-12);
}

// A pair's device map names real hardware (the usb backend's); the simulator reads past it.
TEST(Rig, APairsDeviceMapIsAcceptedAndLeavesTheSimulatedPairAsItIs) {
  const std::string pair = "{name: p, height: 1.2, seed: 7";
  const sim::Rig plain =
      sim::loadRig(writeRig("poles: [{name: a, position: [1, 0], pairs: [" + pair + "}]}]"));
  const sim::Rig with_device =
      sim::loadRig(writeRig("poles: [{name: a, position: [1, 0], pairs: [" + pair +
                            ", device: {camera_id: \"046d:0825\", camera_serial: A1}}]}]"));
  ASSERT_EQ(with_device.pairs.size(), 1u);
  EXPECT_TRUE(with_device.pairs[0].world_from_camera.isApprox(plain.pairs[0].world_from_camera));
  EXPECT_EQ(with_device.pairs[0].sensor.seed, plain.pairs[0].sensor.seed);
}

// All 12 pairs projecting at once: other pairs' stripes corrupt a pair's decoding wherever
// their light falls on what it sees; alone, it decodes cleanly. A pair whose view the other's
// light cannot reach is unaffected (frames bit-identical).
TEST(Rig, OtherPairsLightCorruptsDecodingOnlyWhereItReaches) {
  const sim::Rig rig = sim::loadRig(kConfigDir + "/rigs/thesis_rig.yaml");
  auto scene =
      std::make_shared<sim::Scene>(sim::loadScene(kConfigDir + "/scenes/standing_person.yaml"));
  std::vector<sim::VirtualPair> others;
  for (const auto& config : rig.pairs)
    others.push_back(sim::VirtualPair::projectorOnly(config, scene));
  std::vector<const sim::VirtualPair*> all;
  for (const auto& other : others) all.push_back(&other);

  for (const char* id : {"pole_a/pair_2", "pole_c/pair_3"}) {
    const sim::VirtualPair pair(rig.pair(id), scene);
    const auto start = std::chrono::steady_clock::now();
    const double alone = sim::wrongStripeFraction(pair.render(1), *scene, pair.layout());
    const auto middle = std::chrono::steady_clock::now();
    const double together = sim::wrongStripeFraction(pair.render(1, all), *scene, pair.layout());
    const auto end = std::chrono::steady_clock::now();
    std::cout << "[ figure ] " << id << ": wrong stripes on the person alone " << 100 * alone
              << " %, with all 12 pairs projecting " << 100 * together << " % (render "
              << std::chrono::duration<double, std::milli>(middle - start).count() << " / "
              << std::chrono::duration<double, std::milli>(end - middle).count() << " ms)\n";
    EXPECT_LT(alone, 0.002) << id;
    EXPECT_GT(together, 0.02) << id;
  }

  // The back pole's bottom pair lights the back of the legs: the front-left top pair never
  // sees it, so its frames do not change at all.
  const sim::VirtualPair front_top(rig.pair("pole_a/pair_1"), scene);
  const sim::VirtualPair back_bottom =
      sim::VirtualPair::projectorOnly(rig.pair("pole_c/pair_4"), scene);
  const auto alone = front_top.render(3);
  const auto with_back = front_top.render(3, {&back_bottom});
  int changed = 0;
  for (size_t f = 0; f < alone.frames.size(); ++f)
    changed += cv::countNonZero(alone.frames[f] != with_back.frames[f]);
  EXPECT_EQ(changed, 0);
}
