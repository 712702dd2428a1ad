// Evaluation CLI of gait recognition (issue 6 item 5; thesis 5.8.3-5.8.4): simulated people
// walk through the scanner, every representative pose is scanned and fitted, gait cycles are
// reconstructed and identified; prints a table beside the thesis's figures and writes a YAML
// report and a CMC / ROC plot.
//
//   evaluate_gait_id [--protocol thesis|cross-walk] [--subjects N] [--scanner sampler|full|truth]
//                    [--columns C] [--noise SIGMA_M] [--threads T] [--cache DIR] [--seed S]
//                    [--transform none|pca|lda] [--components K] [--rows all|3d]
//                    [--probe-frames interpolated|all|scans] [--per-walk 1] [--gallery-walks N]
//                    [--shape 1] [--noise-seed S2 [--noise-subjects N2] [--noise-first K]]
//                    [--walk-body mean|median]
//                    [--write-noise FILE.yaml | --noise-file FILE.yaml] [--robust-sigmas C]
//                    [--measure-noise 1]
//                    [--report FILE.yaml] [--plot FILE.png] [--quiet 1]
//                    [--bvh [PERSON=]WALK.bvh,... [--bvh-map MAP.yaml]]
//
// --bvh (issue 7): the people are motion-capture walks instead of simulated people; walk t of a
// person is trial t (the cross-walk protocol needs 2 walks per person), its 4 poses are the ones
// body_scan_driver's pickGaitPoses finds; PERSON defaults to the file name up to its first '_'
// (CMU: 07_02.bvh -> 07). --bvh-map: the joint map (default: the CMU map of body_scan_driver).
//
// --scanner truth skips scan and fit (models read off the simulator's skeleton): the upper
// bound of the features on these people, to tell the fitter's share of the errors.
// --gallery-walks N (cross-walk): enrol every person from walks 0 .. N - 1 (eta1 + eta2 of each),
// probe with walk N (default 1).
// --per-walk 1 (cross-walk) adds the 3D rows with one decision per probe walk (the mean of a
// subject's scores over the walk's 20 frames) beside the per-frame decisions.
// Beyond the thesis (issue 6, cross-walk): --shape 1 adds the 3D dynamic+static+shape row
// (bodyShapeFeatures); --noise-seed S2 fits N2 (default 50) other people (seed S2, two walks) to
// learn each feature component's within-subject noise (--noise-first K: persons K..K+N2-1 of
// seed S2, so with S2 = S and K >= N the test seed's later people serve) and adds the
// noise-weighted 3D rows (noiseWeights); --walk-body median takes each walk's body measures as the
// median of its four fits instead of eq 5.13's mean; --write-noise saves the learned noise for
// gait_id_node's ~feature_noise and gait_gallery's --feature-noise, --noise-file weighs by a saved
// noise instead of learning it; --robust-sigmas C adds weighted rows whose distance counts each
// component at most C noise SDs (robust to one failed component; brute force); --measure-noise 1
// prints how steady each body measure is between a person's walks against its spread between
// people. Thesis protocol: the probes are eta3's 16 interpolated frames per person as in the thesis
// (96 poses of 6 subjects);
// --probe-frames all adds the 4 representative frames, which are in the training sets too.
// --probe-frames scans (cross-walk): the probes are walk 1's 4 fits as single scans, each with
// its own body, as gait_id_node sees a person scanned once; with --noise-seed the noise is
// learned the same way (single scans against the other walk's median body).
// Cross-walk: all 20 frames of walk 1 (no overlap with walk 0).
#include <body_gait_id/eval/gait_id_evaluation.h>
#include <body_gait_id/feature_noise_file.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <body_scan_driver/atomic_file.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace {

using namespace body_gait_id::eval;

[[noreturn]] void usage(const std::string& problem) {
  std::fprintf(
      stderr,
      "evaluate_gait_id: %s\n"
      "usage: evaluate_gait_id [--protocol thesis|cross-walk] [--subjects N (>= 2; "
      "default 6, cross-walk 50)] [--scanner sampler|full|truth] [--columns C (>= 20)] "
      "[--noise SIGMA_M] [--threads T (1-16)] [--cache DIR] [--seed S] "
      "[--transform none|pca|lda] [--components K] [--rows all|3d] "
      "[--probe-frames interpolated|all|scans] [--per-walk 1] [--gallery-walks N] [--shape 1] "
      "[--noise-seed S2 [--noise-subjects N2 (default 50)] [--noise-first K]] "
      "[--walk-body mean|median] [--write-noise FILE.yaml | --noise-file FILE.yaml] "
      "[--robust-sigmas C] [--measure-noise 1] [--report FILE.yaml] [--plot FILE.png] "
      "[--quiet 1] [--bvh [PERSON=]WALK.bvh,... [--bvh-map MAP.yaml]]\n",
      problem.c_str());
  std::exit(2);
}

double number(const char* text, const std::string& flag) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0') usage(flag + " needs a number, got '" + text + "'");
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  std::string protocol = "thesis", report_path, plot_path, rows_choice = "all", noise_path,
              noise_file;
  int subjects = 0;
  std::uint32_t seed = 1;
  ScanOptions scan;
  TransformOptions transform;
  ProbeFrames probe_frames = ProbeFrames::kInterpolated;
  bool per_walk = false, measure_noise = false, shape = false, median_body = false;
  int gallery_walks = 1;
  std::vector<std::string> bvh_files;
  std::string bvh_map = BODY_SCAN_DRIVER_CONFIG_DIR "/bvh/cmu_joint_map.yaml";
  std::uint32_t noise_seed = 0;  // 0: no noise-weighted rows
  int noise_subjects = 50;
  int noise_first = 0;       // the development people are persons noise_first.. of the noise seed
  double robust_sigmas = 0;  // > 0: also the weighted rows with the truncated distance
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--help" || flag == "-h") usage("evaluates gait identification");
    if (i + 1 >= argc) usage("missing value after " + flag);
    const char* value = argv[++i];
    if (flag == "--protocol") {
      protocol = value;
      if (protocol != "thesis" && protocol != "cross-walk")
        usage("--protocol must be thesis or cross-walk, got '" + protocol + "'");
    } else if (flag == "--subjects") {
      subjects = static_cast<int>(number(value, flag));
    } else if (flag == "--scanner") {
      const std::string kind = value;
      if (kind == "full")
        scan.scanner = ScannerKind::kFull;
      else if (kind == "sampler")
        scan.scanner = ScannerKind::kSampler;
      else if (kind == "truth")
        scan.scanner = ScannerKind::kTruth;
      else
        usage("--scanner must be sampler, full or truth, got '" + kind + "'");
    } else if (flag == "--columns") {
      scan.sampler_columns = static_cast<int>(number(value, flag));
    } else if (flag == "--noise") {
      scan.sampler_noise = number(value, flag);
    } else if (flag == "--threads") {
      scan.threads = static_cast<int>(number(value, flag));
    } else if (flag == "--cache") {
      scan.cache_folder = value;
    } else if (flag == "--seed") {
      seed = static_cast<std::uint32_t>(number(value, flag));
    } else if (flag == "--transform") {
      const std::string kind = value;
      if (kind == "none")
        transform.kind = FeatureTransform::kNone;
      else if (kind == "pca")
        transform.kind = FeatureTransform::kPca;
      else if (kind == "lda")
        transform.kind = FeatureTransform::kLda;
      else
        usage("--transform must be none, pca or lda, got '" + kind + "'");
    } else if (flag == "--components") {
      transform.components = static_cast<int>(number(value, flag));
    } else if (flag == "--rows") {
      rows_choice = value;
      if (rows_choice != "all" && rows_choice != "3d")
        usage("--rows must be all or 3d, got '" + rows_choice + "'");
    } else if (flag == "--probe-frames") {
      const std::string kind = value;
      if (kind == "interpolated")
        probe_frames = ProbeFrames::kInterpolated;
      else if (kind == "all")
        probe_frames = ProbeFrames::kAll;
      else if (kind == "scans")
        probe_frames = ProbeFrames::kSingleScans;
      else
        usage("--probe-frames must be interpolated, all or scans, got '" + kind + "'");
    } else if (flag == "--report") {
      report_path = value;
    } else if (flag == "--plot") {
      plot_path = value;
    } else if (flag == "--per-walk") {
      per_walk = number(value, flag) != 0;
    } else if (flag == "--gallery-walks") {
      gallery_walks = static_cast<int>(number(value, flag));
      if (gallery_walks < 1 || gallery_walks > 5) usage("--gallery-walks must be 1..5");
    } else if (flag == "--bvh") {
      std::stringstream list(value);
      for (std::string file; std::getline(list, file, ',');) bvh_files.push_back(file);
    } else if (flag == "--bvh-map") {
      bvh_map = value;
    } else if (flag == "--shape") {
      shape = number(value, flag) != 0;
    } else if (flag == "--noise-seed") {
      noise_seed = static_cast<std::uint32_t>(number(value, flag));
    } else if (flag == "--robust-sigmas") {
      robust_sigmas = number(value, flag);
    } else if (flag == "--noise-first") {
      noise_first = static_cast<int>(number(value, flag));
    } else if (flag == "--noise-subjects") {
      noise_subjects = static_cast<int>(number(value, flag));
    } else if (flag == "--noise-file") {
      noise_file = value;
    } else if (flag == "--write-noise") {
      noise_path = value;
    } else if (flag == "--walk-body") {
      const std::string kind = value;
      if (kind != "mean" && kind != "median")
        usage("--walk-body must be mean or median, got '" + kind + "'");
      median_body = kind == "median";
    } else if (flag == "--measure-noise") {
      measure_noise = number(value, flag) != 0;
    } else if (flag == "--quiet") {
      scan.progress = number(value, flag) == 0;
    } else {
      usage("unknown option " + flag);
    }
  }
  const bool cross_walk = protocol == "cross-walk";
  if (gallery_walks > 1 && !cross_walk) usage("--gallery-walks is for --protocol cross-walk");
  const int trials = cross_walk ? gallery_walks + 1 : 1;
  PersonSource people;
  if (!bvh_files.empty()) {
    if (subjects != 0) usage("--subjects and --bvh exclude each other (the files are the people)");
    try {
      std::vector<std::string> picked;
      people = bvhPeople(bvh_files, bvh_map, trials, &picked);
      for (const std::string& line : picked) std::printf("%s\n", line.c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "evaluate_gait_id: %s\n", e.what());
      return 1;
    }
    subjects = int(people.names.size());
  }
  if (subjects == 0) subjects = cross_walk ? 50 : 6;
  if (subjects < 2) usage("--subjects must be >= 2 (identification needs a choice)");
  if (probe_frames == ProbeFrames::kSingleScans && !cross_walk)
    usage(
        "--probe-frames scans is for the cross-walk protocol (the thesis protocol's scans "
        "are its gallery)");
  if (scan.sampler_columns < 20) usage("--columns must be >= 20");
  if (scan.threads < 1 || scan.threads > 16) usage("--threads must be 1..16");
  if (noise_first < 0) usage("--noise-first must be >= 0");
  if (noise_seed != 0 && noise_seed == seed && noise_first < subjects)
    usage(
        "--noise-seed equals --seed: give --noise-first >= --subjects, so the noise is "
        "learned on other people");
  if (noise_seed != 0 && noise_subjects < 2) usage("--noise-subjects must be >= 2");
  if (!noise_file.empty() && noise_seed != 0)
    usage("give --noise-seed (learn the noise) or --noise-file (read it), not both");
  if (!noise_path.empty() && noise_seed == 0)
    usage("--write-noise needs --noise-seed (the people the noise is learned on)");

  std::vector<body_gait_model::eval::SimulatedPerson> persons;
  if (bvh_files.empty()) {
    persons = body_gait_model::eval::simulatedPeople(subjects, seed);
    for (const auto& person : persons) people.names.push_back(person.name);
    people.spec = [&persons](int person, int pose, int trial, double heading) {
      return body_gait_model::eval::walkingSubject(persons[person], pose, trial, heading);
    };
  }

  std::vector<FeatureRow> rows = thesisRows();
  if (rows_choice == "3d") rows.resize(2);
  std::vector<FeatureRow> rows_3d(rows.begin(), rows.begin() + 2);
  if (shape) {
    rows.insert(rows.begin() + 2, shapeRow());
    rows_3d.push_back(shapeRow());
  }
  FitSummary summary;
  std::vector<NamedMetrics> results;
  try {
    FittedWalks walks = fitWalks(people, trials, scan, &summary);
    // Walks the protocols leave out: a pose not fitted, or fits with no forward stride (the gait
    // cycle cannot be rebuilt). Their people are not counted in the rates below.
    for (size_t person = 0; person < walks.size(); ++person)
      for (size_t trial = 0; trial < walks[person].size(); ++trial) {
        std::string reason = "a pose was not fitted";
        if (const auto& poses = walks[person][trial]) {
          try {
            for (const auto set : {body_gait_model::GaitSet::kEta1, body_gait_model::GaitSet::kEta2,
                                   body_gait_model::GaitSet::kEta3})
              body_gait_model::reconstructGaitCycle(body_gait_model::gaitSet(*poses, set));
            continue;
          } catch (const std::invalid_argument& e) {
            reason = e.what();
          }
        }
        std::printf("  left out: %s walk %zu: %s\n", people.names[person].c_str(), trial,
                    reason.c_str());
      }
    // Single-scan probes keep each fit's own body; the gallery walks take the median.
    const bool single_scans = probe_frames == ProbeFrames::kSingleScans;
    const ProbeFrames cross_probes = single_scans ? ProbeFrames::kSingleScans : ProbeFrames::kAll;
    if (median_body)
      walks = single_scans ? withMedianBody(std::move(walks), gallery_walks)
                           : withMedianBody(std::move(walks));
    TransformOptions weighted;
    if (noise_seed != 0) {
      // Development people (another seed: nobody of the test set) with two walks each.
      // Persons 0 .. noise_first - 1 are fitted too (their scans keep their index, so the
      // cache serves them) and then left out.
      const std::vector<body_gait_model::eval::SimulatedPerson> development =
          body_gait_model::eval::simulatedPeople(noise_first + noise_subjects, noise_seed);
      PersonSource dev;
      for (const auto& person : development) dev.names.push_back(person.name);
      dev.spec = [&development](int person, int pose, int trial, double heading) {
        return body_gait_model::eval::walkingSubject(development[person], pose, trial, heading);
      };
      FittedWalks dev_walks = fitWalks(dev, 2, scan);
      dev_walks.erase(dev_walks.begin(), dev_walks.begin() + noise_first);
      if (median_body)
        dev_walks = single_scans ? withMedianBody(std::move(dev_walks), 1)
                                 : withMedianBody(std::move(dev_walks));
      weighted.kind = FeatureTransform::kNoiseWeighted;
      weighted.noise = crossWalkNoise(dev_walks, body_gait_id::View::k3D, 0, 1, single_scans);
      if (!noise_path.empty()) {
        const std::string source = std::string(scan.scanner == ScannerKind::kFull      ? "full"
                                               : scan.scanner == ScannerKind::kSampler ? "sampler"
                                                                                       : "truth") +
                                   " scanner, " + std::to_string(noise_subjects) + " people from " +
                                   std::to_string(noise_first) + ", seed " +
                                   std::to_string(noise_seed) + ", " +
                                   (median_body ? "median" : "mean") + " body of a walk" +
                                   (single_scans ? ", single-scan probes" : "");
        body_scan_driver::writeFileAtomically(
            noise_path, body_gait_id::featureNoiseYaml(weighted.noise, source));
      }
    }
    if (measure_noise && cross_walk) {
      std::printf("%-30s %9s %9s %9s %7s\n", "measure (walk = mean of 4 fits)", "mean", "between",
                  "within", "F");
      for (const MeasureNoise& m : bodyMeasureNoise(walks))
        std::printf("%-30s %9.4f %9.4f %9.4f %7.2f\n", m.name.c_str(), m.mean, m.between_sd,
                    m.within_sd, m.within_sd > 0 ? std::pow(m.between_sd / m.within_sd, 2) : 0.0);
    }
    results = cross_walk ? crossWalkProtocol(walks, rows, {}, false, gallery_walks, cross_probes)
                         : thesisProtocol(walks, rows, {}, probe_frames);
    auto add = [&results](std::vector<NamedMetrics> extra) {
      for (NamedMetrics& r : extra) results.push_back(std::move(r));
    };
    if (transform.kind != FeatureTransform::kNone)
      add(cross_walk
              ? crossWalkProtocol(walks, rows_3d, transform, false, gallery_walks, cross_probes)
              : thesisProtocol(walks, rows_3d, transform, probe_frames));
    if (!noise_file.empty()) {
      weighted.kind = FeatureTransform::kNoiseWeighted;
      weighted.noise = body_gait_id::readFeatureNoise(noise_file);
    }
    TransformOptions robust = weighted;
    robust.truncate_sigmas = robust_sigmas;
    const bool with_robust = weighted.kind == FeatureTransform::kNoiseWeighted && robust_sigmas > 0;
    if (with_robust)
      add(cross_walk ? crossWalkProtocol(walks, rows_3d, robust, false, gallery_walks, cross_probes)
                     : thesisProtocol(walks, rows_3d, robust, probe_frames));
    if (weighted.kind == FeatureTransform::kNoiseWeighted)
      add(cross_walk
              ? crossWalkProtocol(walks, rows_3d, weighted, false, gallery_walks, cross_probes)
              : thesisProtocol(walks, rows_3d, weighted, probe_frames));
    if (per_walk && cross_walk) {
      add(crossWalkProtocol(walks, rows_3d, {}, true, gallery_walks, cross_probes));
      if (transform.kind != FeatureTransform::kNone)
        add(crossWalkProtocol(walks, rows_3d, transform, true, gallery_walks, cross_probes));
      if (weighted.kind == FeatureTransform::kNoiseWeighted)
        add(crossWalkProtocol(walks, rows_3d, weighted, true, gallery_walks, cross_probes));
      if (with_robust)
        add(crossWalkProtocol(walks, rows_3d, robust, true, gallery_walks, cross_probes));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "evaluate_gait_id: %s\n", e.what());
    return 1;
  }

  const char* scanner_name = scan.scanner == ScannerKind::kFull      ? "full"
                             : scan.scanner == ScannerKind::kSampler ? "sampler"
                                                                     : "truth (no scan, no fit)";
  std::printf(
      "%s protocol, %d people, %s scanner: %d scans (%d cached, %d failed, %d low quality) "
      "in %.1f s\n",
      protocol.c_str(), subjects, scanner_name, summary.scans, summary.cached, summary.failed,
      summary.low_quality, summary.seconds);
  for (const std::string& failure : summary.failures)
    std::printf("  failed: %s\n", failure.c_str());
  std::printf("%s", recognitionTable(results).c_str());
  for (const NamedMetrics& r : results) {
    const RecognitionMetrics& m = r.metrics;
    std::printf("%-42s CMC", r.name.c_str());
    for (const Proportion& p : m.cmc) std::printf(" %.2f", 100 * p.rate);
    if (m.open_set)
      std::printf(" | open set: threshold %.3f, FNIR %.2f %%%s, FPIR %.2f %% [%.2f, %.2f] (n %d)",
                  m.open_set->threshold, 100 * m.open_set->fnir.rate,
                  m.open_set->target_reached ? "" : " (5 % not reachable)",
                  100 * m.open_set->fpir.rate, 100 * m.open_set->fpir.ci_low,
                  100 * m.open_set->fpir.ci_high, m.open_set->fpir.n);
    std::printf("\n");
  }

  RecognitionReport report;
  report.settings = {
      {"protocol", protocol},
      {"people", bvh_files.empty() ? "simulated" : "motion capture (BVH)"},
      {"subjects", std::to_string(subjects)},
      {"gallery_walks", std::to_string(cross_walk ? gallery_walks : 1)},
      {"scanner", scanner_name},
      {"seed", std::to_string(seed)},
      {"probe_frames", probe_frames == ProbeFrames::kSingleScans ? "single scans (walk 1's 4 fits)"
                       : cross_walk                              ? "all (walk 1)"
                       : probe_frames == ProbeFrames::kAll       ? "all"
                                                                 : "interpolated"},
      {"scans", std::to_string(summary.scans)},
      {"cached_scans", std::to_string(summary.cached)},
      {"failed_scans", std::to_string(summary.failed)},
      {"low_quality_fits", std::to_string(summary.low_quality)},
      {"scan_and_fit_seconds", std::to_string(summary.seconds)}};
  if (scan.scanner == ScannerKind::kSampler) {
    report.settings.push_back({"sampler_columns", std::to_string(scan.sampler_columns)});
    report.settings.push_back({"sampler_noise_m", std::to_string(scan.sampler_noise)});
  }
  report.results = results;
  try {
    if (!report_path.empty()) writeRecognitionReport(report_path, report);
    if (!plot_path.empty()) writePng(plot_path, plotPanels(cmcAndRocPanels(results)));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "evaluate_gait_id: %s\n", e.what());
    return 1;
  }
  return 0;
}
