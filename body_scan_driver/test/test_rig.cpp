#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/sim/scene.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>

using namespace body_scan;

namespace {

const std::string kConfigDir = BODY_SCAN_DRIVER_CONFIG_DIR;

// Loads `text` as a rig file; returns the error message ("" when it loaded).
std::string rigError(const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / "body_scan_test_rig.yaml";
  std::ofstream(path) << text;
  std::string message;
  try {
    sim::loadRig(path.string());
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  std::filesystem::remove(path);
  return message;
}

const char* kGoodPole =
    "poles:\n"
    "  - name: pole_a\n"
    "    position: [1, 0]\n"
    "    heading_deg: 180\n"
    "    pairs:\n"
    "      - {name: pair_1, height: 1.5, pitch_deg: 10, seed: 3}\n";

}  // namespace

TEST(Rig, TheThesisRigHasTwelvePairsLookingAtTheSubject) {
  const sim::Rig rig = sim::loadRig(kConfigDir + "/rigs/thesis_rig.yaml");
  EXPECT_EQ(rig.name, "thesis_rig");
  ASSERT_EQ(rig.poles, (std::vector<std::string>{"pole_a", "pole_b", "pole_c"}));
  ASSERT_EQ(rig.pairs.size(), 12u);
  const sim::Scene scene = sim::loadScene(kConfigDir + "/scenes/standing_person.yaml");
  std::set<uint32_t> seeds;
  for (size_t i = 0; i < rig.pairs.size(); ++i) {
    const sim::VirtualPairConfig& pair = rig.pairs[i];
    const std::string id = rig.poles[i / 4] + "/pair_" + std::to_string(i % 4 + 1);
    EXPECT_EQ(pair.pair_id, id);
    EXPECT_EQ(&rig.pair(id), &pair);
    seeds.insert(pair.sensor.seed);
    const Eigen::Vector3d position = pair.world_from_camera.translation();
    const Eigen::Vector3d axis = pair.world_from_camera.linear() * Eigen::Vector3d::UnitZ();
    // About 1 m from the subject axis, looking at it (horizontally within 2 degrees).
    const double distance = position.head<2>().norm();
    EXPECT_GT(distance, 0.9) << id;
    EXPECT_LT(distance, 1.2) << id;
    const double cos_angle = axis.head<2>().normalized().dot(-position.head<2>().normalized());
    EXPECT_GT(cos_angle, std::cos(2 * M_PI / 180)) << id;
    // Image x stays horizontal; the pole's pairs are stacked top to bottom.
    EXPECT_NEAR((pair.world_from_camera.linear() * Eigen::Vector3d::UnitX()).z(), 0, 1e-12);
    if (i % 4 != 0) {
      EXPECT_LT(position.z(), rig.pairs[i - 1].world_from_camera.translation().z());
    }
    // Projector (330 mm above the camera) below the pole's top, 2135 mm.
    const Eigen::Vector3d projector = pair.world_from_camera * pair.projector.mirror_axis_point;
    EXPECT_LT(projector.z(), 2.135) << id;
    // A part of its view (rays on a 32 x 24 grid over the image) is the standing person.
    int on_person = 0, rays = 0;
    for (int v = 10; v < pair.camera.height; v += 20)
      for (int u = 10; u < pair.camera.width; u += 20, ++rays) {
        const Eigen::Vector2d p = pair.camera.normalizedPoint({u, v});
        const Eigen::Vector3d direction =
            pair.world_from_camera.linear() * Eigen::Vector3d(p.x(), p.y(), 1).normalized();
        sim::Hit hit;
        if (scene.intersect(sim::Ray{position, direction}, hit) &&
            scene.surfaces()[hit.surface_index]->name.rfind("person/", 0) == 0)
          ++on_person;
      }
    std::cout << "[ figure ] " << id << ": person in " << 100 * on_person / rays
              << "% of the view\n";
    EXPECT_GT(on_person, rays / 20) << id;  // the feet pair sees the least: ~9%
  }
  EXPECT_EQ(seeds.size(), 12u);  // every pair has its own sensor noise
  // The top pair looks down at the head, the second one up under the chin.
  EXPECT_LT((rig.pair("pole_a/pair_1").world_from_camera.linear() * Eigen::Vector3d::UnitZ()).z(),
            -0.1);
  EXPECT_GT((rig.pair("pole_c/pair_2").world_from_camera.linear() * Eigen::Vector3d::UnitZ()).z(),
            0.1);
  EXPECT_GT(rig.pair("pole_b/pair_1").world_from_camera.translation().z(), 1.7);
  EXPECT_LT(rig.pair("pole_b/pair_4").world_from_camera.translation().z(), 0.5);
  try {
    rig.pair("pole_d/pair_1");
    FAIL() << "unknown pair accepted";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("'pole_d/pair_1'"), std::string::npos) << message;
    EXPECT_NE(message.find("pole_c/pair_4"), std::string::npos) << message;  // known ids listed
  }
}

TEST(Rig, PairDefaultsApplyToEveryPairAndPosesFollowTheFile) {
  const auto path = std::filesystem::temp_directory_path() / "body_scan_test_rig_ok.yaml";
  std::ofstream(path) << "name: small\n"
                         "pair_defaults: {sensor: {noise_sigma: 0.5}, camera: {alpha: 900}}\n"
                      << kGoodPole
                      << "      - {name: pair_2, height: 0.5, pitch_deg: -20, yaw_offset_deg: 90, "
                         "seed: 4}\n";
  const sim::Rig rig = sim::loadRig(path.string());
  std::filesystem::remove(path);
  ASSERT_EQ(rig.pairs.size(), 2u);
  for (const auto& pair : rig.pairs) {
    EXPECT_DOUBLE_EQ(pair.sensor.noise_sigma, 0.5);
    EXPECT_DOUBLE_EQ(pair.camera.alpha, 900);
    EXPECT_DOUBLE_EQ(pair.camera.beta, 810);  // absent keys keep the pair defaults
  }
  EXPECT_EQ(rig.pairs[1].sensor.seed, 4u);
  const Eigen::Isometry3d expected =
      sim::cameraPose({1, 0, 0.5}, (180 + 90) * M_PI / 180, -20 * M_PI / 180);
  EXPECT_TRUE(rig.pairs[1].world_from_camera.isApprox(expected, 1e-12));
}

TEST(Rig, BadFilesNameTheFileAndTheKey) {
  const std::string file = "body_scan_test_rig.yaml";
  struct Case {
    std::string text, expected;
  };
  const std::vector<Case> cases = {
      {"name: r\n" + std::string(kGoodPole) + "    colour: red\n", "unknown key 'colour'"},
      {"name: r\npair_defaults: {sensor: {noise_sgima: 1}}\n" + std::string(kGoodPole),
       "pair_defaults: sensor: unknown key 'noise_sgima'"},
      {"name: r\npair_defaults: {pose: {yaw_deg: 3}}\n" + std::string(kGoodPole),
       "pair_defaults: unknown key 'pose'"},
      {"name: r\npoles: []\n", "'poles' must be a non-empty list"},
      {"name: r\n", "missing key 'poles'"},
      {std::string(kGoodPole), "missing key 'name'"},
      {"name: r\npoles:\n  - {name: pole_a, position: [1, 0, 0], heading_deg: 0, pairs: []}\n",
       "poles[0] (pole_a): 'position' must be [x, y]"},
      {"name: r\npoles:\n  - {name: pole_a, position: [1, 0], pairs: []}\n",
       "poles[0] (pole_a): missing key 'heading_deg'"},
      {"name: r\npoles:\n  - {name: pole_a, position: [1, 0], heading_deg: x, pairs: [{}]}\n",
       "'heading_deg' has the wrong type"},
      {"name: r\n" + std::string(kGoodPole) + "      - {name: pair_2, pitch_deg: 0, seed: 1}\n",
       "pairs[1] (pole_a/pair_2): missing key 'height'"},
      {"name: r\n" + std::string(kGoodPole) +
           "      - {name: pair_1, height: 1, pitch_deg: 0, seed: 1}\n",
       "pairs[1] (pole_a/pair_1): duplicate pair name"},
      {"name: r\n" + std::string(kGoodPole) + "      - {name: a/b, height: 1, pitch_deg: 0}\n",
       "'name' must be non-empty and without '/'"},
      {"name: r\n" + std::string(kGoodPole) +
           "      - {name: pair_2, height: 1, pitch_deg: 95, seed: 1}\n",
       "'pitch_deg' must be within (-90, 90)"},
      {"name: r\npoles: [\n", "cannot read rig file"},
  };
  for (const Case& c : cases) {
    const std::string message = rigError(c.text);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "file:\n"
                                                           << c.text << "message: " << message;
    EXPECT_NE(message.find(file), std::string::npos) << message;
  }
  EXPECT_EQ(rigError("name: r\n" + std::string(kGoodPole)), "");
}
