// The whole pair calibration against the simulator's truth: the board in the rig's poses, the
// stripe planes against the factory (true) planes, stripes seen on fewer than 3 poses stored as
// NaN, the calibration file read back by loadCalibration, and the sphere table (eq 3.31) of the
// plane model against the pinhole-projector baseline.
#include <body_scan_calib/calibration_rig.h>
#include <body_scan_calib/capture_folder.h>
#include <body_scan_calib/pair_calibration_pipeline.h>
#include <body_scan_calib/pair_calibration_run.h>
#include <body_scan_calib/sim/calibration_scenes.h>
#include <body_scan_calib/sim/simulated_captures.h>
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>
#include <gtest/gtest.h>
#include <ros/package.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

using namespace body_scan_driver;
using namespace body_scan_calib;

namespace {

struct Calibrated {
  body_scan_driver::sim::VirtualPairConfig config;
  body_scan_driver::PairCalibration truth;
  std::vector<std::vector<cv::Mat>> pose_frames;
  PairCalibrationOutcome outcome;
};

// One calibration shared by the tests (rendering the poses is the slow part). One exposure per
// pose: the plane fits average thousands of points, noise hardly matters there.
const Calibrated& calibrated() {
  static const std::unique_ptr<Calibrated> result = [] {
    auto c = std::make_unique<Calibrated>();
    PairCalibrationOptions options;
    for (const Eigen::Isometry3d& pose : rig::defaultBoardPoses()) {
      const body_scan_driver::sim::VirtualPair pair(
          c->config, rig::boardScene(options.board, pose, c->config.world_from_camera));
      c->pose_frames.push_back(rig::captureAveraged(pair, 1, 7));
      c->truth = pair.factoryCalibration();
    }
    c->outcome = calibratePair(c->pose_frames, body_scan_driver::PatternLayout(8, true), options);
    return c;
  }();
  return *result;
}

double angleDeg(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  return std::acos(
             std::min(1.0, std::abs(a.head<3>().normalized().dot(b.head<3>().normalized())))) *
         180 / M_PI;
}

}  // namespace

TEST(PairCalibration, StripePlanesMatchTheSimulatorsTruePlanes) {
  const Calibrated& c = calibrated();
  const body_scan_driver::StripePlaneProjector& estimated = c.outcome.calibration.projector;
  ASSERT_EQ(estimated.stripeCount(), 256);
  double worst_angle = 0, worst_offset = 0, mean_angle = 0;
  int fitted = 0;
  for (int i = 0; i < 256; ++i) {
    if (!estimated.planes[i].allFinite()) continue;
    ++fitted;
    const Eigen::Vector4d e = estimated.planes[i] / estimated.planes[i].head<3>().norm();
    const Eigen::Vector4d t =
        c.truth.projector.planes[i] / c.truth.projector.planes[i].head<3>().norm();
    // Same orientation convention as the factory planes, so neighbours interpolate alike.
    EXPECT_GT(e.head<3>().dot(t.head<3>()), 0) << "stripe " << i;
    worst_angle = std::max(worst_angle, angleDeg(e, t));
    mean_angle += angleDeg(e, t);
    worst_offset = std::max(worst_offset, std::abs(e[3] - t[3]));
  }
  mean_angle /= std::max(1, fitted);
  std::printf(
      "[ figure ] fitted %d planes; normal angle mean %.4f worst %.4f deg, worst offset %.3f mm\n",
      fitted, mean_angle, worst_angle, worst_offset * 1e3);
  // The stripes a 1 m scene uses (spheres and body at 0.9-1.1 m) are all calibrated.
  EXPECT_GE(fitted, 150);
  // Bounds the joint refinement is needed for (without it: mean 0.014 deg, worst 0.08 deg,
  // offset 0.9 mm; with it 0.006 deg, 0.02 deg, 0.2 mm).
  EXPECT_LT(mean_angle, 0.06);
  EXPECT_LT(worst_angle, 0.1);
  EXPECT_LT(worst_offset, 0.0005);
  EXPECT_FALSE(c.outcome.refinement_summary.empty());
  // Camera (our Zhang + ML calibration) close to the truth: focal length within 1%.
  EXPECT_NEAR(c.outcome.calibration.camera.alpha / c.config.camera.alpha, 1.0, 0.01);
  EXPECT_LT(c.outcome.camera.rms_px, 0.3);
  // The reported standard deviations (camera calibration) cover the true focal length and
  // principal point.
  const Eigen::Matrix<double, 7, 1>& std_devs = c.outcome.camera.std_devs;
  EXPECT_NEAR(c.outcome.calibration.camera.alpha, c.config.camera.alpha, 5 * std_devs[0]);
  EXPECT_NEAR(c.outcome.calibration.camera.u0, c.config.camera.u0, 5 * std_devs[3]);
  EXPECT_NEAR(c.outcome.calibration.camera.v0, c.config.camera.v0, 5 * std_devs[4]);
}

TEST(PairCalibration, StripesSeenOnFewerThanThreePosesAreNaNAndReported) {
  const Calibrated& c = calibrated();
  const ProjectorCalibrationResult& planes = c.outcome.planes;
  ASSERT_FALSE(planes.missing_stripes.empty()) << "the rig cannot see the outermost stripes";
  for (int i = 0; i < 256; ++i) {
    const bool missing = planes.poses_per_stripe[i] < 3;
    EXPECT_EQ(missing, !planes.projector.planes[i].allFinite()) << "stripe " << i;
    EXPECT_EQ(missing,
              std::count(planes.missing_stripes.begin(), planes.missing_stripes.end(), i) == 1)
        << "stripe " << i;
    if (missing) {
      EXPECT_TRUE(planes.projector.planes[i].array().isNaN().all()) << "stripe " << i;
    }
  }
  // With only three poses, stripes that two of them see are missing too: never invented.
  std::vector<ReferencePlaneObservation> three;
  for (int pose : {0, 2, 6}) {
    body_scan_driver::StripeImage stripes;
    body_scan_driver::StripeDecoder(body_scan_driver::PatternLayout(8, true))
        .decode(c.pose_frames[pose], stripes);
    three.push_back({c.outcome.camera.board_to_camera[pose], stripes.coordinate.clone(),
                     boardRegion(c.outcome.camera.camera, c.outcome.camera.board_to_camera[pose],
                                 referenceBoard())});
  }
  const ProjectorCalibrationResult from_three =
      calibrateStripePlanes(c.outcome.camera.camera, three);
  int seen_on_two = 0;
  for (int i = 0; i < 256; ++i) {
    if (from_three.poses_per_stripe[i] == 2) {
      ++seen_on_two;
      EXPECT_TRUE(from_three.projector.planes[i].array().isNaN().all()) << "stripe " << i;
    }
    if (from_three.poses_per_stripe[i] == 3) {
      EXPECT_TRUE(from_three.projector.planes[i].allFinite()) << "stripe " << i;
    }
  }
  EXPECT_GT(seen_on_two, 0);
  EXPECT_THROW(calibrateStripePlanes(c.outcome.camera.camera, {three[0], three[1]}),
               std::invalid_argument);
}

TEST(PairCalibration, TheCalibrationFileIsReadByLoadCalibration) {
  const Calibrated& c = calibrated();
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("calib_test_" + std::to_string(::getpid())) / "pair.yaml")
                               .string();
  saveCalibration(path, c.outcome.calibration);
  const body_scan_driver::PairCalibration loaded = loadCalibration(path);
  EXPECT_NEAR(loaded.camera.alpha, c.outcome.calibration.camera.alpha, 1e-6);
  ASSERT_EQ(loaded.projector.stripeCount(), 256);
  for (int i = 0; i < 256; ++i)
    EXPECT_EQ(loaded.projector.planes[i].allFinite(),
              c.outcome.calibration.projector.planes[i].allFinite());
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());

  // A never-observed stripe triangulates to nothing, a calibrated one to points.
  const body_scan_driver::Triangulator triangulator(loaded);
  std::vector<float> xyz(640 * 480 * 3);
  const int missing = c.outcome.planes.missing_stripes.front();
  EXPECT_EQ(triangulator.triangulate(cv::Mat1f(480, 640, missing + 0.5f), xyz.data(), 3), 0u);
  EXPECT_GT(triangulator.triangulate(cv::Mat1f(480, 640, 128.5f), xyz.data(), 3), 0u);

  // The checked-in calibration of the repository's docs/calibration is readable too.
  const body_scan_driver::PairCalibration checked_in =
      loadCalibration(ros::package::getPath("body_scan_calib") + "/../docs/calibration/pair.yaml");
  EXPECT_EQ(checked_in.projector.stripeCount(), 256);
  EXPECT_NEAR(checked_in.camera.alpha, c.config.camera.alpha, 0.01 * c.config.camera.alpha);
}

TEST(PairCalibration, OfflineFromAnImageFolderGivesTheLiveResult) {
  const Calibrated& c = calibrated();
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("calib_offline_" + std::to_string(::getpid()));
  for (size_t pose = 0; pose < c.pose_frames.size(); ++pose)
    savePatternFrames((folder / poseFolderName(static_cast<int>(pose))).string(),
                      c.pose_frames[pose]);
  const body_scan_driver::PatternLayout layout(8, true);
  const auto loaded = loadPoseCaptures(folder.string(), layout);
  ASSERT_EQ(loaded.size(), c.pose_frames.size());
  PairCalibrationOptions options;
  options.joint_refinement = false;  // the images are what is under test, not the refinement
  const PairCalibrationOutcome offline = calibratePair(loaded, layout, options);
  const PairCalibrationOutcome live = calibratePair(c.pose_frames, layout, options);
  EXPECT_EQ(offline.planes.missing_stripes, live.planes.missing_stripes);
  EXPECT_DOUBLE_EQ(offline.calibration.camera.alpha, live.calibration.camera.alpha);
  for (int i = 0; i < 256; ++i)
    if (live.calibration.projector.planes[i].allFinite()) {
      EXPECT_EQ(offline.calibration.projector.planes[i], live.calibration.projector.planes[i]);
    }
  // A folder without poses, or with a frame missing, is an error naming the file.
  std::filesystem::remove(folder / "pose_01" / "frame_05.png");
  EXPECT_THROW(loadPoseCaptures(folder.string(), layout), std::runtime_error);
  std::filesystem::remove_all(folder);
  EXPECT_THROW(loadPoseCaptures(folder.string(), layout), std::runtime_error);
}

namespace {
std::string fileText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}
}  // namespace

// calibrate_simulated_pair --save-images then calibrate_pair --images on that folder: the two
// tools' runs (rendered views in memory, the folder read back) write the same calibration file.
TEST(PairCalibration, SimulatedRunAndFolderRunWriteTheSameCalibration) {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("calib_runs_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  const body_scan_driver::sim::VirtualPairConfig config;
  PairCalibrationOptions options;
  options.joint_refinement = false;  // the views are what is under test, not the refinement
  options.pair_id = config.pair_id;
  const PairViews simulated = body_scan_calib::sim::captureSimulatedPairViews(
      config, options.board, 1, (root / "captures").string());
  ASSERT_TRUE(simulated.truth.has_value());
  const auto files = [&](const std::string& name) {
    return PairCalibrationFiles{(root / (name + ".yaml")).string(),
                                (root / (name + "_accuracy.yaml")).string(),
                                (root / (name + ".png")).string()};
  };
  calibratePairToFiles(simulated, options, files("simulated"));
  const PairViews folder = loadPairViews((root / "captures").string(), config.bits, 1);
  EXPECT_EQ(folder.pose_frames.size(), simulated.pose_frames.size());
  EXPECT_EQ(folder.sphere_frames.size(), simulated.sphere_frames.size());
  calibratePairToFiles(folder, options, files("folder"));
  const std::string calibration = fileText(root / "simulated.yaml");
  EXPECT_GT(calibration.size(), 10000u);
  EXPECT_EQ(fileText(root / "folder.yaml"), calibration);
  // Only the simulator knows the truth: the decoding floor is in its report alone.
  EXPECT_NE(fileText(root / "simulated_accuracy.yaml").find("Decoding floor"), std::string::npos);
  EXPECT_EQ(fileText(root / "folder_accuracy.yaml").find("Decoding floor"), std::string::npos);
  EXPECT_GT(std::filesystem::file_size(root / "folder.png"), 1000u);
  std::filesystem::remove_all(root);
}

TEST(PairCalibration, SphereTablePlaneModelBeatsThePinholeBaseline) {
  const Calibrated& c = calibrated();
  constexpr double kRadius = 0.025;
  const std::vector<Eigen::Vector3d> centers = rig::defaultSphereCenters();
  const body_scan_driver::sim::VirtualPair pair(
      c.config, rig::sphereScene(centers, kRadius, c.config.world_from_camera));
  const int exposures = 8;  // the capture protocol (16 in the checked-in report), kept short here
  const AccuracyEvaluation evaluation = evaluateSphereAccuracy(
      c.outcome.calibration, c.outcome.pinhole_calibration,
      rig::captureAveraged(pair, exposures, 500), body_scan_driver::PatternLayout(8, true), centers,
      centers, kRadius, exposures);
  ASSERT_EQ(evaluation.spheres.size(), 5u);
  double plane_center_error = 0, pinhole_center_error = 0;
  for (const SphereAccuracy& row : evaluation.spheres) {
    std::printf(
        "[ figure ] sphere %d: E_s plane %.4f pinhole %.4f mm^2; centre error %.2f / %.2f mm\n",
        row.number, row.plane_model.e_s_m2 * 1e6, row.pinhole_model.e_s_m2 * 1e6,
        row.plane_center_error_m * 1e3, row.pinhole_center_error_m * 1e3);
    EXPECT_LE(row.plane_model.e_s_m2, 0.20e-6) << "sphere " << row.number;
    EXPECT_GT(row.plane_model.points, 500);
    plane_center_error += row.plane_center_error_m / 5;
    pinhole_center_error += row.pinhole_center_error_m / 5;
  }
  std::printf("[ figure ] mean E_s plane %.4f pinhole %.4f mm^2 (%.1f%% lower)\n",
              evaluation.meanPlaneEs() * 1e6, evaluation.meanPinholeEs() * 1e6,
              evaluation.improvementPercent());
  // Must show: at least 20% lower on average (the thesis reports 19-44% per sphere).
  EXPECT_GE(evaluation.improvementPercent(), 20.0);
  EXPECT_LT(plane_center_error, pinhole_center_error);
}
