// Calibrates one projector-camera pair from reference-plane poses (thesis sec. 3.3) and evaluates
// it on five spheres (sec. 3.4.2) beside the pinhole-projector baseline. Live against the
// simulator, or offline from an image folder. Writes the calibration file, the accuracy report
// (YAML) and the Fig 3.6 plot (PNG), all atomically.
#include <body_scan_calib/calibration_rig.h>
#include <body_scan_calib/capture_folder.h>
#include <body_scan_calib/pair_calibration_pipeline.h>
#include <body_scan_calib/projector_plot.h>
#include <body_scan_calib/sim/calibration_scenes.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/tools/command_line.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <string>

using namespace body_scan_driver;
namespace fs = std::filesystem;

namespace {

struct Arguments {
  bool live = false;
  std::string images, pair, pair_id, save_images;
  int exposures = 16, bits = 8;
  bool refinement = true;
  std::string output = "calibration/pair.yaml", report = "calibration/pair_accuracy.yaml",
              plot = "calibration/projector_parameters.png";
};

// Returns the exit status when the tool should stop (--help, a usage error).
std::optional<int> parse(int argc, char** argv, Arguments& arguments) {
  CLI::App app(
      "Calibrates one projector-camera pair from reference-plane poses (thesis sec. 3.3) and "
      "evaluates it on five spheres (sec. 3.4.2) beside the pinhole-projector baseline. Live "
      "against the simulator (--live), or offline from an image folder (--images).",
      "calibrate_pair");
  auto* live =
      app.add_flag("--live", arguments.live, "place the board in its poses in the simulator");
  auto* images =
      app.add_option("--images", arguments.images,
                     "recorded captures: FOLDER/pose_NN/frame_MM.png (pattern frames in "
                     "PatternSet order, >= 3 poses), optional FOLDER/spheres/frame_MM.png to "
                     "evaluate")
          ->check(CLI::ExistingDirectory);
  live->excludes(images);
  app.add_option("--pair", arguments.pair,
                 "virtual pair file (default: the built-in default pair); its pair_id names the "
                 "calibration (camera_name) and the report")
      ->check(CLI::ExistingFile)
      ->needs(live);
  app.add_option("--pair-id", arguments.pair_id,
                 "pair id written into the files (offline: default \"pair\"; live: overrides the "
                 "pair file's), e.g. pole_a/pair_1");
  app.add_option("--exposures", arguments.exposures,
                 "frames averaged per pattern for the static targets (offline: how many the "
                 "recorded frames average, for the report)")
      ->capture_default_str()
      ->check(body_scan_driver::tools::atLeast(1));
  app.add_option("--bits", arguments.bits, "Gray code bits of the captures (live: from the pair)")
      ->capture_default_str()
      ->check(CLI::Range(body_scan_driver::kMinBits, body_scan_driver::kMaxBits));
  app.add_option("--output", arguments.output, "calibration file")->capture_default_str();
  app.add_option("--report", arguments.report, "accuracy report")->capture_default_str();
  app.add_option("--plot", arguments.plot, "projector parameters plot")->capture_default_str();
  app.add_option("--save-images", arguments.save_images,
                 "live: also write the captures in the --images layout")
      ->needs(live);
  bool no_refinement = false;
  app.add_flag("--no-refinement", no_refinement, "skip the joint Ceres refinement");
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv)) return status;
  arguments.refinement = !no_refinement;
  if (arguments.live == !arguments.images.empty()) {
    std::cerr << "calibrate_pair: give exactly one of --live and --images FOLDER\nRun with --help "
                 "for more information.\n";
    return 2;
  }
  return std::nullopt;
}

void progress(const std::string& message) { std::cout << "  " << message << std::endl; }

}  // namespace

int main(int argc, char** argv) {
  Arguments arguments;
  if (const auto status = parse(argc, argv, arguments)) return *status;
  try {
    const auto start = std::chrono::steady_clock::now();
    body_scan_calib::PairCalibrationOptions options;
    options.joint_refinement = arguments.refinement;
    std::vector<std::vector<cv::Mat>> pose_frames;
    std::vector<cv::Mat> sphere_frames, sphere_single_frames;
    std::vector<Eigen::Vector3d> true_centers;
    const std::vector<Eigen::Vector3d> nominal_centers =
        body_scan_calib::rig::defaultSphereCenters();
    constexpr double kSphereRadius = 0.025;
    std::unique_ptr<body_scan_driver::PairCalibration> truth;
    std::unique_ptr<body_scan_driver::PatternLayout> layout;
    if (!arguments.pair_id.empty()) options.pair_id = arguments.pair_id;

    if (arguments.live) {
      body_scan_driver::sim::VirtualPairConfig config =
          arguments.pair.empty() ? body_scan_driver::sim::VirtualPairConfig{}
                                 : body_scan_driver::sim::loadVirtualPairConfig(arguments.pair);
      if (arguments.pair_id.empty()) options.pair_id = config.pair_id;
      layout =
          std::make_unique<body_scan_driver::PatternLayout>(config.bits, config.inverse_frames);
      const auto poses = body_scan_calib::rig::defaultBoardPoses();
      for (size_t pose = 0; pose < poses.size(); ++pose) {
        std::cout << "placing the board in pose " << pose + 1 << "/" << poses.size()
                  << ", capturing " << arguments.exposures << " exposures" << std::endl;
        const body_scan_driver::sim::VirtualPair pair(
            config,
            body_scan_calib::rig::boardScene(options.board, poses[pose], config.world_from_camera));
        pose_frames.push_back(body_scan_calib::rig::captureAveraged(
            pair, arguments.exposures, static_cast<uint32_t>(1000 * pose)));
        if (!arguments.save_images.empty())
          body_scan_calib::savePatternFrames(
              (fs::path(arguments.save_images) /
               body_scan_calib::poseFolderName(static_cast<int>(pose)))
                  .string(),
              pose_frames.back());
      }
      std::cout << "placing the five evaluation spheres, capturing " << arguments.exposures
                << " exposures" << std::endl;
      const body_scan_driver::sim::VirtualPair sphere_pair(
          config, body_scan_calib::rig::sphereScene(nominal_centers, kSphereRadius,
                                                    config.world_from_camera));
      sphere_frames =
          body_scan_calib::rig::captureAveraged(sphere_pair, arguments.exposures, 90000);
      sphere_single_frames = body_scan_calib::rig::captureAveraged(sphere_pair, 1, 99000);
      if (!arguments.save_images.empty())
        body_scan_calib::savePatternFrames((fs::path(arguments.save_images) / "spheres").string(),
                                           sphere_frames);
      true_centers = nominal_centers;  // the simulator places them exactly
      truth = std::make_unique<body_scan_driver::PairCalibration>(sphere_pair.factoryCalibration());
    } else {
      layout = std::make_unique<body_scan_driver::PatternLayout>(arguments.bits, true);
      std::cout << "reading " << arguments.images << std::endl;
      pose_frames = body_scan_calib::loadPoseCaptures(arguments.images, *layout);
      const fs::path spheres = fs::path(arguments.images) / "spheres";
      if (fs::is_directory(spheres))
        sphere_frames = body_scan_calib::loadPatternFrames(spheres.string(), *layout);
    }

    std::cout << "calibrating from " << pose_frames.size() << " reference-plane poses" << std::endl;
    const body_scan_calib::PairCalibrationOutcome outcome =
        body_scan_calib::calibratePair(pose_frames, *layout, options, progress);
    for (int stripe : outcome.planes.missing_stripes)
      std::cout << "  stripe " << stripe << " seen on " << outcome.planes.poses_per_stripe[stripe]
                << " poses: not calibrated (NaN plane; it triangulates to nothing)\n";
    saveCalibration(arguments.output, outcome.calibration);
    std::cout << "wrote " << arguments.output << std::endl;

    std::vector<body_scan_calib::AccuracyEvaluation> evaluations;
    std::vector<std::string> notes = {
        "E_s (thesis eq 3.31) of the ideal sphere (radius fixed at 25 mm) fitted to each "
        "sphere's points, per model; spheres numbered top left to bottom right (Fig 3.7).",
        "Capture protocol: the static board and spheres are captured " +
            std::to_string(arguments.exposures) +
            " times and the frames of each pattern averaged (sensor noise down by sqrt of the "
            "count); both models triangulate the same decoded stripe image."};
    if (!sphere_frames.empty()) {
      std::cout << "evaluating on the five spheres" << std::endl;
      evaluations.push_back(body_scan_calib::evaluateSphereAccuracy(
          outcome.calibration, outcome.pinhole_calibration, sphere_frames, *layout, nominal_centers,
          true_centers, kSphereRadius, arguments.exposures));
      if (!sphere_single_frames.empty()) {
        evaluations.push_back(body_scan_calib::evaluateSphereAccuracy(
            outcome.calibration, outcome.pinhole_calibration, sphere_single_frames, *layout,
            nominal_centers, true_centers, kSphereRadius, 1));
        notes.push_back(
            "The second table is a single capture of the spheres (same calibration): decoding "
            "noise then dominates E_s for both models.");
      }
      if (truth) {
        // The same capture triangulated with the simulator's true planes and camera: what
        // decoding alone costs, the floor any calibration can reach.
        const body_scan_calib::AccuracyEvaluation floor = body_scan_calib::evaluateSphereAccuracy(
            *truth, outcome.pinhole_calibration, sphere_frames, *layout, nominal_centers,
            true_centers, kSphereRadius, arguments.exposures);
        char note[256];
        std::snprintf(note, sizeof(note),
                      "Decoding floor: the first capture triangulated with the simulator's TRUE "
                      "calibration gives mean E_s %.4f mm^2 (the plane model: %.4f).",
                      floor.meanPlaneEs() * 1e6, evaluations.front().meanPlaneEs() * 1e6);
        notes.push_back(note);
        std::cout << "  " << note << std::endl;
      }
      for (const body_scan_calib::AccuracyEvaluation& evaluation : evaluations) {
        std::printf("  E_s [mm^2], %d exposure(s) per pattern\n  sphere   pinhole   plane\n",
                    evaluation.exposures);
        for (const body_scan_calib::SphereAccuracy& row : evaluation.spheres)
          std::printf("  %6d  %8.4f  %8.4f\n", row.number, row.pinhole_model.e_s_m2 * 1e6,
                      row.plane_model.e_s_m2 * 1e6);
        std::printf("  mean    %8.4f  %8.4f  (plane model %.1f%% lower)\n",
                    evaluation.meanPinholeEs() * 1e6, evaluation.meanPlaneEs() * 1e6,
                    evaluation.improvementPercent());
      }
    } else {
      notes.push_back("No sphere capture (FOLDER/spheres): accuracy not evaluated.");
    }
    writeFileAtomically(arguments.report,
                        body_scan_calib::accuracyReportYaml(outcome, evaluations, notes));
    std::cout << "wrote " << arguments.report << std::endl;
    body_scan_calib::writePngAtomically(
        arguments.plot, body_scan_calib::plotProjectorParameters(
                            outcome.calibration.projector, truth ? &truth->projector : nullptr));
    std::cout << "wrote " << arguments.plot << " ("
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
              << " s)" << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
