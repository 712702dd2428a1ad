// Evaluation CLI of gait recognition (thesis 5.8.3-5.8.4): simulated people
// walk through the scanner, every representative pose is scanned and fitted, gait cycles are
// reconstructed and identified; prints a table beside the thesis's figures and writes a YAML
// report and a CMC / ROC plot.
//
//   evaluate_gait_id [--protocol thesis|cross-walk] [--subjects N] [--scanner sampler|full|truth]
//                    [--fit walk|scan] [--body ellipsoid|mesh]
//                    [--columns C] [--noise SIGMA_M] [--threads T] [--cache DIR] [--seed S]
//                    [--transform none|pca|lda] [--components K] [--rows all|3d]
//                    [--probe-frames interpolated|all|scans] [--per-walk] [--gallery-walks N]
//                    [--shape] [--decomposition] [--noise-seed S2 [--noise-subjects N2]
//                    [--noise-first K] [--noise-body same|ellipsoid|mesh|both]]
//                    [--walk-body mean|median]
//                    [--write-noise FILE.yaml | --noise-file FILE.yaml] [--robust-sigmas C]
//                    [--measure-noise] [--feature-scatter] [--write-features FILE.csv]
//                    [--report FILE.yaml] [--plot FILE.png] [--quiet]
//                    [--bvh [PERSON=]WALK.bvh,... [--bvh-map MAP.yaml]]
//
// --bvh: the people are motion-capture walks instead of simulated people; walk t of a
// person is trial t (the cross-walk protocol needs 2 walks per person), its 4 poses are the ones
// body_scan_driver's pickGaitPoses finds; PERSON defaults to the file name up to its first '_'
// (CMU: 07_02.bvh -> 07). --bvh-map: the joint map (default: the CMU map of body_scan_driver).
//
// --body mesh scans the skinned mesh human (body_scan_driver/sim/mesh_human.h) posed the same
// way instead of the ellipsoid body; its fits are cached apart.
// --fit walk (default) fits a walk's 4 scans together (body_gait_model::fitWalk: one body), as
// the body fitter fits a live walk, so gallery and probe walks are fitted as gait_id_node's are;
// --fit scan fits each scan alone (fitBody), as a scan outside a walk.
// --scanner truth skips scan and fit (models read off the simulator's skeleton): the upper
// bound of the features on these people, to tell the fitter's share of the errors.
// --gallery-walks N (cross-walk): enrol every person from walks 0 .. N - 1 (eta1 + eta2 of each),
// probe with walk N (default 1).
// --per-walk (cross-walk) adds the 3D rows with one decision per probe walk (the mean of a
// subject's scores over the walk's 20 frames) beside the per-frame decisions.
// Beyond the thesis (cross-walk): --shape adds the 3D dynamic+static+shape row
// (bodyShapeFeatures); --noise-seed S2 fits N2 (default 50) other people (seed S2, two walks) to
// learn each feature component's within-subject noise (--noise-first K: persons K..K+N2-1 of
// seed S2, so with S2 = S and K >= N the test seed's later people serve) and adds the
// noise-weighted 3D rows (noiseWeights); --noise-body learns it on the ellipsoid or the mesh
// people, or on both pooled (default: the evaluated body); --walk-body median takes each walk's
// body measures as the median of its four fits instead of eq 5.13's mean; --write-noise saves the
// learned noise for gait_id_node's ~feature_noise and gait_gallery's --feature-noise, --noise-file
// weighs by a saved noise instead of learning it; --robust-sigmas C adds weighted rows whose
// distance counts each component at most C noise SDs (robust to one failed component; brute force);
// --measure-noise prints how steady each body measure is between a person's walks against its
// spread between people; --feature-scatter prints every component of the 3D recognition vector
// (q, r, shape) with its SD between people and within a person between walks (and the
// --noise-file's SD), the most scattered relative to people's spread first; --write-features
// writes every fitted pose's features as CSV. Thesis protocol: the probes are eta3's 16
// interpolated frames per person as in the thesis (96 poses of 6 subjects);
// --probe-frames all adds the 4 representative frames, which are in the training sets too.
// --probe-frames scans (cross-walk): the probes are walk 1's 4 fits as single scans, as
// gait_id_node identifies each scan (with --fit scan each has its own body, as a person scanned
// once outside a walk); with --noise-seed the noise is learned the same way (single scans
// against the other walk's median body).
// Cross-walk: all 20 frames of walk 1 (no overlap with walk 0).
#include <body_gait_id/eval/gait_id_evaluation.h>
#include <body_gait_id/feature_noise_file.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/tools/command_line.h>
#include <body_scan_driver/tools/package_file.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "scanner_choices.h"

namespace {

using namespace body_gait_id::eval;
namespace tools = body_scan_driver::tools;

// The command line (see --help and the comment above).
struct Settings {
  std::string protocol = "thesis", report_path, plot_path, rows_choice = "all", noise_path,
              noise_file;
  int subjects = 0;  // 0: 6 (thesis), 50 (cross-walk), or the BVH files' people
  std::uint32_t seed = 1;
  ScanOptions scan;
  TransformOptions transform;
  ProbeFrames probe_frames = ProbeFrames::kInterpolated;
  bool feature_scatter = false;
  std::string features_path;
  bool per_walk = false, measure_noise = false, shape = false, median_body = false,
       decomposition = false;
  int gallery_walks = 1;
  std::vector<std::string> bvh_files;
  std::string bvh_map;
  std::uint32_t noise_seed = 0;  // 0: no noise-weighted rows
  int noise_subjects = 50;
  int noise_first = 0;  // the development people are persons noise_first.. of the noise seed
  // The bodies the noise is learned on (empty: the evaluated one; two: pooled).
  std::vector<body_gait_model::eval::BodyKind> noise_bodies;
  double robust_sigmas = 0;  // > 0: also the weighted rows with the truncated distance
  bool crossWalk() const { return protocol == "cross-walk"; }
};

// Returns the exit status when the tool should stop (--help, a usage error).
std::optional<int> parseSettings(int argc, char** argv, Settings& s) {
  CLI::App app(
      "Evaluates gait identification (thesis 5.8.3-5.8.4): simulated people (or motion-capture "
      "walks) walk through the scanner, every representative pose is scanned and fitted, gait "
      "cycles are reconstructed and identified; prints a table beside the thesis's figures, "
      "writes a YAML report and a CMC / ROC plot.",
      "evaluate_gait_id");
  app.add_option("--protocol", s.protocol,
                 "thesis, or cross-walk (gallery and probes from "
                 "different walks)")
      ->capture_default_str()
      ->check(CLI::IsMember({"thesis", "cross-walk"}));
  auto* subjects = app.add_option("--subjects", s.subjects, "people (default 6, cross-walk 50)")
                       ->check(tools::atLeast(2));
  tools::addChoice(app, "--scanner", s.scan.scanner, body_gait_id::tools::kScannerChoices,
                   "full: the 12-pair scanner simulation; sampler: rays cast from its viewpoints; "
                   "truth: no scan and no fit (the features' upper bound)");
  tools::addChoice(app, "--fit", s.scan.fit, body_gait_id::tools::kFitChoices,
                   body_gait_id::tools::kFitHelp);
  app.add_option("--columns", s.scan.sampler_columns, "sampler: ray grid per viewpoint")
      ->capture_default_str()
      ->check(tools::atLeast(20));
  app.add_option("--noise", s.scan.sampler_noise, "sampler: range noise SD (m)")
      ->capture_default_str();
  app.add_option("--threads", s.scan.threads, "scans in parallel")
      ->capture_default_str()
      ->check(tools::inRange(1, 16));
  tools::addChoice(app, "--body", s.scan.body, body_gait_id::tools::kBodyChoices,
                   "the simulated body: ellipsoid (default) or the skinned mesh human");
  app.add_option("--cache", s.scan.cache_folder, "fit cache folder (fits are reused)");
  app.add_option("--seed", s.seed, "seed of the simulated people")->capture_default_str();
  tools::addChoice(app, "--transform", s.transform.kind,
                   {{"none", FeatureTransform::kNone},
                    {"pca", FeatureTransform::kPca},
                    {"lda", FeatureTransform::kLda}},
                   "also the 3D rows after this feature transform");
  app.add_option("--components", s.transform.components, "components of the transform");
  app.add_option("--rows", s.rows_choice, "all: the thesis's rows; 3d: the 3D rows only")
      ->capture_default_str()
      ->check(CLI::IsMember({"all", "3d"}));
  tools::addChoice(app, "--probe-frames", s.probe_frames,
                   {{"interpolated", ProbeFrames::kInterpolated},
                    {"all", ProbeFrames::kAll},
                    {"scans", ProbeFrames::kSingleScans}},
                   "interpolated: eta3's 16 frames; all: and the 4 representative ones; scans "
                   "(cross-walk): walk 1's 4 fits as single scans");
  app.add_flag("--per-walk", s.per_walk,
               "cross-walk: also the 3D rows with one decision per probe walk");
  app.add_option("--gallery-walks", s.gallery_walks,
                 "cross-walk: enrol from walks 0 .. N - 1, probe with walk N")
      ->capture_default_str()
      ->check(tools::inRange(1, 5));
  app.add_flag("--shape", s.shape, "also the 3D dynamic+static+shape row");
  app.add_flag("--decomposition", s.decomposition,
               "the 3D rows of each feature alone and combined (dynamic, static, shape, static + "
               "shape, dynamic + static, dynamic + shape, all): how much is gait, how much body "
               "size");
  auto* noise_seed = app.add_option(
      "--noise-seed", s.noise_seed,
      "learn each feature component's within-subject noise on other people (this seed, two "
      "walks) and add the noise-weighted 3D rows");
  app.add_option("--noise-subjects", s.noise_subjects, "people the noise is learned on")
      ->capture_default_str()
      ->check(tools::atLeast(2));
  app.add_option("--noise-first", s.noise_first,
                 "the noise people are persons K.. of the noise seed")
      ->capture_default_str()
      ->check(tools::atLeast(0));
  std::string noise_body = "same";
  app.add_option("--noise-body", noise_body,
                 "the simulated bodies the noise is learned on: same (the evaluated one), "
                 "ellipsoid, mesh, or both (their pairs pooled)")
      ->capture_default_str()
      ->check(CLI::IsMember({"same", "ellipsoid", "mesh", "both"}))
      ->needs(noise_seed);
  tools::addChoice(app, "--walk-body", s.median_body, {{"mean", false}, {"median", true}},
                   "a walk's body measures: eq 5.13's mean of its four fits, or their median");
  app.add_option("--write-noise", s.noise_path,
                 "save the learned noise (gait_id_node's ~feature_noise)")
      ->needs(noise_seed);
  app.add_option("--noise-file", s.noise_file, "weigh by a saved noise instead of learning it")
      ->excludes(noise_seed);
  app.add_option("--robust-sigmas", s.robust_sigmas,
                 "also weighted rows whose distance counts each component at most C noise SDs")
      ->check(tools::atLeast(0));
  app.add_flag("--measure-noise", s.measure_noise,
               "cross-walk: print how steady each body measure is between a person's walks");
  app.add_flag(
      "--feature-scatter", s.feature_scatter,
      "cross-walk: print each feature's SD within a person's walks against between people");
  app.add_option("--write-features", s.features_path,
                 "write every fitted pose's 3D features as CSV (person, walk, pose, features)");
  app.add_option("--report", s.report_path, "YAML report");
  app.add_option("--plot", s.plot_path, "CMC / ROC plot (PNG)");
  bool quiet = false;
  app.add_flag("--quiet", quiet, "no line per scan");
  app.add_option("--bvh", s.bvh_files,
                 "[PERSON=]WALK.bvh,...: motion-capture walks are the people (walk t of a person "
                 "is trial t; PERSON defaults to the file name up to its first '_')")
      ->delimiter(',')
      ->excludes(subjects);
  app.add_option("--bvh-map", s.bvh_map,
                 "BVH joint map (default: body_scan_driver's config/bvh/cmu_joint_map.yaml)")
      ->check(CLI::ExistingFile);
  if (const auto status = tools::parseCommandLine(app, argc, argv)) return status;
  s.scan.progress = !quiet;
  using body_gait_model::eval::BodyKind;
  if (noise_body == "ellipsoid" || noise_body == "both")
    s.noise_bodies.push_back(BodyKind::kEllipsoid);
  if (noise_body == "mesh" || noise_body == "both") s.noise_bodies.push_back(BodyKind::kMesh);
  return std::nullopt;
}

// What CLI11 cannot check alone; empty when the settings go together.
std::string settingsProblem(const Settings& s) {
  if (s.subjects < 2) return "identification needs 2 or more people (the persons of --bvh)";
  if (s.gallery_walks > 1 && !s.crossWalk()) return "--gallery-walks is for --protocol cross-walk";
  if (s.probe_frames == ProbeFrames::kSingleScans && !s.crossWalk())
    return "--probe-frames scans is for the cross-walk protocol (the thesis protocol's scans are "
           "its gallery)";
  if (s.noise_seed != 0 && s.noise_seed == s.seed && s.noise_first < s.subjects)
    return "--noise-seed equals --seed: give --noise-first >= --subjects, so the noise is learned "
           "on other people";
  return "";
}

// The people who walk: simulated people of the seed, or the BVH walks (prints the poses picked).
PersonSource walkingPeople(Settings& s, int trials) {
  PersonSource people;
  if (!s.bvh_files.empty()) {
    if (s.bvh_map.empty())
      s.bvh_map =
          tools::packageFile("body_scan_driver", "config/bvh/cmu_joint_map.yaml", "--bvh-map");
    std::vector<std::string> picked;
    people = bvhPeople(s.bvh_files, s.bvh_map, trials, &picked);
    for (const std::string& line : picked) std::printf("%s\n", line.c_str());
    s.subjects = int(people.names.size());
    return people;
  }
  const auto persons = std::make_shared<std::vector<body_gait_model::eval::SimulatedPerson>>(
      body_gait_model::eval::simulatedPeople(s.subjects, s.seed));
  for (const auto& person : *persons) people.names.push_back(person.name);
  people.spec = [persons](int person, int pose, int trial, double heading) {
    return body_gait_model::eval::walkingSubject((*persons)[person], pose, trial, heading);
  };
  return people;
}

// Prints the walks the protocols leave out: a pose not fitted, or fits with no forward stride
// (the gait cycle cannot be rebuilt). Their people are not counted in the rates.
void printLeftOutWalks(const FittedWalks& walks, const PersonSource& people) {
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
}

// --noise-seed: the noise learned on development people (another seed: nobody of the test set)
// with two walks each, saved with --write-noise. Persons 0 .. noise_first - 1 are fitted too
// (their scans keep their index, so the cache serves them) and then left out. --noise-body
// both: the same people with either body, all their walk pairs pooled.
TransformOptions learnedNoiseWeights(const Settings& s, bool single_scans) {
  const std::vector<body_gait_model::eval::SimulatedPerson> development =
      body_gait_model::eval::simulatedPeople(s.noise_first + s.noise_subjects, s.noise_seed);
  PersonSource dev;
  for (const auto& person : development) dev.names.push_back(person.name);
  dev.spec = [&development](int person, int pose, int trial, double heading) {
    return body_gait_model::eval::walkingSubject(development[person], pose, trial, heading);
  };
  std::vector<body_gait_model::eval::BodyKind> bodies = s.noise_bodies;
  if (bodies.empty()) bodies.push_back(s.scan.body);
  FittedWalks dev_walks;
  std::string body_names;
  for (const body_gait_model::eval::BodyKind body : bodies) {
    ScanOptions scan = s.scan;
    scan.body = body;
    FittedWalks walks = fitWalks(dev, 2, scan);
    dev_walks.insert(dev_walks.end(), walks.begin() + s.noise_first, walks.end());
    body_names += (body_names.empty() ? "" : " and ") + body_gait_id::tools::bodyName(body);
  }
  if (s.median_body)
    dev_walks = single_scans ? withMedianBody(std::move(dev_walks), 1)
                             : withMedianBody(std::move(dev_walks));
  TransformOptions weighted;
  weighted.kind = FeatureTransform::kNoiseWeighted;
  weighted.noise = crossWalkNoise(dev_walks, body_gait_id::View::k3D, 0, 1, single_scans);
  if (!s.noise_path.empty()) {
    const std::string source =
        body_gait_id::tools::scannerName(s.scan.scanner) + " scanner, " +
        std::to_string(s.noise_subjects) + " people from " + std::to_string(s.noise_first) +
        ", seed " + std::to_string(s.noise_seed) + ", " + body_names +
        (bodies.size() > 1 ? " bodies pooled, " : " bodies, ") +
        (s.median_body ? "median" : "mean") + " body of a walk" +
        (s.scan.fit == FitLevel::kWalk ? ", walks fitted together" : ", scans fitted alone") +
        (single_scans ? ", single-scan probes" : "");
    body_scan_driver::writeFileAtomically(s.noise_path,
                                          body_gait_id::featureNoiseYaml(weighted.noise, source));
  }
  return weighted;
}

// --measure-noise: each body measure's spread within a person's walks against between people.
void printMeasureNoise(const FittedWalks& walks) {
  std::printf("%-30s %9s %9s %9s %7s\n", "measure (walk = mean of 4 fits)", "mean", "between",
              "within", "F");
  for (const MeasureNoise& m : bodyMeasureNoise(walks))
    std::printf("%-30s %9.4f %9.4f %9.4f %7.2f\n", m.name.c_str(), m.mean, m.between_sd,
                m.within_sd, m.within_sd > 0 ? std::pow(m.between_sd / m.within_sd, 2) : 0.0);
}

// --feature-scatter: the components whose walk-to-walk scatter is largest against people's spread.
void printFeatureScatter(const Settings& s, const FittedWalks& walks) {
  std::optional<body_gait_id::FeatureNoise> reference;
  if (!s.noise_file.empty()) reference = body_gait_id::readFeatureNoise(s.noise_file);
  std::vector<FeatureScatter> rows = featureScatter(walks, reference ? &*reference : nullptr);
  auto ratio = [](const FeatureScatter& r) {
    return r.between_sd > 0 ? r.within_sd / r.between_sd : 0.0;
  };
  std::stable_sort(rows.begin(), rows.end(), [&](const FeatureScatter& a, const FeatureScatter& b) {
    return ratio(a) > ratio(b);
  });
  std::printf("%-24s %10s %10s %8s %10s %8s\n", "feature (rad, m)", "between", "within", "w/b",
              "noise file", "w/file");
  for (const FeatureScatter& r : rows)
    std::printf("%-24s %10.5f %10.5f %8.3f %10.5f %8.2f\n", r.name.c_str(), r.between_sd,
                r.within_sd, ratio(r), r.reference_sd,
                r.reference_sd > 0 ? r.within_sd / r.reference_sd : 0.0);
}

// Scans and fits the people and runs the protocol: the thesis's rows, then the transformed,
// robust, noise-weighted and per-walk 3D rows asked for.
std::vector<NamedMetrics> evaluate(const Settings& s, const PersonSource& people, int trials,
                                   FitSummary& summary) {
  const bool cross_walk = s.crossWalk();
  std::vector<FeatureRow> rows = thesisRows();
  if (s.rows_choice == "3d") rows.resize(2);
  std::vector<FeatureRow> rows_3d(rows.begin(), rows.begin() + 2);
  if (s.shape) {
    rows.insert(rows.begin() + 2, shapeRow());
    rows_3d.push_back(shapeRow());
  }
  if (s.decomposition) rows = rows_3d = decompositionRows();
  FittedWalks walks = fitWalks(people, trials, s.scan, &summary);
  printLeftOutWalks(walks, people);
  if (!s.features_path.empty())
    body_scan_driver::writeFileAtomically(s.features_path, walkFeaturesCsv(walks));
  // Single-scan probes keep their fits' bodies; the gallery walks take the median.
  const bool single_scans = s.probe_frames == ProbeFrames::kSingleScans;
  const ProbeFrames cross_probes = single_scans ? ProbeFrames::kSingleScans : ProbeFrames::kAll;
  if (s.median_body)
    walks = single_scans ? withMedianBody(std::move(walks), s.gallery_walks)
                         : withMedianBody(std::move(walks));
  TransformOptions weighted;
  if (s.noise_seed != 0) weighted = learnedNoiseWeights(s, single_scans);
  if (s.measure_noise && cross_walk) printMeasureNoise(walks);
  if (s.feature_scatter && cross_walk) printFeatureScatter(s, walks);
  auto protocol = [&](const std::vector<FeatureRow>& which, const TransformOptions& transform,
                      bool per_walk) {
    return cross_walk
               ? crossWalkProtocol(walks, which, transform, per_walk, s.gallery_walks, cross_probes)
               : thesisProtocol(walks, which, transform, s.probe_frames);
  };
  std::vector<NamedMetrics> results = protocol(rows, {}, false);
  auto add = [&results](std::vector<NamedMetrics> extra) {
    for (NamedMetrics& r : extra) results.push_back(std::move(r));
  };
  if (s.transform.kind != FeatureTransform::kNone) add(protocol(rows_3d, s.transform, false));
  if (!s.noise_file.empty()) {
    weighted.kind = FeatureTransform::kNoiseWeighted;
    weighted.noise = body_gait_id::readFeatureNoise(s.noise_file);
  }
  TransformOptions robust = weighted;
  robust.truncate_sigmas = s.robust_sigmas;
  const bool with_robust = weighted.kind == FeatureTransform::kNoiseWeighted && s.robust_sigmas > 0;
  if (with_robust) add(protocol(rows_3d, robust, false));
  if (weighted.kind == FeatureTransform::kNoiseWeighted) add(protocol(rows_3d, weighted, false));
  if (s.per_walk && cross_walk) {
    add(protocol(rows_3d, {}, true));
    if (s.transform.kind != FeatureTransform::kNone) add(protocol(rows_3d, s.transform, true));
    if (weighted.kind == FeatureTransform::kNoiseWeighted) add(protocol(rows_3d, weighted, true));
    if (with_robust) add(protocol(rows_3d, robust, true));
  }
  return results;
}

std::string scannerDescription(ScannerKind scanner) {
  return scanner == ScannerKind::kTruth ? "truth (no scan, no fit)"
                                        : body_gait_id::tools::scannerName(scanner);
}

// The table, then every row's CMC and open-set figures.
void printResults(const Settings& s, const FitSummary& summary,
                  const std::vector<NamedMetrics>& results) {
  std::printf(
      "%s protocol, %d people, %s scanner: %d scans (%d cached, %d failed, %d low quality) "
      "in %.1f s\n",
      s.protocol.c_str(), s.subjects, scannerDescription(s.scan.scanner).c_str(), summary.scans,
      summary.cached, summary.failed, summary.low_quality, summary.seconds);
  for (const std::string& failure : summary.failures)
    std::printf("  failed: %s\n", failure.c_str());
  std::printf("%s", recognitionTable(results).c_str());
  for (const NamedMetrics& r : results) {
    const RecognitionMetrics& m = r.metrics;
    std::printf("%-42s CMC", r.name.c_str());
    for (const Proportion& p : m.cmc) std::printf(" %.2f", 100 * p.rate);
    for (const auto* open : {&m.open_set, &m.open_set_strict})
      if (*open)
        std::printf(
            " | open set at FNIR %.0f %%: threshold %.3f, FNIR %.2f %%%s, FPIR %.2f %% [%.2f, "
            "%.2f] (n %d)",
            100 * (*open)->target_fnir, (*open)->threshold, 100 * (*open)->fnir.rate,
            (*open)->target_reached ? "" : " (not reachable)", 100 * (*open)->fpir.rate,
            100 * (*open)->fpir.ci_low, 100 * (*open)->fpir.ci_high, (*open)->fpir.n);
    std::printf("\n");
  }
}

RecognitionReport report(const Settings& s, const FitSummary& summary,
                         const std::vector<NamedMetrics>& results) {
  const bool cross_walk = s.crossWalk();
  RecognitionReport report;
  report.settings = {{"protocol", s.protocol},
                     {"people", s.bvh_files.empty() ? "simulated" : "motion capture (BVH)"},
                     {"subjects", std::to_string(s.subjects)},
                     {"gallery_walks", std::to_string(cross_walk ? s.gallery_walks : 1)},
                     {"scanner", scannerDescription(s.scan.scanner)},
                     {"seed", std::to_string(s.seed)},
                     {"probe_frames", s.probe_frames == ProbeFrames::kSingleScans
                                          ? "single scans (walk 1's 4 fits)"
                                      : cross_walk                          ? "all (walk 1)"
                                      : s.probe_frames == ProbeFrames::kAll ? "all"
                                                                            : "interpolated"},
                     {"scans", std::to_string(summary.scans)},
                     {"cached_scans", std::to_string(summary.cached)},
                     {"failed_scans", std::to_string(summary.failed)},
                     {"low_quality_fits", std::to_string(summary.low_quality)},
                     {"scan_and_fit_seconds", std::to_string(summary.seconds)}};
  if (s.scan.scanner == ScannerKind::kSampler) {
    report.settings.push_back({"sampler_columns", std::to_string(s.scan.sampler_columns)});
    report.settings.push_back({"sampler_noise_m", std::to_string(s.scan.sampler_noise)});
  }
  report.results = results;
  return report;
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  if (const auto status = parseSettings(argc, argv, settings)) return *status;
  if (settings.subjects == 0 && settings.bvh_files.empty())
    settings.subjects = settings.crossWalk() ? 50 : 6;
  const int trials = settings.crossWalk() ? settings.gallery_walks + 1 : 1;
  PersonSource people;
  try {
    people = walkingPeople(settings, trials);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "evaluate_gait_id: %s\n", e.what());
    return 1;
  }
  if (const std::string problem = settingsProblem(settings); !problem.empty()) {
    std::fprintf(stderr, "evaluate_gait_id: %s\nRun with --help for more information.\n",
                 problem.c_str());
    return 2;
  }
  try {
    FitSummary summary;
    const std::vector<NamedMetrics> results = evaluate(settings, people, trials, summary);
    printResults(settings, summary, results);
    if (!settings.report_path.empty())
      writeRecognitionReport(settings.report_path, report(settings, summary, results));
    if (!settings.plot_path.empty())
      writePng(settings.plot_path, plotPanels(cmcAndRocPanels(results)));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "evaluate_gait_id: %s\n", e.what());
    return 1;
  }
  return 0;
}
