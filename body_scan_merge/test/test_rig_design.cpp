// Rig design (eval/rig_design.h) on a tiny template: the written rig file is the scored rig, the
// sweep is what the template asks, the search is deterministic and picks by the measured
// figures.
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <body_scan_merge/eval/rig_design.h>
#include <body_scan_merge/simulated_scan.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

using namespace body_scan_merge;
using namespace body_scan_merge::design;

namespace {

RigLayoutChoice thesisLike(int pairs_per_pole) {
  RigLayoutChoice c;
  c.pairs_per_pole = pairs_per_pole;
  c.pole_distance = 1.04;
  c.front_azimuth_deg = 35;
  if (pairs_per_pole == 4) {
    c.heights = {1.85, 1.15, 0.72, 0.30};
    c.pitches_deg = {18, -8, 0, 8};
  } else {
    c.heights = {1.7, 0.6};
    c.pitches_deg = {15, 0};
  }
  return c;
}

// Degrees between the first and the last calibrated stripe plane of a pair.
double calibratedSweepDeg(const body_scan_driver::sim::VirtualPairConfig& config) {
  const auto calibration = body_scan_driver::sim::VirtualPair::projectorOnly(
                               config, std::make_shared<body_scan_driver::sim::Scene>())
                               .factoryCalibration();
  const auto& planes = calibration.projector.planes;
  const Eigen::Vector3d first = planes.front().head<3>().normalized();
  const Eigen::Vector3d last = planes.back().head<3>().normalized();
  return std::acos(std::min(1.0, std::abs(first.dot(last)))) * 180 / M_PI;
}

}  // namespace

TEST(RigDesign, TheRigFileIsTheThesisRigForTheThesisLayout) {
  // The thesis layout through the design's rig file: the same poses as the shipped rig file
  // (its poles at 1.04 m, +-35 deg: (0.85, +-0.60) within 5 mm; behind at 1.04 m, not 1.05).
  const auto designed = buildRig(thesisLike(4), "designed");
  const auto shipped = body_scan_driver::sim::loadRig(body_scan_driver::sim::driverConfigDir() +
                                                      "/rigs/thesis_rig.yaml");
  ASSERT_EQ(designed.pairIds(), shipped.pairIds());
  for (size_t i = 0; i < 8; ++i) {
    EXPECT_LT((designed.pairs[i].world_from_camera.translation() -
               shipped.pairs[i].world_from_camera.translation())
                  .norm(),
              0.005)
        << designed.pairs[i].pair_id;
    EXPECT_TRUE(designed.pairs[i].world_from_camera.linear().isApprox(
        shipped.pairs[i].world_from_camera.linear(), 0.01))
        << designed.pairs[i].pair_id;
  }
  EXPECT_EQ(designed.pairs[5].sensor.seed, 202u);
}

TEST(RigDesign, TheSweepIsTheTemplatesAndANarrowerOneConflictsLess) {
  RigLayoutChoice wide = thesisLike(4), narrow = thesisLike(4);
  narrow.sweep_deg = 24;
  const auto wide_rig = buildRig(wide, "wide"), narrow_rig = buildRig(narrow, "narrow");
  const double wide_sweep = calibratedSweepDeg(wide_rig.pairs[0]);
  const double narrow_sweep = calibratedSweepDeg(narrow_rig.pairs[0]);
  std::cout << "[ figure ] calibrated sweep " << wide_sweep << " / " << narrow_sweep
            << " deg (asked 40 / 24)\n";
  EXPECT_NEAR(wide_sweep, 40, 1.0);
  EXPECT_NEAR(narrow_sweep, 24, 1.0);
  const ProxyScore wide_score = scoreOnProxy(wide_rig), narrow_score = scoreOnProxy(narrow_rig);
  std::cout << "[ figure ] proxy: sweep 40 deg " << wide_score.groups << " groups, coverage "
            << 100 * wide_score.coverage << " %; 24 deg " << narrow_score.groups
            << " groups, coverage " << 100 * narrow_score.coverage << " %\n";
  EXPECT_EQ(wide_score.pairs, 12);
  EXPECT_LE(narrow_score.groups, wide_score.groups);
  EXPECT_LT(narrow_score.coverage, wide_score.coverage);  // less light, less surface
  // The proxy at the planner's spacing gives the planner's group count.
  EXPECT_EQ(scoreOnProxy(wide_rig, 0.01).groups,
            static_cast<int>(plannedTimingGroups(wide_rig).size()));
}

TEST(RigDesign, TheSearchIsDeterministicAndPicksTheFewestGroupsMeetingTheTargets) {
  const std::vector<RigTemplate> templates = {RigTemplate::standard(3, 2, {24, 40})};
  const std::vector<Subject> subjects = {
      {"standing",
       std::make_shared<const body_scan_driver::sim::Scene>(body_scan_driver::sim::loadScene(
           body_scan_driver::sim::driverConfigDir() + "/scenes/standing_person.yaml"))}};
  DesignOptions options;
  options.candidates = 3;
  options.refine_steps = 2;  // from the best of each of the (up to 3) group counts found
  options.finalists = 1;
  options.min_proxy_coverage = 0;
  CoverageTargets targets{0.5, 0.5, 0.0};  // two pairs per pole: a low bar any layout may meet
  const DesignResult result = designRig(templates, subjects, options, targets);
  ASSERT_GE(result.candidates.size(), 4u + 2);
  ASSERT_LE(result.candidates.size(), 4u + 6);
  int simulated = 0;
  for (const Candidate& c : result.candidates) {
    EXPECT_EQ(c.proxy.pairs, 6);
    EXPECT_GE(c.choice.sweep_deg, 24);
    EXPECT_LE(c.choice.sweep_deg, 40);
    if (!c.simulated) continue;
    ++simulated;
    ASSERT_EQ(c.simulation.per_subject.size(), 1u);
    EXPECT_GT(c.simulation.per_subject[0].second.points, 10000u);
    EXPECT_NEAR(c.simulation.min_coverage, c.simulation.per_subject[0].second.body.fraction(),
                1e-12);
  }
  EXPECT_GE(simulated, 1);
  ASSERT_GE(result.chosen, 0);
  const Candidate& chosen = result.candidates[result.chosen];
  for (const Candidate& c : result.candidates)
    if (c.simulated && c.simulation.min_coverage >= 0.5) {
      EXPECT_LE(chosen.simulation.groups.size(), c.simulation.groups.size());
    }

  // Same seed, same layouts and proxy figures (proxy only: nothing simulated); another seed,
  // other layouts.
  options.min_proxy_coverage = 2;
  const DesignResult again = designRig(templates, subjects, options, targets);
  for (size_t i = 0; i < result.candidates.size(); ++i) {
    EXPECT_EQ(again.candidates[i].choice.heights, result.candidates[i].choice.heights);
    EXPECT_EQ(again.candidates[i].proxy.coverage, result.candidates[i].proxy.coverage);
  }
  EXPECT_EQ(again.chosen, -1);
  options.seed = 2;
  const DesignResult other = designRig(templates, subjects, options, targets);
  EXPECT_NE(other.candidates[1].choice.heights, result.candidates[1].choice.heights);

  const std::string table = tradeOffTable(result);
  EXPECT_NE(table.find("| 3 x 2 |"), std::string::npos) << table;
  EXPECT_NE(table.find("| yes |"), std::string::npos) << table;
  const std::string plot = std::filesystem::temp_directory_path() /
                           ("rig_design_" + std::to_string(::getpid()) + ".png");
  writeTradeOffPlot(result, plot);
  const cv::Mat image = cv::imread(plot);
  std::filesystem::remove(plot);
  EXPECT_EQ(image.cols, 720);
  EXPECT_EQ(image.rows, 480);
}
