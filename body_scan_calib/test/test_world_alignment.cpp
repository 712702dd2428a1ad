// World alignment (thesis sec. 4.3.2): the polar split, the calibration-file section, the
// least-squares affine of eq 4.1, grid-point detection on the simulated calibration cylinder
// against its true projections, and E_h (eq 4.2, Table 4.2) of a two-pole rig.
#include <body_scan_calib/calibration_rig.h>
#include <body_scan_calib/cylinder_target.h>
#include <body_scan_calib/pair_calibration_pipeline.h>
#include <body_scan_calib/sim/calibration_scenes.h>
#include <body_scan_calib/world_alignment.h>
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/sim/calibration_cylinder.h>
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/tools/package_file.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <random>
#include <set>

using namespace body_scan_driver;
using namespace body_scan_calib;

namespace {

const std::string kAlignmentConfig =
    body_scan_driver::tools::packageDir("body_scan_calib") + "/config/alignment/";
const std::string kCylinderScene =
    body_scan_driver::sim::driverConfigDir() + "/scenes/calibration_cylinder.yaml";
const char* kRig[] = {"pole_a_pair_1", "pole_a_pair_2", "pole_b_pair_1", "pole_b_pair_2"};

Eigen::Matrix3d randomRotation(std::mt19937& random) {
  std::normal_distribution<double> normal;
  return Eigen::Quaterniond(
             Eigen::Vector4d(normal(random), normal(random), normal(random), normal(random))
                 .normalized())
      .toRotationMatrix();
}

TEST(WorldAlignmentModel, PolarSplitRecoversRotationAndSymmetricPart) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> small(-0.03, 0.03);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Matrix3d rotation = randomRotation(random);
    Eigen::Matrix3d residual;
    residual << 1 + small(random), small(random), small(random), 0, 1 + small(random),
        small(random), 0, 0, 1 + small(random);
    residual = (0.5 * (residual + residual.transpose())).eval();
    const Eigen::Vector3d translation(small(random) * 30, small(random) * 30, 1.2);
    Eigen::Matrix<double, 3, 4> affine;
    affine << rotation * residual, translation;

    const body_scan_driver::WorldAlignment alignment =
        body_scan_driver::WorldAlignment::fromAffine(affine);
    EXPECT_LT((alignment.world_from_camera.linear() - rotation).norm(), 1e-9);
    EXPECT_LT((alignment.residual_linear - residual).norm(), 1e-9);
    EXPECT_LT((alignment.world_from_camera.translation() - translation).norm(), 1e-12);
    EXPECT_LT((alignment.affine() - affine).norm(), 1e-12);
    const Eigen::Vector3d point(0.1, -0.2, 0.9);
    EXPECT_LT((alignment.toWorld(point) - (affine.leftCols<3>() * point + translation)).norm(),
              1e-12);
  }
  Eigen::Matrix<double, 3, 4> singular = Eigen::Matrix<double, 3, 4>::Zero();
  singular(0, 0) = singular(1, 1) = 1;
  EXPECT_THROW(body_scan_driver::WorldAlignment::fromAffine(singular), std::invalid_argument);
}

TEST(WorldAlignmentModel, CalibrationFileKeepsTheAlignment) {
  body_scan_driver::PairCalibration calibration;
  calibration.pair_id = "pole_a/pair_1";
  calibration.projector.planes = {{0, 1, 0.1, 0.3}, {0, 1, 0.2, 0.3}};
  const std::string path =
      testing::TempDir() + "/alignment_round_trip_" + std::to_string(::getpid()) + ".yaml";
  saveCalibration(path, calibration);
  EXPECT_FALSE(loadCalibration(path).alignment.has_value());

  std::mt19937 random(5);
  Eigen::Matrix<double, 3, 4> affine;
  affine << randomRotation(random) * Eigen::Vector3d(1.002, 0.998, 1.001).asDiagonal(),
      Eigen::Vector3d(0.9, -0.4, 1.1);
  calibration.alignment = body_scan_driver::WorldAlignment::fromAffine(affine);
  saveCalibration(path, calibration);
  const body_scan_driver::PairCalibration loaded = loadCalibration(path);
  ASSERT_TRUE(loaded.alignment.has_value());
  EXPECT_LT((loaded.alignment->affine() - affine).norm(), 1e-12);
  std::remove(path.c_str());
}

TEST(CylinderLayout, MarkersAndGridPointsAreConsistent) {
  const body_scan_driver::CalibrationCylinderLayout layout;
  EXPECT_EQ(layout.columns(), 26);        // 2 pi 207.5 mm / 50 mm, even
  EXPECT_EQ(layout.rows(), 36);           // 1800 mm / 50 mm
  EXPECT_LE(layout.markerCount(), 1000);  // DICT_4X4_1000
  std::set<int> ids;
  for (int row = 0; row < layout.rows(); ++row)
    for (int col = 0; col < layout.columns(); ++col) {
      const int id = layout.markerId(col, row);
      if (id < 0) continue;
      EXPECT_TRUE(ids.insert(id).second) << "marker id " << id << " used twice";
      int found_col, found_row;
      layout.markerSquare(id, found_col, found_row);
      EXPECT_EQ(found_col, col);
      EXPECT_EQ(found_row, row);
    }
  EXPECT_EQ(static_cast<int>(ids.size()), layout.markerCount());
  // Neighbouring grid points are 50 mm apart along the axis and ~50 mm along the arc.
  const int id = layout.gridPointId(5, 10);
  EXPECT_NEAR(
      (cylinderGridPoint(layout, id) - cylinderGridPoint(layout, id + layout.columns())).norm(),
      0.05, 1e-12);
  EXPECT_NEAR((cylinderGridPoint(layout, id) - cylinderGridPoint(layout, id + 1)).norm(), 0.05,
              0.001);
  EXPECT_NEAR(cylinderGridPoint(layout, id).head<2>().norm(), 0.2075, 1e-12);
}

TEST(WorldAlignmentFit, RecoversAnAffineAndRejectsBadPointSets) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-0.3, 0.3);
  Eigen::Matrix<double, 3, 4> truth;
  truth << randomRotation(random) * Eigen::Vector3d(1.01, 0.99, 1.0).asDiagonal(),
      Eigen::Vector3d(0.5, 0.2, 1.0);
  std::vector<Eigen::Vector3d> camera, world;
  for (int i = 0; i < 30; ++i) {
    camera.emplace_back(uniform(random), uniform(random), 1 + uniform(random));
    world.push_back(truth.leftCols<3>() * camera.back() + truth.col(3));
  }
  const AffineFit fit = fitWorldAffine(camera, world);
  EXPECT_LT((fit.affine - truth).norm(), 1e-9);
  EXPECT_LT(fit.rms_m, 1e-9);
  EXPECT_EQ(fit.points, 30);
  EXPECT_TRUE(fit.outliers.empty());

  // A misread grid point 40 mm off is left out and the rest give the exact affine.
  std::vector<Eigen::Vector3d> with_outlier = world;
  with_outlier[7].x() += 0.04;
  const AffineFit robust = fitWorldAffine(camera, with_outlier);
  EXPECT_EQ(robust.outliers, std::vector<int>{7});
  EXPECT_EQ(robust.points, 29);
  EXPECT_LT((robust.affine - truth).norm(), 1e-9);

  EXPECT_THROW(
      fitWorldAffine({camera.begin(), camera.begin() + 3}, {world.begin(), world.begin() + 3}),
      WorldAlignmentError);
  for (auto& point : camera) point.z() = 1.0;  // all on one plane
  EXPECT_THROW(fitWorldAffine(camera, world), WorldAlignmentError);
}

// Renders, decodes and observes the cylinder with each rig pair; keeps the configs for truth.
// Triangulates with `calibration` if given, else with the simulator's factory calibration.
struct RigView {
  body_scan_driver::sim::VirtualPairConfig config;
  body_scan_driver::PairCalibration calibration;
  CylinderObservation observation;
};

RigView viewCylinder(
    const std::string& name,
    const std::optional<body_scan_driver::PairCalibration>& calibration = std::nullopt) {
  static const auto scene = std::make_shared<body_scan_driver::sim::Scene>(
      body_scan_driver::sim::loadScene(kCylinderScene));
  RigView view;
  view.config = body_scan_driver::sim::loadVirtualPairConfig(kAlignmentConfig + name + ".yaml");
  const body_scan_driver::sim::VirtualPair pair(view.config, scene);
  view.calibration = calibration ? *calibration : pair.factoryCalibration();
  const body_scan_driver::sim::RenderedPatternSet rendered = pair.render(1);
  body_scan_driver::StripeImage stripes;
  body_scan_driver::StripeDecoder(pair.layout()).decode(rendered.frames, stripes);
  cv::Mat gray;
  cv::cvtColor(rendered.texture, gray, cv::COLOR_RGB2GRAY);
  view.observation = observeCylinder(gray, stripes.coordinate, view.calibration,
                                     body_scan_driver::CalibrationCylinderLayout{});
  return view;
}

TEST(CylinderTarget, DetectsGridPointsAtTheirTrueProjections) {
  const RigView view = viewCylinder("pole_a_pair_1");
  const body_scan_driver::CalibrationCylinderLayout layout;
  const Eigen::Isometry3d camera_from_world = view.config.world_from_camera.inverse();
  double sum = 0, worst = 0;
  for (const GridPointDetection& detection : view.observation.detections) {
    // The scene's cylinder stands at the world origin: cylinder frame = world frame.
    const Eigen::Vector2d truth =
        view.config.camera.project(camera_from_world * cylinderGridPoint(layout, detection.id));
    const double error = (detection.pixel - truth).norm();
    sum += error;
    worst = std::max(worst, error);
  }
  const size_t count = view.observation.detections.size();
  std::printf(
      "[ figure ] cylinder detections %zu of %d predicted (%d markers), mean %.3f px, max %.3f "
      "px\n",
      count, view.observation.stats.predicted, view.observation.stats.markers, sum / count, worst);
  ASSERT_GE(count, 60u);
  EXPECT_LT(sum / count, 0.15);
  EXPECT_LT(worst, 0.5);

  double depth_error = 0;
  for (const TriangulatedGridPoint& point : view.observation.points)
    depth_error +=
        (point.camera_point - camera_from_world * cylinderGridPoint(layout, point.id)).norm();
  ASSERT_GE(view.observation.points.size(), 0.9 * count);
  std::printf("[ figure ] cylinder grid points triangulated %zu, mean 3D error %.3f mm\n",
              view.observation.points.size(), 1000 * depth_error / view.observation.points.size());
  EXPECT_LT(1000 * depth_error / view.observation.points.size(), 0.4);
}

// Aligns the rig's four pairs (each triangulating with calibrations[name] if present, else the
// factory calibration) and returns E_h (eq 4.2); expects a sound fit per pair.
SharedPointAccuracy alignRig(
    const std::map<std::string, body_scan_driver::PairCalibration>& calibrations) {
  const body_scan_driver::CalibrationCylinderLayout layout;
  std::vector<AlignedPair> aligned;
  for (const char* name : kRig) {
    const auto estimated = calibrations.find(name);
    const RigView view = estimated == calibrations.end() ? viewCylinder(name)
                                                         : viewCylinder(name, estimated->second);
    std::vector<Eigen::Vector3d> camera, world;
    AlignedPair pair{view.config.pair_id, {}, {}};
    for (const TriangulatedGridPoint& point : view.observation.points) {
      camera.push_back(point.camera_point);
      world.push_back(cylinderGridPoint(layout, point.id));
      pair.camera_points[point.id] = point.camera_point;
    }
    const AffineFit fit = fitWorldAffine(camera, world);
    pair.alignment = fit.alignment;
    const Eigen::Isometry3d& truth = view.config.world_from_camera;
    const double angle_deg =
        Eigen::AngleAxisd(truth.linear().transpose() * fit.alignment.world_from_camera.linear())
            .angle() *
        180 / M_PI;
    const double offset_mm =
        1000 * (fit.alignment.world_from_camera.translation() - truth.translation()).norm();
    std::printf(
        "[ figure ] alignment %s: %d points, rms %.3f mm, rotation error %.3f deg, translation "
        "error %.2f mm, "
        "|L - I| %.4f\n",
        name, fit.points, 1000 * fit.rms_m, angle_deg, offset_mm,
        (fit.alignment.residual_linear - Eigen::Matrix3d::Identity()).norm());
    EXPECT_GE(fit.points, 30) << name;
    EXPECT_LT(1000 * fit.rms_m, 1.0) << name;
    EXPECT_LT(angle_deg, 0.3) << name;
    EXPECT_LT(offset_mm, 5.0) << name;
    aligned.push_back(pair);
  }
  const SharedPointAccuracy accuracy = evaluateSharedPoints(aligned);
  std::printf(
      "[ figure ] E_h (eq 4.2): %d shared points, %d comparisons, mean %.3f mm, std %.3f mm, max "
      "%.3f mm\n",
      accuracy.shared_points, accuracy.comparisons, 1000 * accuracy.mean_m, 1000 * accuracy.std_m,
      1000 * accuracy.max_m);
  return accuracy;
}

TEST(WorldAlignment, TwoPolesAgreeOnSharedPointsAsInTable42) {
  const SharedPointAccuracy accuracy = alignRig({});
  EXPECT_GE(accuracy.shared_points, 33);
  EXPECT_LE(1000 * accuracy.mean_m, 1.0);
  EXPECT_GT(accuracy.std_m, 0.0);
}

// The setting: every pair calibrated from observations (the rig's board poses, one
// exposure each to stay cheap; scripts/calibrate_simulated_rig.sh uses 16), not the factory.
TEST(WorldAlignment, EstimatedCalibrationsAgreeOnSharedPoints) {
  std::map<std::string, body_scan_driver::PairCalibration> estimated;
  for (const char* name : kRig) {
    const body_scan_driver::sim::VirtualPairConfig config =
        body_scan_driver::sim::loadVirtualPairConfig(kAlignmentConfig + name + ".yaml");
    PairCalibrationOptions options;
    options.pair_id = config.pair_id;
    std::vector<std::vector<cv::Mat>> pose_frames;
    for (const Eigen::Isometry3d& pose : rig::defaultBoardPoses()) {
      const body_scan_driver::sim::VirtualPair pair(
          config, rig::boardScene(options.board, pose, config.world_from_camera));
      pose_frames.push_back(rig::captureAveraged(pair, 1, 7));
    }
    const PairCalibrationOutcome outcome = calibratePair(
        pose_frames, body_scan_driver::PatternLayout(config.bits, config.inverse_frames), options);
    // Estimated, not the factory planes: the stripes the board never showed are NaN.
    EXPECT_FALSE(outcome.planes.missing_stripes.empty()) << name;
    estimated[name] = outcome.calibration;
  }
  const SharedPointAccuracy accuracy = alignRig(estimated);
  EXPECT_GE(accuracy.shared_points, 33);
  EXPECT_LE(1000 * accuracy.mean_m, 1.0);
  EXPECT_GT(accuracy.std_m, 0.0);
}

}  // namespace
