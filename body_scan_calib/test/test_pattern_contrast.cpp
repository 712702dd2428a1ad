// The simulator's board renders against real captures (test/data/kamino_procam, README there):
// the finest Gray-code bit's |pattern - inverse| on the dark and light squares
// (eval/pattern_contrast.h) has the real set's percentiles with the real-capture optics
// (body_scan_driver sim/virtual_pair.h), and the ideal optics are refused by the same criterion.
#include <body_scan_calib/calibration_rig.h>
#include <body_scan_calib/capture_layout.h>
#include <body_scan_calib/eval/pattern_contrast.h>
#include <body_scan_calib/pair_calibration_pipeline.h>
#include <body_scan_calib/sim/calibration_scenes.h>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

namespace body_scan_calib {
namespace {

using eval::BoardContrast;
using eval::ContrastDistribution;

// Simulated board poses measured (the rig's first; a few suffice, the test stays fast).
constexpr int kSimulatedPoses = 4;

BoardContrast realContrast() {
  std::vector<std::vector<cv::Mat>> poses;
  for (CapturedPatternSet& set :
       loadCapturedPoses(REAL_CAPTURES_DIR, captureLayout("opencv"), CaptureBits{10, 0}))
    poses.push_back(std::move(set.frames));
  return eval::finestBitContrastOnBoard(poses, body_scan_driver::PatternLayout(10, true),
                                        Checkerboard{9, 7, 0.075});
}

BoardContrast simulatedContrast(const body_scan_driver::sim::VirtualPairConfig& config) {
  const auto board_poses = rig::defaultBoardPoses();
  std::vector<std::vector<cv::Mat>> rendered;
  for (int pose = 0; pose < kSimulatedPoses; ++pose) {
    const body_scan_driver::sim::VirtualPair pair(
        config, rig::boardScene(referenceBoard(), board_poses[pose], config.world_from_camera));
    rendered.push_back(pair.render(static_cast<uint32_t>(1000 * pose)).frames);
  }
  return eval::finestBitContrastOnBoard(
      rendered, body_scan_driver::PatternLayout(config.bits, true), referenceBoard());
}

// Percentiles p25 .. p95 within 3 grey levels + 25% of the real value. 3 levels: the simulated
// sensor noise (sigma 2 levels per frame; the real camera's is lower) alone gives a square
// without signal |pattern - inverse| p50 1.9, p75 3.3, p95 5.5 levels, where the real dark
// squares have 1, 2, 6. 25%: the simulator's exposure is its own (its light squares are lit ~30%
// brighter). Returns the worst excess over the tolerance (<= 0: within).
double worstExcess(const ContrastDistribution& real, const ContrastDistribution& simulated) {
  const double real_values[] = {real.p25, real.p50, real.p75, real.p95};
  const double simulated_values[] = {simulated.p25, simulated.p50, simulated.p75, simulated.p95};
  double worst = -1e9;
  for (int i = 0; i < 4; ++i)
    worst = std::max(
        worst, std::abs(simulated_values[i] - real_values[i]) - (3.0 + 0.25 * real_values[i]));
  return worst;
}

TEST(PatternContrast, SimulatedBoardMatchesTheRealCaptures) {
  const BoardContrast real = realContrast();
  ASSERT_EQ(real.poses, 4);
  // The real set is hard: the dark squares' finest bit is at the noise floor.
  EXPECT_LE(real.dark.p50, 2);
  EXPECT_GT(real.light.p50, 20);

  const BoardContrast simulated = simulatedContrast(
      body_scan_driver::sim::withRealCaptureOptics(body_scan_driver::sim::VirtualPairConfig{}));
  ASSERT_EQ(simulated.poses, kSimulatedPoses);
  body_scan_driver::sim::VirtualPairConfig ideal;
  const BoardContrast ideal_contrast = simulatedContrast(ideal);
  std::cout << eval::contrastTable("real", real, "sim", simulated);
  auto figure = [](const char* name, const BoardContrast& c) {
    std::cout << "[ figure ] finest bit |pattern - inverse| p25/p50/p75/p95, " << name << ": dark "
              << c.dark.p25 << "/" << c.dark.p50 << "/" << c.dark.p75 << "/" << c.dark.p95
              << ", light " << c.light.p25 << "/" << c.light.p50 << "/" << c.light.p75 << "/"
              << c.light.p95 << "\n";
  };
  figure("real fixture", real);
  figure("simulator (real-capture optics)", simulated);
  figure("simulator (ideal optics, same board)", ideal_contrast);

  EXPECT_LE(worstExcess(real.dark, simulated.dark), 0) << "dark squares drifted";
  EXPECT_LE(worstExcess(real.light, simulated.light), 0) << "light squares drifted";
  // The criterion tells the ideal optics apart (on the light squares: on the dark ones the
  // black print alone leaves little to tell).
  EXPECT_GT(worstExcess(real.light, ideal_contrast.light), 0);
}

TEST(PatternContrast, DistributionPercentilesAndHistogram) {
  std::vector<float> values;
  for (int i = 0; i <= 100; ++i) values.push_back(static_cast<float>(i));
  const ContrastDistribution d = eval::contrastDistribution(values);
  EXPECT_EQ(d.pixels, 101u);
  EXPECT_EQ(d.p5, 5);
  EXPECT_EQ(d.p50, 50);
  EXPECT_EQ(d.p95, 95);
  EXPECT_NEAR(d.histogram[0], 2.0 / 101, 1e-12);   // 0, 1
  EXPECT_NEAR(d.histogram[6], 37.0 / 101, 1e-12);  // 64 .. 100
  double total = 0;
  for (double share : d.histogram) total += share;
  EXPECT_NEAR(total, 1.0, 1e-12);
}

}  // namespace
}  // namespace body_scan_calib
