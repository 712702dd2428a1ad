#include <body_scan_calib/capture_decoding.h>
#include <body_scan_calib/joint_refinement.h>
#include <body_scan_calib/pair_calibration_pipeline.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace body_scan_calib {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// A joint refinement that worsens the corner rms by more than this factor is refused: the
// stripe points would be pulling the camera off its corners.
constexpr double kMaxCornerRmsGrowth = 1.10;
// Above this growth the refinement is repeated with the stripe points weighed as one group.
constexpr double kRebalanceCornerRmsGrowth = 1.05;

std::vector<Eigen::Vector3d> triangulateCloud(const body_scan_driver::PairCalibration& calibration,
                                              const cv::Mat1f& coordinate) {
  const body_scan_driver::Triangulator triangulator(calibration);
  std::vector<float> xyz(coordinate.total() * 3);
  triangulator.triangulate(coordinate, xyz.data(), 3);
  std::vector<Eigen::Vector3d> cloud;
  for (size_t i = 0; i < coordinate.total(); ++i)
    if (std::isfinite(xyz[3 * i + 2]))
      cloud.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  return cloud;
}

std::string projectorSummary(const ProjectorCalibrationResult& planes,
                             const ProjectorCalibrationOptions& options) {
  const int stripes = planes.projector.stripeCount();
  const int on_board =
      static_cast<int>(std::count_if(planes.poses_per_stripe.begin(), planes.poses_per_stripe.end(),
                                     [](int poses) { return poses > 0; }));
  std::ostringstream line;
  line << "projector: " << stripes - planes.missing_stripes.size() << " of " << stripes
       << " planes (" << on_board << " stripes on a board; " << planes.smooth_stripes.size()
       << " from the smooth model, " << planes.extrapolated_stripes.size()
       << " of them extrapolated); " << planes.missing_stripes.size() << " NaN ("
       << (options.model == StripePlaneModel::kPerStripe
               ? "seen on fewer than " + std::to_string(options.min_poses_per_stripe) + " poses"
               : "more than " + std::to_string(options.extrapolation_margin) +
                     " stripes beyond every board")
       << "), rms " << planes.rms_m * 1e3 << " mm";
  return line.str();
}

}  // namespace

CameraAndBoardPoses estimateCameraAndBoardPoses(const std::vector<cv::Mat>& board_images,
                                                const Checkerboard& board) {
  if (board_images.size() < 3)
    throw PairCalibrationError("camera calibration needs >= 3 board images, got " +
                               std::to_string(board_images.size()));
  CameraAndBoardPoses result;
  for (size_t i = 0; i < board_images.size(); ++i) {
    std::vector<Eigen::Vector2d> corners;
    if (!detectCheckerboardCorners(board_images[i], board, corners))
      throw PairCalibrationError(
          "reference-plane pose " + std::to_string(i) + ": the " +
          std::to_string(board.inner_cols) + "x" + std::to_string(board.inner_rows) +
          " inner checker corners were not found; keep the whole board with its white margin in "
          "view, lit, and check the board size (inner corners, not squares)");
    result.corners.push_back(std::move(corners));
  }
  try {
    // Zhang's closed form (eqs 3.14-3.26) + maximum-likelihood refinement (Ceres).
    const CameraCalibrationResult calibration =
        calibrateCamera(result.corners, board, board_images[0].cols, board_images[0].rows);
    result.camera = calibration.camera;
    result.board_to_camera = calibration.board_to_camera;
    result.rms_px = calibration.rms_px;
    result.std_devs = calibration.std_devs;
  } catch (const CameraCalibrationError& error) {
    throw PairCalibrationError(std::string("camera calibration from the reference-plane poses: ") +
                               error.what());
  }
  return result;
}

cv::Mat1b boardRegion(const body_scan_driver::PinholeCamera& camera,
                      const Eigen::Isometry3d& board_to_camera, const Checkerboard& board) {
  // Outline sampled densely so that lens distortion bends it like the image.
  const double s = board.square_size;
  const Eigen::Vector2d low(-0.5 * s, -0.5 * s);
  const Eigen::Vector2d high((board.inner_cols - 0.5) * s, (board.inner_rows - 0.5) * s);
  const Eigen::Vector2d outline[] = {low, {high.x(), low.y()}, high, {low.x(), high.y()}};
  std::vector<cv::Point> polygon;
  constexpr int kSamplesPerEdge = 32;
  for (int edge = 0; edge < 4; ++edge)
    for (int k = 0; k < kSamplesPerEdge; ++k) {
      const Eigen::Vector2d p =
          outline[edge] + (outline[(edge + 1) % 4] - outline[edge]) * k / kSamplesPerEdge;
      const Eigen::Vector2d pixel =
          camera.project(board_to_camera * Eigen::Vector3d(p.x(), p.y(), 0));
      polygon.emplace_back(static_cast<int>(std::lround(pixel.x())),
                           static_cast<int>(std::lround(pixel.y())));
    }
  cv::Mat1b region = cv::Mat1b::zeros(camera.height, camera.width);
  cv::fillPoly(region, std::vector<std::vector<cv::Point>>{polygon}, cv::Scalar(255));
  return region;
}

PairCalibrationOutcome calibratePair(const std::vector<std::vector<cv::Mat>>& pose_frames,
                                     const body_scan_driver::PatternLayout& layout,
                                     const PairCalibrationOptions& options,
                                     const Progress& progress,
                                     const std::vector<std::vector<cv::Mat>>& pose_cross_frames) {
  auto report = [&](const std::string& message) {
    if (progress) progress(message);
  };
  if (pose_frames.size() < 3)
    throw PairCalibrationError("pair calibration needs >= 3 reference-plane poses, got " +
                               std::to_string(pose_frames.size()) +
                               ": capture the board in more poses");
  PairCalibrationOutcome outcome;
  std::vector<cv::Mat> board_images;
  for (size_t pose = 0; pose < pose_frames.size(); ++pose) {
    try {
      checkFrames(layout, pose_frames[pose]);
    } catch (const std::invalid_argument& error) {
      throw PairCalibrationError("reference-plane pose " + std::to_string(pose) + ": " +
                                 error.what());
    }
    board_images.push_back(pose_frames[pose][body_scan_driver::PatternLayout::litFrame()]);
  }
  report("camera: corners of " + std::to_string(board_images.size()) + " poses");
  outcome.camera = estimateCameraAndBoardPoses(board_images, options.board);
  report("camera: reprojection rms " + std::to_string(outcome.camera.rms_px) + " px");

  std::vector<ReferencePlaneObservation> observations;
  for (size_t pose = 0; pose < pose_frames.size(); ++pose) {
    const body_scan_driver::StripeImage stripes = decodePatternFrames(
        pose_frames[pose],
        pose < pose_cross_frames.size() ? pose_cross_frames[pose] : std::vector<cv::Mat>(), layout,
        options.decoding);
    observations.push_back(
        {outcome.camera.board_to_camera[pose], stripes.coordinate.clone(),
         boardRegion(outcome.camera.camera, outcome.camera.board_to_camera[pose], options.board)});
    report("projector: decoded pose " + std::to_string(pose + 1) + "/" +
           std::to_string(pose_frames.size()));
  }
  ProjectorCalibrationOptions projector_options = options.projector;
  projector_options.stripe_count = layout.stripeCount();
  outcome.planes = calibrateStripePlanes(outcome.camera.camera, observations, projector_options);
  report(projectorSummary(outcome.planes, projector_options));

  if (options.joint_refinement) {
    report("joint refinement of camera, board poses and planes (Ceres)...");
    JointRefinementInput input;
    input.camera = outcome.camera.camera;
    input.board_to_camera = outcome.camera.board_to_camera;
    input.corners = outcome.camera.corners;
    input.board_points = options.board.objectPoints();
    input.planes = &outcome.planes;
    JointRefinementResult refined = refineJointly(input);
    if (refined.corner_rms_px_after > kRebalanceCornerRmsGrowth * refined.corner_rms_px_before) {
      // The stripe points pull the camera off its corners: weigh them as one group.
      report("joint refinement: corner rms " + std::to_string(refined.corner_rms_px_before) +
             " -> " + std::to_string(refined.corner_rms_px_after) +
             " px; again with the stripe points' weight capped at the corners'");
      input.balance_groups = true;
      refined = refineJointly(input);
    }
    const double plane_rms_before = outcome.planes.rms_m;
    if (refined.corner_rms_px_after > kMaxCornerRmsGrowth * refined.corner_rms_px_before) {
      std::ostringstream line;
      line << "joint refinement REFUSED: corner rms " << refined.corner_rms_px_before << " -> "
           << refined.corner_rms_px_after << " px (more than "
           << std::lround((kMaxCornerRmsGrowth - 1) * 100)
           << " % worse); the board-only camera and the plane fits are kept";
      outcome.refinement_summary = line.str();
      report(outcome.refinement_summary);
    } else {
      outcome.camera.camera = refined.camera;
      outcome.camera.board_to_camera = refined.board_to_camera;
      outcome.camera.rms_px = refined.corner_rms_px_after;
      for (size_t pose = 0; pose < observations.size(); ++pose)
        observations[pose].board_to_camera = refined.board_to_camera[pose];
      // With camera and poses at the optimum, the least-squares planes are the refined planes.
      outcome.planes = calibrateStripePlanes(refined.camera, observations, projector_options);
      std::ostringstream line;
      line << refined.summary << "; corner rms " << refined.corner_rms_px_before << " -> "
           << refined.corner_rms_px_after << " px, plane-fit rms " << plane_rms_before * 1e3
           << " -> " << outcome.planes.rms_m * 1e3 << " mm";
      outcome.refinement_summary = line.str();
      report(outcome.refinement_summary);
    }
  }

  std::vector<double> coordinates;
  for (int stripe : outcome.planes.point_stripes) coordinates.push_back(stripe + 0.5);
  outcome.pinhole = estimatePinholeProjector(outcome.planes.points, coordinates);
  report("baseline pinhole projector: rms " + std::to_string(outcome.pinhole.rms_stripes) +
         " stripes");

  outcome.calibration.pair_id = options.pair_id;
  outcome.calibration.source =
      "body_scan_calib calibrate_pair: " + std::to_string(pose_frames.size()) +
      " reference-plane poses, plane per stripe (thesis eqs 3.27-3.30)";
  outcome.calibration.camera = outcome.camera.camera;
  outcome.calibration.projector = outcome.planes.projector;
  outcome.pinhole_calibration = outcome.calibration;
  outcome.pinhole_calibration.source = "baseline: pinhole projector (2x4 projection matrix)";
  outcome.pinhole_calibration.projector =
      outcome.pinhole.projector.toStripePlanes(layout.stripeCount());
  return outcome;
}

double AccuracyEvaluation::meanPlaneEs() const {
  double sum = 0;
  for (const SphereAccuracy& s : spheres) sum += s.plane_model.e_s_m2;
  return spheres.empty() ? kNaN : sum / spheres.size();
}

double AccuracyEvaluation::meanPinholeEs() const {
  double sum = 0;
  for (const SphereAccuracy& s : spheres) sum += s.pinhole_model.e_s_m2;
  return spheres.empty() ? kNaN : sum / spheres.size();
}

double AccuracyEvaluation::improvementPercent() const {
  return 100.0 * (meanPinholeEs() - meanPlaneEs()) / meanPinholeEs();
}

AccuracyEvaluation evaluateSphereAccuracy(const body_scan_driver::PairCalibration& plane_model,
                                          const body_scan_driver::PairCalibration& pinhole_model,
                                          const std::vector<cv::Mat>& frames,
                                          const body_scan_driver::PatternLayout& layout,
                                          const std::vector<Eigen::Vector3d>& nominal_centers,
                                          const std::vector<Eigen::Vector3d>& true_centers,
                                          double radius, int exposures) {
  body_scan_driver::StripeImage stripes;
  body_scan_driver::StripeDecoder(layout).decode(frames, stripes);
  AccuracyEvaluation evaluation;
  evaluation.exposures = exposures;
  evaluation.radius_m = radius;
  // Within 1.8 radii of the nominal centre: the whole sphere even if placed a few mm off,
  // nothing of a neighbour.
  const double capture_radius = 1.8 * radius;
  const auto plane_spheres = segmentSpheres(triangulateCloud(plane_model, stripes.coordinate),
                                            nominal_centers, capture_radius);
  const auto pinhole_spheres = segmentSpheres(triangulateCloud(pinhole_model, stripes.coordinate),
                                              nominal_centers, capture_radius);
  for (size_t k = 0; k < nominal_centers.size(); ++k) {
    if (plane_spheres[k].size() < 4 || pinhole_spheres[k].size() < 4)
      throw PairCalibrationError("sphere " + std::to_string(k + 1) +
                                 ": too few reconstructed points near its nominal centre; is it "
                                 "in view, lit, and are its stripes calibrated?");
    SphereAccuracy row;
    row.number = static_cast<int>(k + 1);
    row.plane_model = fitIdealSphere(plane_spheres[k], radius);
    row.pinhole_model = fitIdealSphere(pinhole_spheres[k], radius);
    if (k < true_centers.size()) {
      row.plane_center_error_m = (row.plane_model.center - true_centers[k]).norm();
      row.pinhole_center_error_m = (row.pinhole_model.center - true_centers[k]).norm();
    }
    evaluation.spheres.push_back(row);
  }
  return evaluation;
}

namespace {

double rounded(double value, double unit) { return std::round(value / unit) * unit; }

void emitEvaluation(YAML::Emitter& out, const AccuracyEvaluation& evaluation) {
  out << YAML::BeginMap;
  out << YAML::Key << "exposures_averaged_per_pattern" << YAML::Value << evaluation.exposures;
  out << YAML::Key << "radius_mm" << YAML::Value << evaluation.radius_m * 1e3;
  auto row = [&](const std::string& key, auto value_of) {
    out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const SphereAccuracy& sphere : evaluation.spheres) out << value_of(sphere);
    out << YAML::EndSeq;
  };
  row("sphere_number", [](const SphereAccuracy& s) { return s.number; });
  row("measuring_points_plane_model", [](const SphereAccuracy& s) { return s.plane_model.points; });
  row("measuring_points_pinhole_model",
      [](const SphereAccuracy& s) { return s.pinhole_model.points; });
  row("e_s_mm2_approach_i_pinhole_projector",
      [](const SphereAccuracy& s) { return rounded(s.pinhole_model.e_s_m2 * 1e6, 1e-5); });
  row("e_s_mm2_approach_iii_plane_per_stripe",
      [](const SphereAccuracy& s) { return rounded(s.plane_model.e_s_m2 * 1e6, 1e-5); });
  row("improvement_percent", [](const SphereAccuracy& s) {
    return rounded(100 * (s.pinhole_model.e_s_m2 - s.plane_model.e_s_m2) / s.pinhole_model.e_s_m2,
                   0.1);
  });
  row("center_error_mm_pinhole_projector",
      [](const SphereAccuracy& s) { return rounded(s.pinhole_center_error_m * 1e3, 1e-3); });
  row("center_error_mm_plane_per_stripe",
      [](const SphereAccuracy& s) { return rounded(s.plane_center_error_m * 1e3, 1e-3); });
  out << YAML::Key << "mean_e_s_mm2_pinhole_projector" << YAML::Value
      << rounded(evaluation.meanPinholeEs() * 1e6, 1e-5);
  out << YAML::Key << "mean_e_s_mm2_plane_per_stripe" << YAML::Value
      << rounded(evaluation.meanPlaneEs() * 1e6, 1e-5);
  out << YAML::Key << "mean_improvement_percent" << YAML::Value
      << rounded(evaluation.improvementPercent(), 0.1);
  out << YAML::EndMap;
}

}  // namespace

std::string accuracyReportYaml(const PairCalibrationOutcome& outcome,
                               const std::vector<AccuracyEvaluation>& evaluations,
                               const std::vector<std::string>& notes) {
  YAML::Emitter out;
  out.SetDoublePrecision(6);
  out << YAML::BeginMap;
  out << YAML::Key << "pair_id" << YAML::Value << outcome.calibration.pair_id;
  out << YAML::Key << "notes" << YAML::Value << YAML::BeginSeq;
  for (const std::string& note : notes) out << note;
  out << YAML::EndSeq;
  const body_scan_driver::PinholeCamera& camera = outcome.calibration.camera;
  out << YAML::Key << "camera" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "reference_plane_poses" << YAML::Value
      << outcome.camera.board_to_camera.size();
  out << YAML::Key << "reprojection_rms_px" << YAML::Value << rounded(outcome.camera.rms_px, 1e-4);
  out << YAML::Key << "alpha_beta_gamma_u0_v0" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << rounded(camera.alpha, 1e-3) << rounded(camera.beta, 1e-3) << rounded(camera.gamma, 1e-4)
      << rounded(camera.u0, 1e-3) << rounded(camera.v0, 1e-3) << YAML::EndSeq;
  out << YAML::Key << "k1_k2" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << rounded(camera.k1, 1e-6) << rounded(camera.k2, 1e-6) << YAML::EndSeq;
  // From the camera calibration alone ((J^T J)^-1 s^2), before the joint refinement.
  out << YAML::Key << "std_dev_alpha_beta_gamma_u0_v0_k1_k2" << YAML::Value << YAML::Flow
      << YAML::BeginSeq;
  for (int i = 0; i < 7; ++i) out << outcome.camera.std_devs[i];
  out << YAML::EndSeq;
  out << YAML::EndMap;
  out << YAML::Key << "projector" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "stripes" << YAML::Value << outcome.planes.projector.stripeCount();
  out << YAML::Key << "planes_fitted" << YAML::Value
      << outcome.planes.projector.stripeCount() - outcome.planes.missing_stripes.size();
  out << YAML::Key << "stripes_stored_as_nan" << YAML::Value << YAML::Flow
      << outcome.planes.missing_stripes;
  out << YAML::Key << "stripes_from_smooth_model" << YAML::Value
      << outcome.planes.smooth_stripes.size();
  out << YAML::Key << "stripes_extrapolated_beyond_the_boards" << YAML::Value << YAML::Flow
      << outcome.planes.extrapolated_stripes;
  // Support per stripe: the poses and the points (inliers) each plane rests on.
  out << YAML::Key << "poses_per_stripe" << YAML::Value << YAML::Flow
      << outcome.planes.poses_per_stripe;
  out << YAML::Key << "points_per_stripe" << YAML::Value << YAML::Flow
      << outcome.planes.points_per_stripe;
  out << YAML::Key << "plane_fit_rms_mm" << YAML::Value
      << rounded(outcome.planes.rms_m * 1e3, 1e-5);
  out << YAML::Key << "points" << YAML::Value << outcome.planes.points.size();
  out << YAML::Key << "pinhole_baseline_rms_stripes" << YAML::Value
      << rounded(outcome.pinhole.rms_stripes, 1e-5);
  if (!outcome.refinement_summary.empty())
    out << YAML::Key << "joint_refinement" << YAML::Value << outcome.refinement_summary;
  out << YAML::EndMap;
  out << YAML::Key << "sphere_accuracy_eq_3_31" << YAML::Value << YAML::BeginSeq;
  for (const AccuracyEvaluation& evaluation : evaluations) emitEvaluation(out, evaluation);
  out << YAML::EndSeq;
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace body_scan_calib
