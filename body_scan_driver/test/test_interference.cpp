// Light interference between pairs projecting at the same time (thesis 4.3, Fig. 4.7), measured
// with the default rig on the standing person.
#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/stripe_decoder.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <opencv2/core.hpp>
#include <set>
#include <tuple>

using namespace body_scan;

namespace {

struct RigPairs {
  std::vector<std::unique_ptr<sim::VirtualPair>> pairs;
  std::shared_ptr<const sim::Scene> scene;

  RigPairs() {
    const sim::Rig rig = sim::loadRig(BODY_SCAN_DRIVER_CONFIG_DIR "/rigs/thesis_rig.yaml");
    scene = std::make_shared<sim::Scene>(
        sim::loadScene(BODY_SCAN_DRIVER_CONFIG_DIR "/scenes/standing_person.yaml"));
    for (const auto& config : rig.pairs)
      pairs.push_back(std::make_unique<sim::VirtualPair>(config, scene));
  }
  const sim::VirtualPair& operator[](const std::string& id) const {
    for (const auto& pair : pairs)
      if (pair->config().pair_id == id) return *pair;
    throw std::runtime_error("no pair " + id);
  }
  std::vector<const sim::VirtualPair*> allBut(const std::string& id) const {
    std::vector<const sim::VirtualPair*> others;
    for (const auto& pair : pairs)
      if (pair->config().pair_id != id) others.push_back(pair.get());
    return others;
  }
};

const RigPairs& rigPairs() {
  static const RigPairs pairs;
  return pairs;
}

struct Decoded {
  double wrong = 0;    // fraction of person pixels decoded to a stripe off by more than 1
  double missing = 0;  // fraction of lit person pixels not decoded
  int person_pixels = 0;
};

Decoded decodeAgainstTruth(const sim::VirtualPair& pair, const sim::RenderedPatternSet& set,
                           const sim::Scene& scene) {
  StripeImage image;
  StripeDecoder(pair.layout()).decode(set.frames, image);
  Decoded result;
  int wrong = 0, missing = 0;
  for (int v = 0; v < image.coordinate.rows; ++v)
    for (int u = 0; u < image.coordinate.cols; ++u) {
      const int surface = set.truth.surface(v, u);
      const float truth = set.truth.stripe(v, u);
      if (surface < 0 || std::isnan(truth) ||
          scene.surfaces()[surface]->name.rfind("person/", 0) != 0)
        continue;
      ++result.person_pixels;
      const float decoded = image.coordinate(v, u);
      if (std::isnan(decoded))
        ++missing;
      else if (std::abs(decoded - truth) > 1)
        ++wrong;
    }
  result.wrong = static_cast<double>(wrong) / std::max(1, result.person_pixels);
  result.missing = static_cast<double>(missing) / std::max(1, result.person_pixels);
  return result;
}

double milliseconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double, std::milli>(d).count();
}

}  // namespace

TEST(Interference, AllTwelvePairsAtOnceDecodeToWrongStripes) {
  const RigPairs& rig = rigPairs();
  for (const std::string id : {"pole_a/pair_2", "pole_b/pair_3", "pole_c/pair_1"}) {
    const sim::VirtualPair& pair = rig[id];
    auto start = std::chrono::steady_clock::now();
    const sim::RenderedPatternSet alone_set = pair.render(7);
    const double alone_ms = milliseconds(std::chrono::steady_clock::now() - start);
    start = std::chrono::steady_clock::now();
    const sim::RenderedPatternSet all_set = pair.render(7, rig.allBut(id));
    const double all_ms = milliseconds(std::chrono::steady_clock::now() - start);
    const Decoded alone = decodeAgainstTruth(pair, alone_set, *rig.scene);
    const Decoded all = decodeAgainstTruth(pair, all_set, *rig.scene);
    std::cout << "[ figure ] " << id << " (" << alone.person_pixels
              << " lit person pixels): wrong stripes alone " << 100 * alone.wrong
              << "%, with the 11 others " << 100 * all.wrong << "% (undecoded "
              << 100 * alone.missing << "% -> " << 100 * all.missing << "%); render " << alone_ms
              << " ms alone, " << all_ms << " ms with 11 others\n";
    EXPECT_GT(alone.person_pixels, 10000) << id;
    EXPECT_LT(alone.wrong, 0.005) << id;
    EXPECT_GT(all.wrong, 0.02) << id;
    EXPECT_GT(all.wrong, 10 * alone.wrong) << id;
    // Ground truth is still this pair's own light.
    EXPECT_EQ(cv::norm(alone_set.truth.stripe, all_set.truth.stripe, cv::NORM_INF), 0) << id;
  }
}

TEST(Interference, APairWhoseLightCannotReachTheViewChangesNothing) {
  // The back pole's bottom pair lights the backs of the legs; the front-left top pair sees the
  // head and chest from the front. Truth check: none of the points the top pair sees is lit by
  // the bottom pair (its own render's lit points, in the world).
  const RigPairs& rig = rigPairs();
  const sim::VirtualPair& pair = rig["pole_a/pair_1"];
  const sim::VirtualPair& other = rig["pole_c/pair_4"];
  const sim::RenderedPatternSet alone = pair.render(3);
  const sim::RenderedPatternSet with_other = pair.render(3, {&other, &pair});
  for (size_t f = 0; f < alone.frames.size(); ++f)
    EXPECT_EQ(cv::norm(alone.frames[f], with_other.frames[f], cv::NORM_INF), 0) << "frame " << f;
  // Truth: the 2 cm cells of the world the other pair lights (what its camera sees of it) and
  // the cells the top pair sees do not meet.
  auto cells = [](const sim::VirtualPair& p, const sim::RenderedPatternSet& set, bool lit_only) {
    std::set<std::tuple<int, int, int>> result;
    for (int v = 0; v < set.truth.points.rows; ++v)
      for (int u = 0; u < set.truth.points.cols; ++u) {
        const cv::Vec3f c = set.truth.points(v, u);
        if (std::isnan(c[0]) || (lit_only && std::isnan(set.truth.stripe(v, u)))) continue;
        const Eigen::Vector3d w = p.config().world_from_camera * Eigen::Vector3d(c[0], c[1], c[2]);
        result.emplace(std::lround(w.x() / 0.02), std::lround(w.y() / 0.02),
                       std::lround(w.z() / 0.02));
      }
    return result;
  };
  const auto lit = cells(other, other.render(3), true);
  const auto seen = cells(pair, alone, false);
  int shared = 0;
  for (const auto& cell : seen) shared += lit.count(cell);
  std::cout << "[ figure ] pole_c/pair_4 lights " << lit.size() << " cells, pole_a/pair_1 sees "
            << seen.size() << ", shared " << shared << "\n";
  EXPECT_GT(lit.size(), 1000u);
  EXPECT_EQ(shared, 0);
  // And the same pair does disturb a pair that sees the legs from the back.
  const sim::VirtualPair& leg_pair = rig["pole_c/pair_3"];
  const Decoded leg_alone = decodeAgainstTruth(leg_pair, leg_pair.render(3), *rig.scene);
  const Decoded leg_with = decodeAgainstTruth(leg_pair, leg_pair.render(3, {&other}), *rig.scene);
  std::cout << "[ figure ] pole_c/pair_3 wrong stripes alone " << 100 * leg_alone.wrong
            << "%, with pole_c/pair_4 " << 100 * leg_with.wrong << "%\n";
  EXPECT_GT(leg_with.wrong, leg_alone.wrong + 0.01);
}

TEST(Interference, PairsOfAnotherSceneAreRejected) {
  const RigPairs& rig = rigPairs();
  const sim::VirtualPair stranger(rig["pole_b/pair_1"].config(), std::make_shared<sim::Scene>());
  try {
    rig["pole_a/pair_1"].render(0, {&stranger});
    FAIL() << "a pair of another scene was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pole_b/pair_1"), std::string::npos) << e.what();
  }
}
