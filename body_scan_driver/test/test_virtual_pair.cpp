#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>

#include "sim_fixtures.h"

using namespace body_scan_driver;

TEST(VirtualPair, StripePlanesDoNotShareOneLine) {
  // A pinhole projector's planes all contain one line through its centre. Ours do not: the
  // line where neighbouring planes meet moves as the mirror turns.
  const sim::VirtualPair pair(test::pairLookingAlongX(), test::planeScene(1.0));
  const auto& planes = pair.factoryCalibration().projector.planes;
  auto meeting_point = [&](int i) {  // where planes i and i+1 cross the camera's y-z plane
    Eigen::Matrix2d a;
    a << planes[i][1], planes[i][2], planes[i + 1][1], planes[i + 1][2];
    return Eigen::Vector2d(a.inverse() * Eigen::Vector2d(-planes[i][3], -planes[i + 1][3]));
  };
  const double moved = (meeting_point(0) - meeting_point(254)).norm();
  std::cout << "[ figure ] the planes' meeting line moves by " << 1000 * moved
            << " mm across the sweep\n";
  EXPECT_GT(moved, 0.005);
}

TEST(VirtualPair, FactoryCalibrationContainsTheTruePoints) {
  const sim::VirtualPair pair(test::pairLookingAlongX(0.0), test::planeScene(1.1));
  const sim::RenderedPatternSet set = pair.render();
  const StripePlaneProjector projector = pair.factoryCalibration().projector;
  double worst = 0;
  int checked = 0;
  for (int v = 0; v < 480; v += 7)
    for (int u = 0; u < 640; u += 7) {
      const float s = set.truth.stripe(v, u);
      if (std::isnan(s)) continue;
      const cv::Vec3f p = set.truth.points(v, u);
      const Eigen::Vector4d plane = projector.planeAt(s);
      const double distance =
          std::abs(plane.head<3>().dot(Eigen::Vector3d(p[0], p[1], p[2])) + plane[3]) /
          plane.head<3>().norm();
      worst = std::max(worst, distance);
      ++checked;
    }
  EXPECT_GT(checked, 5000);
  EXPECT_LT(worst, 20e-6);  // plane interpolation between stripe centres: micrometres
}

TEST(VirtualPair, ObjectsCastShadowsFromTheProjector) {
  // A ball 30 cm in front of a wall: the projector, 330 mm above the camera, throws its shadow
  // on the wall below the ball, where nothing may decode.
  auto scene = test::planeScene(1.2);
  scene->add(std::make_unique<sim::Sphere>(Eigen::Vector3d(0.9, 0, 0), 0.06, sim::Material{}));
  const sim::VirtualPair pair(test::pairLookingAlongX(), scene);
  const sim::RenderedPatternSet set = pair.render();
  int shadowed_wall = 0;
  for (int v = 0; v < 480; ++v) {
    const cv::Vec3f p = set.truth.points(v, 320);
    if (std::abs(p[2] - 1.2f) < 1e-3f && std::isnan(set.truth.stripe(v, 320))) ++shadowed_wall;
  }
  // The shadow's height on the wall is about the ball's diameter scaled by 1.2 / 0.9 - 0.33 m
  // parallax: tens of pixels.
  EXPECT_GT(shadowed_wall, 20);
  // Ambient light only there: lit and dark frames nearly equal.
  int v = 0;
  while (v < 480 && !(std::abs(set.truth.points(v, 320)[2] - 1.2f) < 1e-3f &&
                      std::isnan(set.truth.stripe(v, 320))))
    ++v;
  ASSERT_LT(v, 480);
  EXPECT_LT(std::abs(set.frames[0].at<uint8_t>(v, 320) - set.frames[1].at<uint8_t>(v, 320)), 10);
}

TEST(VirtualPair, RenderingIsDeterministicPerSeedAndScan) {
  const sim::VirtualPair pair(test::pairLookingAlongX(), test::planeScene(1.0));
  const auto start = std::chrono::steady_clock::now();
  const sim::RenderedPatternSet first = pair.render(4);
  std::cout
      << "[ figure ] one 18-frame 640x480 render: "
      << std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()
      << " ms (benchmarked in bench_decode_triangulate)\n";
  const sim::RenderedPatternSet again = pair.render(4);
  const sim::RenderedPatternSet other = pair.render(5);
  ASSERT_EQ(first.frames.size(), 18u);
  for (size_t f = 0; f < first.frames.size(); ++f)
    EXPECT_EQ(cv::norm(first.frames[f], again.frames[f], cv::NORM_INF), 0.0) << f;
  EXPECT_GT(cv::norm(first.frames[5], other.frames[5], cv::NORM_L1), 0.0);
  // Sensor noise has the documented sigma: lit minus dark frame differences on a flat plane
  // vary by about sqrt(2) * 2 grey levels between neighbouring pixels.
  cv::Mat1f difference;
  cv::Mat(first.frames[1]).convertTo(difference, CV_32F);
  cv::Mat1f neighbour = difference(cv::Rect(1, 0, 639, 480)) - difference(cv::Rect(0, 0, 639, 480));
  cv::Scalar mean, deviation;
  cv::meanStdDev(neighbour, mean, deviation);
  // Blur (0.7 px) correlates neighbours, so the difference is below 2 * sqrt(2).
  EXPECT_GT(deviation[0], 1.0);
  EXPECT_LT(deviation[0], 2.9);
}

TEST(VirtualPair, ShotNoiseGrowsWithTheSignal) {
  // Two scans of the same plane differ by the noise alone: per pixel of true level L, variance
  // 2 (read^2 + gain L) + 2/12 (8-bit quantization of each), in the bright lit frame and in the
  // dim dark frame (ambient light only).
  sim::VirtualPairConfig config = test::pairLookingAlongX(0.0);
  const std::vector<cv::Mat> truth =
      sim::VirtualPair(config, test::planeScene(1.0)).render(1).frames;
  config.sensor.noise_sigma = 0.5;
  config.sensor.shot_noise_gain = 0.1;
  const sim::VirtualPair pair(config, test::planeScene(1.0));
  const std::vector<cv::Mat> first = pair.render(1).frames, second = pair.render(2).frames;
  for (int frame : {PatternLayout::litFrame(), PatternLayout::darkFrame()}) {
    const cv::Scalar level = cv::mean(truth[frame]);
    cv::Mat difference;
    cv::subtract(first[frame], second[frame], difference, cv::noArray(), CV_32F);
    cv::Scalar mean, deviation;
    cv::meanStdDev(difference, mean, deviation);
    const double expected = std::sqrt(2 * (0.25 + 0.1 * level[0]) + 2.0 / 12);
    std::cout << "[ figure ] frame " << frame << ", level " << level[0] << ": scan-to-scan sd "
              << deviation[0] << " (expected " << expected << ")\n";
    EXPECT_NEAR(deviation[0], expected, 0.05 * expected) << frame;
  }
  // The real-capture profile brings the real camera's noise unless the pair has shot noise.
  const sim::VirtualPairConfig real = sim::withRealCaptureOptics({});
  EXPECT_DOUBLE_EQ(real.sensor.noise_sigma, sim::RealCaptureOptics{}.noise_sigma);
  EXPECT_DOUBLE_EQ(real.sensor.shot_noise_gain, sim::RealCaptureOptics{}.shot_noise_gain);
  EXPECT_DOUBLE_EQ(sim::withRealCaptureOptics(config).sensor.noise_sigma, 0.5);
}

TEST(VirtualPair, PairFileTyposAreErrorsAndTheDefaultFileLoads) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("body_scan_test_pair_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << "sensor: {noise_sgima: 1.0}\n";
  try {
    sim::loadVirtualPairConfig(path.string());
    FAIL() << "typo accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'noise_sgima'"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
  const auto config =
      sim::loadVirtualPairConfig(sim::driverConfigDir() + "/pairs/default_pair.yaml");
  EXPECT_EQ(config.pair_id, "pole_a/pair_1");
  EXPECT_DOUBLE_EQ(config.camera.alpha, 810.0);
  EXPECT_DOUBLE_EQ(config.sensor.noise_sigma, 2.0);
  // 1 m in front of the subject at 1.25 m, looking back at it (-x).
  EXPECT_NEAR(config.world_from_camera.translation().x(), 1.0, 1e-12);
  EXPECT_NEAR((config.world_from_camera.linear() * Eigen::Vector3d::UnitZ()).x(), -1.0, 1e-12);
}

// Mean of a frame over the pixels where `mask` is set (grey levels).
double meanWhere(const cv::Mat& frame, const cv::Mat& mask) { return cv::mean(frame, mask)[0]; }

TEST(VirtualPair, RealCaptureOpticsBlurTheFinestBitAndSpillLight) {
  // A board of 3 cm squares (about 24 px) 1 m in front, no sensor noise.
  auto board = std::make_shared<sim::Scene>();
  board->add(std::make_unique<sim::CheckerboardPlane>(
      Eigen::Vector3d(1.0, 0, 0), Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(0, 1, 0), 16, 12, 0.03,
      0.85, 0.03));
  const sim::VirtualPairConfig ideal = test::pairLookingAlongX(0.0);
  auto render = [&](const sim::VirtualPairConfig& config) {
    return sim::VirtualPair(config, board).render(1).frames;
  };
  const std::vector<cv::Mat> plain = render(ideal);
  // The squares in the middle of the image (the board covers about 390 x 290 px).
  cv::Mat middle = cv::Mat::zeros(plain[0].size(), CV_8U);
  middle(cv::Rect(220, 165, 200, 150)) = 255;
  const cv::Mat dark_squares = (plain[0] < 40) & middle, light_squares = (plain[0] > 100) & middle;

  // Blooming moves light from light squares into dark ones and keeps the frame's total.
  sim::VirtualPairConfig bloom = ideal;
  bloom.sensor.bloom_share = 0.1;
  const std::vector<cv::Mat> bloomed = render(bloom);
  EXPECT_NEAR(cv::mean(bloomed[0])[0], cv::mean(plain[0])[0], 0.01 * cv::mean(plain[0])[0]);
  EXPECT_GT(meanWhere(bloomed[0], dark_squares), meanWhere(plain[0], dark_squares) + 2);
  EXPECT_LT(meanWhere(bloomed[0], light_squares), meanWhere(plain[0], light_squares) - 2);

  // Stray light adds its share of the frame's mean everywhere.
  sim::VirtualPairConfig stray = ideal;
  stray.sensor.stray_light = 0.1;
  const std::vector<cv::Mat> strayed = render(stray);
  EXPECT_NEAR(meanWhere(strayed[0], middle) - meanWhere(plain[0], middle),
              0.1 * cv::mean(plain[0])[0], 0.3);

  // A 2.5-stripe line box-averages the finest bit (runs of 2 stripes): over a period its mean
  // |pattern - inverse| is 0.365 of full contrast, against 0.875 for the camera pixel's own
  // footprint alone (about half a stripe here), so about 0.42 of the sharp line's.
  sim::VirtualPairConfig wide = ideal;
  wide.projector.line_width = 2.5;
  const std::vector<cv::Mat> blurred = render(wide);
  const PatternLayout layout(ideal.bits, true);
  auto finest_contrast = [&](const std::vector<cv::Mat>& frames) {
    cv::Mat difference;
    cv::absdiff(frames[layout.patternFrame(ideal.bits - 1)],
                frames[layout.inverseFrame(ideal.bits - 1)], difference);
    return meanWhere(difference, light_squares);
  };
  const double ratio = finest_contrast(blurred) / finest_contrast(plain);
  std::cout << "[ figure ] finest bit contrast, 2.5-stripe line vs sharp: " << ratio << "\n";
  EXPECT_NEAR(ratio, 0.365 / 0.875, 0.06);
}

TEST(VirtualPair, OpticsKeysAreReadAndCheckedFromPairFiles) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("body_scan_test_optics_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << "sensor: {bloom_share: 0.2, bloom_sigma: 6, stray_light: 0.01, "
                         "shot_noise_gain: 0.05}\n"
                      << "projector: {line_width: 1.5}\n";
  const auto config = sim::loadVirtualPairConfig(path.string());
  EXPECT_DOUBLE_EQ(config.sensor.bloom_share, 0.2);
  EXPECT_DOUBLE_EQ(config.sensor.bloom_sigma, 6.0);
  EXPECT_DOUBLE_EQ(config.sensor.stray_light, 0.01);
  EXPECT_DOUBLE_EQ(config.sensor.shot_noise_gain, 0.05);
  EXPECT_DOUBLE_EQ(config.projector.line_width, 1.5);
  // The real-capture optics fill only what a pair file leaves off.
  const auto real = sim::withRealCaptureOptics(config);
  EXPECT_DOUBLE_EQ(real.projector.line_width, 1.5);
  EXPECT_DOUBLE_EQ(sim::withRealCaptureOptics({}).projector.line_width,
                   sim::RealCaptureOptics{}.line_width);
  std::ofstream(path) << "sensor: {bloom_share: 1.5}\n";
  EXPECT_THROW(sim::loadVirtualPairConfig(path.string()), std::runtime_error);
  std::ofstream(path) << "projector: {line_width: -1}\n";
  EXPECT_THROW(sim::loadVirtualPairConfig(path.string()), std::runtime_error);
  std::ofstream(path) << "sensor: {shot_noise_gain: -0.1}\n";
  EXPECT_THROW(sim::loadVirtualPairConfig(path.string()), std::runtime_error);
  std::filesystem::remove(path);
}
