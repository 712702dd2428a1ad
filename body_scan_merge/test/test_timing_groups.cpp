// Timing groups (thesis 4.3, Fig 4.7): conflicts from the calibrated geometry, a minimum
// colouring, and - measured with the simulator - that the computed groups do not corrupt any
// pair's decoding while all 12 pairs at once do.
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/decoding_errors.h>
#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_merge/simulated_scan.h>
#include <body_scan_merge/timing_groups.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace body_scan_merge;
using namespace body_scan_driver;

namespace {

const std::string kDriverConfig = body_scan_driver::sim::driverConfigDir();

std::vector<PairGeometry> geometryOf(
    const std::vector<body_scan_driver::sim::VirtualPairConfig>& configs) {
  body_scan_driver::sim::Rig rig;
  rig.pairs = configs;
  return rigFactoryGeometry(rig);
}

body_scan_driver::sim::VirtualPairConfig pairAt(const std::string& id,
                                                const Eigen::Vector3d& position) {
  body_scan_driver::sim::VirtualPairConfig config;
  config.pair_id = id;
  config.world_from_camera =
      body_scan_driver::sim::cameraPose(position, std::atan2(-position.y(), -position.x()), 0.0);
  return config;
}

int chromaticNumberByBruteForce(const std::vector<std::vector<bool>>& graph) {
  const int n = static_cast<int>(graph.size());
  for (int k = 1; k <= n; ++k) {
    std::vector<int> colour(n, 0);
    while (true) {
      bool ok = true;
      for (int a = 0; a < n && ok; ++a)
        for (int b = a + 1; b < n && ok; ++b)
          ok = !((graph[a][b] || graph[b][a]) && colour[a] == colour[b]);
      if (ok) return k;
      int i = 0;
      while (i < n && ++colour[i] == k) colour[i++] = 0;
      if (i == n) break;
    }
  }
  return n;
}

// The least sum of squared group sizes over every colouring with k colours.
int mostBalancedSquares(const std::vector<std::vector<bool>>& graph, int k) {
  const int n = static_cast<int>(graph.size());
  std::vector<int> colour(n, 0);
  int best = n * n + 1;
  while (true) {
    bool ok = true;
    for (int a = 0; a < n && ok; ++a)
      for (int b = a + 1; b < n && ok; ++b)
        ok = !((graph[a][b] || graph[b][a]) && colour[a] == colour[b]);
    if (ok) {
      std::vector<int> sizes(k, 0);
      for (int c : colour) ++sizes[c];
      int squares = 0;
      for (int size : sizes) squares += size * size;
      best = std::min(best, squares);
    }
    int i = 0;
    while (i < n && ++colour[i] == k) colour[i++] = 0;
    if (i == n) break;
  }
  return best;
}

}  // namespace

TEST(TimingGroups, ThreePairsAroundTheSubjectFormATriangle) {
  // 120 degrees apart: each pair lights about 160 degrees of the torso and sees as much, so
  // every pair's light reaches both other views: three groups.
  const auto pairs = geometryOf({pairAt("p0", {1.0, 0, 1.2}), pairAt("p1", {-0.5, 0.866, 1.2}),
                                 pairAt("p2", {-0.5, -0.866, 1.2})});
  InterferenceProxy torso;
  torso.parts = {{0, 0, 0.18, 0.18, 0.6, 1.8}};
  const auto conflicts = lightConflicts(pairs, torso);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j) {
        EXPECT_TRUE(conflicts[i][j]) << i << " -> " << j;
      }
  EXPECT_EQ(planTimingGroups(pairs, torso).groups.size(), 3u);
}

TEST(TimingGroups, TheLightMarginGrowsTheSweep) {
  // One above the other on the same spot: the top pair's sweep (4 deg above to 36 deg below
  // its camera's axis, from 0.33 m above it) ends about 0.7 m above what the low camera sees.
  const auto pairs = geometryOf({pairAt("top", {1.0, 0, 1.8}), pairAt("low", {1.0, 0, 0.5})});
  InterferenceProxy torso;
  torso.parts = {{0, 0, 0.15, 0.2, 0.0, 2.0}};
  torso.light_margin = 0;
  EXPECT_FALSE(lightConflicts(pairs, torso)[0][1]);
  torso.light_margin = 1.0;  // the sweep reaches about 1 m further down
  EXPECT_TRUE(lightConflicts(pairs, torso)[0][1]);
}

TEST(TimingGroups, TheMinimumColouringIsTheMostBalanced) {
  // Only 0-1 conflict: {0 2} {1 3}, not {0 2 3} {1}.
  std::vector<std::vector<bool>> graph(4, std::vector<bool>(4, false));
  graph[0][1] = true;
  EXPECT_EQ(minimumGroups(graph), (std::vector<std::vector<int>>{{0, 2}, {1, 3}}));
  std::mt19937 generator(11);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 3 + trial % 5;
    std::bernoulli_distribution edge(0.15 + 0.01 * trial);
    graph.assign(n, std::vector<bool>(n, false));
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) graph[a][b] = a != b && edge(generator);
    const auto groups = minimumGroups(graph);
    int squares = 0;
    for (const auto& group : groups) squares += group.size() * group.size();
    EXPECT_EQ(squares, mostBalancedSquares(graph, groups.size())) << trial;
  }
}

TEST(TimingGroups, PairsFacingEachOtherDoNotConflictPairsSideBySideDo) {
  const auto pairs = geometryOf({pairAt("front", {1.0, 0, 1.2}), pairAt("back", {-1.0, 0, 1.2}),
                                 pairAt("front_left", {0.97, 0.26, 1.2})});
  InterferenceProxy torso;  // one convex surface: no gaps for grazing light
  torso.parts = {{0, 0, 0.15, 0.2, 0.6, 1.8}};
  const auto conflicts = lightConflicts(pairs, torso);
  EXPECT_FALSE(conflicts[0][1]);
  EXPECT_FALSE(conflicts[1][0]);
  EXPECT_TRUE(conflicts[0][2]);
  EXPECT_TRUE(conflicts[2][0]);
  const TimingPlan plan = planTimingGroups(pairs, torso);
  ASSERT_EQ(plan.groups.size(), 2u);
  EXPECT_EQ(plan.groups[0], (std::vector<std::string>{"front", "back"}));
}

// Thesis sec. 4.2.4: 0.5 s per group; the period follows the pattern and the camera.
TEST(TimingGroups, TheGroupPeriodIsThePatternFramesAtTheCameraRate) {
  EXPECT_DOUBLE_EQ(GroupTiming{}.seconds(), 0.5);
  EXPECT_DOUBLE_EQ((GroupTiming{18, 30, 2}.seconds()), 1.8);  // usb pair: 30 Hz, 2 settle frames
  EXPECT_DOUBLE_EQ((GroupTiming{10, 30, 0}.seconds()), 1.0 / 3);  // 8 bits, no inverse frames
  for (const GroupTiming bad : {GroupTiming{0, 30, 0}, GroupTiming{18, 0, 0},
                                GroupTiming{18, std::nan(""), 0}, GroupTiming{18, 30, -1}}) {
    try {
      bad.seconds();
      ADD_FAILURE() << "accepted " << bad.pattern_frames << " " << bad.camera_fps << " "
                    << bad.settle_frames;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("must"), std::string::npos) << e.what();
    }
  }
}

// The top of the head: two pairs facing each other above the subject both light and see it
// (the sides each sees are the other's shadow side); at eye level neither sees the top.
TEST(TimingGroups, PairsLookingDownShareTheTopOfTheHead) {
  InterferenceProxy head;
  head.parts = {{0, 0, 0.10, 0.09, 1.45, 1.95}};
  head.floor_radius = 0;
  auto facing = [&](double height, double pitch_deg) {
    std::vector<PairGeometry> pairs =
        geometryOf({pairAt("front", {1.0, 0, height}), pairAt("back", {-1.0, 0, height})});
    pairs[0].world_from_camera =
        body_scan_driver::sim::cameraPose({1.0, 0, height}, M_PI, pitch_deg * M_PI / 180);
    pairs[1].world_from_camera =
        body_scan_driver::sim::cameraPose({-1.0, 0, height}, 0, pitch_deg * M_PI / 180);
    return lightConflicts(pairs, head);
  };
  const auto above = facing(2.6, 35), level = facing(1.7, 0);
  EXPECT_TRUE(above[0][1]);
  EXPECT_TRUE(above[1][0]);
  EXPECT_FALSE(level[0][1]);
  EXPECT_FALSE(level[1][0]);
}

TEST(TimingGroups, TheColouringIsMinimal) {
  std::mt19937 generator(5);
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 3 + trial % 6;
    std::bernoulli_distribution edge(0.2 + 0.01 * trial);
    std::vector<std::vector<bool>> graph(n, std::vector<bool>(n, false));
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) graph[a][b] = a != b && edge(generator);
    const auto groups = minimumGroups(graph);
    ASSERT_EQ(static_cast<int>(groups.size()), chromaticNumberByBruteForce(graph)) << trial;
    for (const auto& group : groups)
      for (int a : group)
        for (int b : group) ASSERT_FALSE(graph[a][b]) << "conflicting pairs share a group";
  }
}

// The default rig with the default subject: the computed groups keep every pair's decoding as
// clean as when it projects alone; all 12 pairs at once corrupt it.
TEST(TimingGroups, TheComputedGroupsOfTheDefaultRigDoNotInterfere) {
  const body_scan_driver::sim::Rig rig =
      body_scan_driver::sim::loadRig(kDriverConfig + "/rigs/thesis_rig.yaml");
  const TimingPlan plan = planTimingGroups(geometryOf(rig.pairs));
  std::cout << "[ figure ] default rig: " << plan.groups.size() << " timing groups (thesis: 4),"
            << " simulated acquisition " << 0.5 * plan.groups.size() << " s:";
  for (const auto& group : plan.groups) {
    std::cout << " {";
    for (const auto& id : group) std::cout << " " << id;
    std::cout << " }";
  }
  std::cout << "\n";
  // The three poles light each other's views at every height: at least 3 groups; fewer than
  // one group per pair.
  EXPECT_GE(plan.groups.size(), 3u);
  EXPECT_LT(plan.groups.size(), rig.pairs.size());

  auto scene = std::make_shared<body_scan_driver::sim::Scene>(
      body_scan_driver::sim::loadScene(kDriverConfig + "/scenes/standing_person.yaml"));
  std::vector<body_scan_driver::sim::VirtualPair> projectors;
  for (const auto& config : rig.pairs)
    projectors.push_back(body_scan_driver::sim::VirtualPair::projectorOnly(config, scene));
  auto projector = [&](const std::string& id) {
    for (const auto& p : projectors)
      if (p.config().pair_id == id) return &p;
    throw std::logic_error(id);
  };
  std::vector<const body_scan_driver::sim::VirtualPair*> everyone;
  for (const auto& p : projectors) everyone.push_back(&p);

  auto wrong = [&](const body_scan_driver::sim::VirtualPair& pair,
                   const std::vector<const body_scan_driver::sim::VirtualPair*>& others) {
    return body_scan_driver::sim::wrongStripeFraction(pair.render(1, others), *scene,
                                                      pair.layout());
  };
  double worst_grouped = 0, worst_alone = 0, worst_all = 0;
  for (const auto& group : plan.groups)
    for (const auto& id : group) {
      const body_scan_driver::sim::VirtualPair pair(rig.pair(id), scene);
      std::vector<const body_scan_driver::sim::VirtualPair*> members;
      for (const auto& other : group) members.push_back(projector(other));
      const double grouped = wrong(pair, members), alone = wrong(pair, {});
      worst_grouped = std::max(worst_grouped, grouped);
      worst_alone = std::max(worst_alone, alone);
      EXPECT_LE(grouped, alone + 0.0002) << id << " is disturbed by its group";
      if (id == "pole_a/pair_2" || id == "pole_b/pair_3")
        worst_all = std::max(worst_all, wrong(pair, everyone));
    }
  std::cout << "[ figure ] wrong stripes on the person, worst pair: alone " << 100 * worst_alone
            << " %, in its timing group " << 100 * worst_grouped << " %, all 12 at once "
            << 100 * worst_all << " %\n";
  EXPECT_GT(worst_all, 0.05);
}

// The computed conflicts against the simulator: which pairs' light changes pole_a/pair_1's
// decoding of the person (stripe more than 1 off, or lost / gained) in more than 100 pixels when
// it projects together with it. Pairs whose light never reaches the person in its view flip a
// few dozen pixels at most (the sensor noise meets slightly different levels). Floor pixels are
// not counted: pole_a/pair_1 sees the floor only beyond the proxy's floor disc (more than 1.6 m
// from the subject), where pairs 4 of poles a and b change 5 382 and 1 103 of them.
TEST(TimingGroups, TheConflictsIntoOnePairsViewMatchTheSimulator) {
  const body_scan_driver::sim::Rig rig =
      body_scan_driver::sim::loadRig(kDriverConfig + "/rigs/thesis_rig.yaml");
  const auto conflicts = lightConflicts(geometryOf(rig.pairs));
  auto scene = std::make_shared<body_scan_driver::sim::Scene>(
      body_scan_driver::sim::loadScene(kDriverConfig + "/scenes/standing_person.yaml"));
  const int seer = 0;  // pole_a/pair_1
  const body_scan_driver::sim::VirtualPair pair(rig.pairs[seer], scene);
  std::vector<std::pair<int, int>> person;  // (v, u) of the pixels that see the person
  auto decode = [&](const std::vector<const body_scan_driver::sim::VirtualPair*>& others) {
    const body_scan_driver::sim::RenderedPatternSet set = pair.render(1, others);
    body_scan_driver::StripeImage decoded;
    body_scan_driver::StripeDecoder(pair.layout()).decode(set.frames, decoded);
    if (person.empty())
      for (int v = 0; v < set.truth.surface.rows; ++v)
        for (int u = 0; u < set.truth.surface.cols; ++u) {
          const int surface = set.truth.surface(v, u);
          if (surface >= 0 && scene->surfaces()[surface]->name.rfind("person/", 0) == 0)
            person.emplace_back(v, u);
        }
    return decoded.coordinate.clone();
  };
  const cv::Mat1f alone = decode({});
  for (size_t i = 0; i < rig.pairs.size(); ++i) {
    if (static_cast<int>(i) == seer) continue;
    const auto other = body_scan_driver::sim::VirtualPair::projectorOnly(rig.pairs[i], scene);
    const cv::Mat1f with = decode({&other});
    int pixels = 0;
    for (const auto& [v, u] : person) {
      const float a = alone(v, u), b = with(v, u);
      pixels += std::isnan(a) != std::isnan(b) || (!std::isnan(a) && std::abs(a - b) > 1.f);
    }
    std::cout << "[ figure ] " << rig.pairs[i].pair_id << " -> pole_a/pair_1: " << pixels << " of "
              << person.size() << " person pixels changed, computed conflict " << conflicts[i][seer]
              << "\n";
    EXPECT_EQ(conflicts[i][seer], pixels > 100) << rig.pairs[i].pair_id << ": " << pixels;
  }
}
