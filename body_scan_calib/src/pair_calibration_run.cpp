#include <body_scan_calib/capture_folder.h>
#include <body_scan_calib/pair_calibration_run.h>
#include <body_scan_calib/projector_plot.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/calibration_file.h>

#include <cstdio>
#include <filesystem>
#include <iostream>

namespace body_scan_calib {

namespace fs = std::filesystem;

namespace {

void progress(const std::string& message) { std::cout << "  " << message << std::endl; }

// The accuracy tables of the sphere captures and the report's notes on how they were taken.
struct AccuracySection {
  std::vector<AccuracyEvaluation> evaluations;
  std::vector<std::string> notes;
};

AccuracySection evaluateAccuracy(const PairViews& views, const PairCalibrationOutcome& outcome) {
  AccuracySection section;
  section.notes = {
      "E_s (thesis eq 3.31) of the ideal sphere (radius fixed at 25 mm) fitted to each "
      "sphere's points, per model; spheres numbered top left to bottom right (Fig 3.7).",
      "Capture protocol: the static board and spheres are captured " +
          std::to_string(views.exposures) +
          " times and the frames of each pattern averaged (sensor noise down by sqrt of the "
          "count); both models triangulate the same decoded stripe image."};
  if (views.sphere_frames.empty()) {
    section.notes.push_back("No sphere capture (FOLDER/spheres): accuracy not evaluated.");
    return section;
  }
  std::cout << "evaluating on the five spheres" << std::endl;
  section.evaluations.push_back(evaluateSphereAccuracy(
      outcome.calibration, outcome.pinhole_calibration, views.sphere_frames, views.layout,
      views.nominal_centers, views.true_centers, views.sphere_radius_m, views.exposures));
  if (!views.sphere_single_frames.empty()) {
    section.evaluations.push_back(evaluateSphereAccuracy(
        outcome.calibration, outcome.pinhole_calibration, views.sphere_single_frames, views.layout,
        views.nominal_centers, views.true_centers, views.sphere_radius_m, 1));
    section.notes.push_back(
        "The second table is a single capture of the spheres (same calibration): decoding "
        "noise then dominates E_s for both models.");
  }
  if (views.truth) {
    // The same capture triangulated with the simulator's true planes and camera: what decoding
    // alone costs, the floor any calibration can reach.
    const AccuracyEvaluation floor = evaluateSphereAccuracy(
        *views.truth, outcome.pinhole_calibration, views.sphere_frames, views.layout,
        views.nominal_centers, views.true_centers, views.sphere_radius_m, views.exposures);
    char note[256];
    std::snprintf(note, sizeof(note),
                  "Decoding floor: the first capture triangulated with the simulator's TRUE "
                  "calibration gives mean E_s %.4f mm^2 (the plane model: %.4f).",
                  floor.meanPlaneEs() * 1e6, section.evaluations.front().meanPlaneEs() * 1e6);
    section.notes.push_back(note);
    std::cout << "  " << note << std::endl;
  }
  return section;
}

void printAccuracyTables(const std::vector<AccuracyEvaluation>& evaluations) {
  for (const AccuracyEvaluation& evaluation : evaluations) {
    std::printf("  E_s [mm^2], %d exposure(s) per pattern\n  sphere   pinhole   plane\n",
                evaluation.exposures);
    for (const SphereAccuracy& row : evaluation.spheres)
      std::printf("  %6d  %8.4f  %8.4f\n", row.number, row.pinhole_model.e_s_m2 * 1e6,
                  row.plane_model.e_s_m2 * 1e6);
    std::printf("  mean    %8.4f  %8.4f  (plane model %.1f%% lower)\n",
                evaluation.meanPinholeEs() * 1e6, evaluation.meanPlaneEs() * 1e6,
                evaluation.improvementPercent());
  }
  std::fflush(stdout);
}

}  // namespace

PairViews loadPairViews(const std::string& folder, int bits, int exposures) {
  return loadPairViews(folder, captureLayout("project"), CaptureBits{bits, 0}, exposures);
}

PairViews loadPairViews(const std::string& folder, const CaptureLayout& layout,
                        const CaptureBits& bits, int exposures) {
  PairViews views;
  views.layout = body_scan_driver::PatternLayout(bits.stripe_bits, true);
  views.exposures = exposures;
  std::cout << "reading " << folder << " (" << layout.name << " layout)" << std::endl;
  for (CapturedPatternSet& pose : loadCapturedPoses(folder, layout, bits)) {
    views.pose_frames.push_back(std::move(pose.frames));
    views.pose_cross_frames.push_back(std::move(pose.cross_frames));
  }
  const fs::path spheres = fs::path(folder) / "spheres";
  if (fs::is_directory(spheres))
    views.sphere_frames = loadPatternFrames(spheres.string(), views.layout);
  return views;
}

PairCalibrationOutcome calibratePairToFiles(const PairViews& views,
                                            const PairCalibrationOptions& options,
                                            const PairCalibrationFiles& files) {
  std::cout << "calibrating from " << views.pose_frames.size() << " reference-plane poses"
            << std::endl;
  const PairCalibrationOutcome outcome =
      calibratePair(views.pose_frames, views.layout, options, progress, views.pose_cross_frames);
  for (int stripe : outcome.planes.missing_stripes)
    if (outcome.planes.poses_per_stripe[stripe] > 0)
      std::cout << "  stripe " << stripe << " seen on " << outcome.planes.poses_per_stripe[stripe]
                << " poses: not calibrated (NaN plane; it triangulates to nothing)\n";
  body_scan_driver::saveCalibration(files.calibration, outcome.calibration);
  std::cout << "wrote " << files.calibration << std::endl;

  const AccuracySection accuracy = evaluateAccuracy(views, outcome);
  printAccuracyTables(accuracy.evaluations);
  body_scan_driver::writeFileAtomically(
      files.report, accuracyReportYaml(outcome, accuracy.evaluations, accuracy.notes));
  std::cout << "wrote " << files.report << std::endl;
  writePngAtomically(files.plot,
                     plotProjectorParameters(outcome.calibration.projector,
                                             views.truth ? &views.truth->projector : nullptr));
  std::cout << "wrote " << files.plot << std::endl;
  return outcome;
}

}  // namespace body_scan_calib
