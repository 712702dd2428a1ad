#include <body_gait_id/enrollment.h>
#include <body_gait_id/eval/fit_cache.h>
#include <body_gait_id/eval/gait_id_evaluation.h>
#include <body_gait_id/matcher.h>
#include <body_gait_model/body_fitter.h>
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <body_gait_model/eval/full_scanner_body.h>
#include <body_gait_model/eval/skeleton_model.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/sim/bvh_body.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace body_gait_id::eval {
namespace {

using body_gait_model::GaitSet;
using Clock = std::chrono::steady_clock;

// Names the scans in the fit cache's key: a mesh body's fits are not an ellipsoid body's.
std::string scannerSettings(const ScanOptions& options) {
  const std::string body =
      options.body == body_gait_model::eval::BodyKind::kMesh ? " body=mesh" : "";
  if (options.scanner == ScannerKind::kFull) return "full scanner (thesis rig)" + body;
  if (options.scanner == ScannerKind::kTruth) return "true skeleton" + body;
  char text[96];
  std::snprintf(text, sizeof(text), "sampler columns=%d noise=%.6g", options.sampler_columns,
                options.sampler_noise);
  return text + body;
}

// The scanned cloud of one pose (sampler or full scanner; not kTruth).
body_gait_model::Cloud scanBody(const body_scan_driver::sim::HumanBodySpec& spec,
                                const ScanOptions& options) {
  if (options.scanner == ScannerKind::kFull) {
    body_gait_model::eval::FullScannerOptions full;
    full.body = options.body;
    return body_gait_model::eval::scanBodyWithFullScanner(spec, full).points;
  }
  body_gait_model::eval::ScanRig rig;
  rig.columns = options.sampler_columns;
  rig.rows = options.sampler_columns * 13 / 16;  // the rig's default aspect (320 x 260)
  rig.noise_sigma = options.sampler_noise;
  rig.body = options.body;
  return body_gait_model::eval::sampleBody(spec, rig).points;
}

CachedFit scanAndFit(const body_scan_driver::sim::HumanBodySpec& spec, const ScanOptions& options) {
  if (options.scanner == ScannerKind::kTruth) {
    if (options.body == body_gait_model::eval::BodyKind::kEllipsoid)
      return {body_gait_model::eval::modelFromSkeleton(spec), false, 0};
    body_scan_driver::sim::Scene scene;
    const auto placed = body_gait_model::eval::addSimulatedBody(spec, options.body, scene);
    return {body_gait_model::eval::modelFromSkeleton(scene.skeleton(), placed.body), false, 0};
  }
  const body_gait_model::Cloud cloud = scanBody(spec, options);
  const body_gait_model::BodyFit fit = body_gait_model::fitBody(cloud);
  return {fit.model, fit.quality.low_quality, static_cast<int>(cloud.size())};
}

// A walk's 4 poses scanned and fitted together (fitWalk: one body for the walk), as the body
// fitter fits a live walk. A scan that throws fails its pose (`errors`) and leaves the walk
// unfitted; a walk fit that throws (a cloud that is no body at all) fails all 4 poses.
std::array<std::optional<CachedFit>, 4> scanAndFitWalk(
    const std::array<body_scan_driver::sim::HumanBodySpec, 4>& specs, const ScanOptions& options,
    std::array<std::string, 4>& errors) {
  std::array<std::optional<CachedFit>, 4> fits;
  std::vector<body_gait_model::Cloud> clouds;
  std::vector<int> scanned;  // pose index (0-3) of each cloud
  for (int k = 0; k < 4; ++k) {
    try {
      clouds.push_back(scanBody(specs[k], options));
      scanned.push_back(k);
    } catch (const std::exception& e) {
      errors[k] = e.what();
    }
  }
  if (scanned.size() < 4) {  // a walk with a pose missing is left out anyway
    for (int k : scanned) errors[k] = "another pose of the walk could not be scanned";
    return fits;
  }
  try {
    const body_gait_model::WalkFit walk = body_gait_model::fitWalk(clouds);
    for (std::size_t i = 0; i < scanned.size(); ++i)
      fits[scanned[i]] = CachedFit{walk.scans[i].model, walk.scans[i].quality.low_quality,
                                   static_cast<int>(clouds[i].size())};
  } catch (const std::exception& e) {
    for (int k : scanned) errors[k] = std::string("walk fit: ") + e.what();
  }
  return fits;
}

// The three cycles of 5.8.3 from one walk's representative poses: eta1, eta2 (training) and
// eta3 (testing); nullopt when the walk is missing or has no forward stride.
struct WalkCycles {
  body_gait_model::GaitCycle eta1, eta2, eta3;
};
std::optional<WalkCycles> cyclesOf(
    const std::optional<body_gait_model::RepresentativePoses>& walk) {
  if (!walk) return std::nullopt;
  try {
    return WalkCycles{
        body_gait_model::reconstructGaitCycle(body_gait_model::gaitSet(*walk, GaitSet::kEta1)),
        body_gait_model::reconstructGaitCycle(body_gait_model::gaitSet(*walk, GaitSet::kEta2)),
        body_gait_model::reconstructGaitCycle(body_gait_model::gaitSet(*walk, GaitSet::kEta3))};
  } catch (const std::invalid_argument&) {
    return std::nullopt;  // e.g. a backwards fit: no forward stride
  }
}

std::int64_t subjectId(int person) { return person + 1; }

// The best gallery pose of every subject under score(row i), best first (ties keep subject
// order): the ranking a brute-force scan gives for CMC, ROC and the open set.
template <typename Score>
std::vector<RankedCandidate> bestPerSubject(const std::vector<std::pair<std::int64_t, int>>& ids,
                                            Score score_of_row) {
  std::map<std::int64_t, RankedCandidate> best;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const double score = score_of_row(static_cast<Eigen::Index>(i));
    auto [it, inserted] = best.try_emplace(ids[i].first, RankedCandidate{});
    if (inserted || score < it->second.score) it->second = {ids[i].first, ids[i].second, score};
  }
  std::vector<RankedCandidate> ranked;
  for (const auto& [id, candidate] : best) ranked.push_back(candidate);
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const auto& a, const auto& b) { return a.score < b.score; });
  return ranked;
}

// Ranking through a learned projection: best gallery pose per subject, best first.
class ProjectedRanker {
 public:
  ProjectedRanker(const std::vector<GalleryPose>& gallery, FeatureSet set,
                  const TransformOptions& options)
      : set_(set) {
    std::vector<GaitFeatures> features;
    for (const GalleryPose& pose : gallery) features.push_back(pose.features);
    normalization_ = FeatureNormalization::fit(features);
    Eigen::MatrixXd rows(gallery.size(), normalization_.size(set));
    std::vector<std::int64_t> labels;
    for (std::size_t i = 0; i < gallery.size(); ++i) {
      rows.row(i) = normalization_.normalized(gallery[i].features, set).transpose();
      labels.push_back(gallery[i].subject_id);
    }
    if (options.kind == FeatureTransform::kPca) {
      const int components =
          options.components > 0 ? options.components : (static_cast<int>(rows.cols()) + 1) / 2;
      transform_ = LinearFeatureTransform::pca(rows, std::min<int>(components, rows.cols()));
    } else {
      std::vector<std::int64_t> subjects(labels);
      std::sort(subjects.begin(), subjects.end());
      subjects.erase(std::unique(subjects.begin(), subjects.end()), subjects.end());
      const int most = std::min<int>(static_cast<int>(subjects.size()) - 1, rows.cols());
      const int components = options.components > 0 ? std::min(options.components, most) : most;
      transform_ = LinearFeatureTransform::lda(rows, labels, components);
    }
    projected_ = transform_.applyRows(rows);
    for (const GalleryPose& pose : gallery) ids_.push_back({pose.subject_id, pose.frame});
  }

  std::vector<RankedCandidate> rank(const GaitFeatures& probe) const {
    const Eigen::VectorXd y = transform_.apply(normalization_.normalized(probe, set_));
    return bestPerSubject(
        ids_, [&](Eigen::Index i) { return (projected_.row(i).transpose() - y).norm(); });
  }

 private:
  FeatureSet set_;
  FeatureNormalization normalization_;
  LinearFeatureTransform transform_;
  Eigen::MatrixXd projected_;
  std::vector<std::pair<std::int64_t, int>> ids_;  // subject, frame
};

std::string droppedNote(int dropped_people) {
  if (dropped_people == 0) return "";
  return std::to_string(dropped_people) +
         " people left out: a walk could not be fitted or gave no forward stride";
}

// Ranking by the truncated distance sqrt(sum_i min(d_i^2, c^2)) over weighted normalized
// components d_i (noise units): best gallery pose per subject, best first.
class TruncatedRanker {
 public:
  TruncatedRanker(const std::vector<GalleryPose>& gallery, FeatureSet set,
                  const FeatureNormalization& normalization, double truncate_sigmas)
      : set_(set), normalization_(normalization), limit_(truncate_sigmas * truncate_sigmas) {
    rows_.resize(gallery.size(), normalization_.size(set));
    for (std::size_t i = 0; i < gallery.size(); ++i) {
      rows_.row(i) = normalization_.normalized(gallery[i].features, set).transpose();
      ids_.push_back({gallery[i].subject_id, gallery[i].frame});
    }
  }

  std::vector<RankedCandidate> rank(const GaitFeatures& probe) const {
    const Eigen::RowVectorXd y = normalization_.normalized(probe, set_).transpose();
    return bestPerSubject(ids_, [&](Eigen::Index i) {
      return std::sqrt((rows_.row(i) - y).array().square().min(limit_).sum());
    });
  }

 private:
  FeatureSet set_;
  FeatureNormalization normalization_;
  double limit_;
  Eigen::MatrixXd rows_;
  std::vector<std::pair<std::int64_t, int>> ids_;  // subject, frame
};

std::string transformSuffix(const TransformOptions& transform) {
  switch (transform.kind) {
    case FeatureTransform::kPca:
      return " PCA";
    case FeatureTransform::kLda:
      return " LDA";
    case FeatureTransform::kNoiseWeighted:
      return transform.truncate_sigmas > 0 ? " weighted robust" : " weighted";
    default:
      return "";
  }
}

}  // namespace

FittedWalks fitWalks(const PersonSource& people, int trials, const ScanOptions& options,
                     FitSummary* summary) {
  struct Job {  // one walk
    int person, trial;
  };
  std::vector<Job> jobs;
  for (int person = 0; person < static_cast<int>(people.names.size()); ++person)
    for (int trial = 0; trial < trials; ++trial) jobs.push_back({person, trial});
  const bool walk_level = options.fit == FitLevel::kWalk && options.scanner != ScannerKind::kTruth;

  const FitCache cache(options.cache_folder);
  const std::string scanner = scannerSettings(options);
  // Pose k of walk j is entry 4 j + k.
  std::vector<std::optional<CachedFit>> fits(4 * jobs.size());
  std::vector<std::string> errors(fits.size());
  std::vector<char> from_cache(fits.size(), 0);
  std::atomic<std::size_t> next{0};
  std::atomic<int> done{0};
  std::mutex output;
  std::string write_error;
  const auto start = Clock::now();
  auto work = [&] {
    for (std::size_t j = next++; j < jobs.size(); j = next++) {
      const Job& job = jobs[j];
      std::array<body_scan_driver::sim::HumanBodySpec, 4> specs;
      std::array<std::string, 4> keys;
      for (int k = 0; k < 4; ++k) {
        // Heading within +-46 deg of the rig's front, varied per case as the scanner sees
        // people; from (person, trial, pose) alone, so runs with other counts share the cache.
        const int heading_case = 4 * job.person + k + 2 * job.trial;
        specs[k] = people.spec(job.person, k + 1, job.trial,
                               body_gait_model::eval::fullScannerHeading(heading_case));
        keys[k] = scanKey(specs[k], scanner);
      }
      if (walk_level) {  // a pose's walk-level fit depends on all 4 scans of its walk
        std::string walk = " walk fit of";
        for (const std::string& key : keys) walk += " " + key;
        for (int k = 0; k < 4; ++k) keys[k] = scanKey(specs[k], scanner + walk);
      }
      const auto job_start = Clock::now();
      try {
        for (int k = 0; k < 4; ++k)
          if ((fits[4 * j + k] = cache.load(keys[k]))) from_cache[4 * j + k] = 1;
        const bool all_cached =
            std::all_of(from_cache.begin() + 4 * j, from_cache.begin() + 4 * j + 4,
                        [](char cached) { return cached != 0; });
        if (walk_level && !all_cached) {
          std::array<std::string, 4> walk_errors;
          const auto walk_fits = scanAndFitWalk(specs, options, walk_errors);
          for (int k = 0; k < 4; ++k) {
            fits[4 * j + k] = walk_fits[k];
            from_cache[4 * j + k] = 0;
            errors[4 * j + k] = walk_errors[k];
            if (walk_fits[k]) cache.store(keys[k], *walk_fits[k]);
          }
        } else if (!walk_level) {
          for (int k = 0; k < 4; ++k) {
            if (from_cache[4 * j + k]) continue;
            try {
              fits[4 * j + k] = scanAndFit(specs[k], options);
            } catch (const std::exception& e) {
              errors[4 * j + k] = e.what();  // the fitter refused the cloud: a failed pose
              continue;
            }
            cache.store(keys[k], *fits[4 * j + k]);
          }
        }
      } catch (const body_scan_driver::FileWriteError& e) {
        std::lock_guard<std::mutex> lock(output);
        write_error = e.what();
      }
      if (options.progress) {
        // A walk's poses share its time (a walk-level fit is one computation).
        const double ms =
            1000 * std::chrono::duration<double>(Clock::now() - job_start).count() / 4;
        std::lock_guard<std::mutex> lock(output);
        for (int k = 0; k < 4; ++k) {
          const std::size_t i = 4 * j + k;
          std::string status = "FAILED: " + errors[i];
          if (from_cache[i])
            status = "cached";
          else if (fits[i])
            status = std::to_string(fits[i]->points) + " points, " +
                     std::to_string(static_cast<int>(ms)) + " ms" +
                     (walk_level ? " (walk fit)" : "") +
                     (fits[i]->low_quality ? ", low quality" : "");
          std::fprintf(stderr, "[%d/%zu] %s walk %d pose %d: %s\n", ++done, fits.size(),
                       people.names[job.person].c_str(), job.trial, k + 1, status.c_str());
        }
      }
    }
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < std::max(1, options.threads); ++t) threads.emplace_back(work);
  work();
  for (std::thread& thread : threads) thread.join();
  if (!write_error.empty()) throw std::runtime_error(write_error);

  FittedWalks walks(people.names.size(),
                    std::vector<std::optional<body_gait_model::RepresentativePoses>>(trials));
  std::vector<std::vector<int>> missing(people.names.size(), std::vector<int>(trials, 0));
  FitSummary local;
  for (std::size_t i = 0; i < fits.size(); ++i) {
    const Job& job = jobs[i / 4];
    const int pose = static_cast<int>(i % 4) + 1;
    ++local.scans;
    local.cached += from_cache[i];
    if (!fits[i]) {
      ++local.failed;
      ++missing[job.person][job.trial];
      local.failures.push_back(people.names[job.person] + " walk " + std::to_string(job.trial) +
                               " pose " + std::to_string(pose) + ": " + errors[i]);
      continue;
    }
    local.low_quality += fits[i]->low_quality;
    if (!walks[job.person][job.trial]) walks[job.person][job.trial].emplace();
    (*walks[job.person][job.trial])[pose - 1] = fits[i]->model;
  }
  for (std::size_t person = 0; person < walks.size(); ++person)
    for (int trial = 0; trial < trials; ++trial)
      if (missing[person][trial] > 0) walks[person][trial].reset();
  local.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (summary) *summary = local;
  return walks;
}

std::vector<FeatureRow> thesisRows() {
  return {
      {"3D dynamic", View::k3D, FeatureSet::kDynamic, ThesisFigures{98.96, 0.41}},
      {"3D dynamic+static", View::k3D, FeatureSet::kDynamicStatic, ThesisFigures{100.0, 1.31}},
      {"frontal dynamic", View::kFrontal, FeatureSet::kDynamic, ThesisFigures{93.75, 1.42}},
      {"frontal dynamic+static", View::kFrontal, FeatureSet::kDynamicStatic,
       ThesisFigures{100.0, 1.49}},
      {"side dynamic", View::kSide, FeatureSet::kDynamic, ThesisFigures{95.83, 0.57}},
      {"side dynamic+static", View::kSide, FeatureSet::kDynamicStatic, ThesisFigures{100.0, 1.29}},
  };
}

ProbeSet identifyProbes(const FittedWalks& walks, const FeatureRow& row, int gallery_trial,
                        int probe_trial, int enrolled, ProbeFrames frames,
                        const TransformOptions& transform) {
  return identifyProbes(walks, row, std::vector<int>{gallery_trial}, probe_trial, enrolled, frames,
                        transform);
}

ProbeSet identifyProbes(const FittedWalks& walks, const FeatureRow& row,
                        const std::vector<int>& gallery_trials, int probe_trial, int enrolled,
                        ProbeFrames frames, const TransformOptions& transform) {
  ProbeSet result;
  std::vector<GalleryPose> gallery;
  std::vector<char> in_gallery(walks.size(), 0);
  for (int person = 0; person < std::min<int>(enrolled, walks.size()); ++person) {
    std::vector<WalkCycles> enrolment;
    for (int trial : gallery_trials)
      if (std::optional<WalkCycles> cycles = cyclesOf(walks[person].at(trial)))
        enrolment.push_back(std::move(*cycles));
    if (enrolment.size() != gallery_trials.size()) {
      ++result.dropped_people;
      continue;
    }
    in_gallery[person] = 1;
    int sequence = 0;
    for (const WalkCycles& cycles : enrolment)
      for (const body_gait_model::GaitCycle* cycle : {&cycles.eta1, &cycles.eta2}) {
        for (int f = 0; f < static_cast<int>(cycle->frames.size()); ++f)
          gallery.push_back(
              {subjectId(person), sequence, f + 1, gaitFeatures(cycle->frames[f], row.view)});
        ++sequence;
      }
  }
  if (gallery.empty())
    throw std::runtime_error("no gallery: no enrolled person's gallery walks could be fitted");

  std::optional<Matcher> matcher;
  std::optional<ProjectedRanker> ranker;
  std::optional<TruncatedRanker> robust;
  if (transform.kind == FeatureTransform::kNone) {
    matcher.emplace(gallery, row.set);
  } else if (transform.kind == FeatureTransform::kNoiseWeighted) {
    std::vector<GaitFeatures> features;
    for (const GalleryPose& pose : gallery) features.push_back(pose.features);
    FeatureNormalization normalization = FeatureNormalization::fit(features);
    normalization.weights = noiseWeights(normalization, transform.noise, row.set);
    if (transform.truncate_sigmas > 0)
      robust.emplace(gallery, row.set, normalization, transform.truncate_sigmas);
    else
      matcher.emplace(gallery, row.set, normalization);
  } else {
    ranker.emplace(gallery, row.set, transform);
  }

  for (int person = 0; person < static_cast<int>(walks.size()); ++person) {
    const bool enrolled_person = person < enrolled;
    if (enrolled_person && !in_gallery[person]) continue;  // dropped above
    const std::optional<WalkCycles> cycles = cyclesOf(walks[person].at(probe_trial));
    if (!cycles) {
      ++result.dropped_people;  // no probes from this person
      continue;
    }
    // (model, true frame) of every probe of this person.
    std::vector<std::pair<const body_gait_model::BodyModel*, int>> probe_models;
    if (frames == ProbeFrames::kSingleScans) {
      const body_gait_model::RepresentativePoses& scans = *walks[person].at(probe_trial);
      for (int k = 0; k < 4; ++k)
        probe_models.push_back({&scans[k], body_gait_model::kRepresentativeFrames[k]});
    } else {
      for (int f = 0; f < static_cast<int>(cycles->eta3.frames.size()); ++f) {
        const bool representative =
            std::find(body_gait_model::kRepresentativeFrames.begin(),
                      body_gait_model::kRepresentativeFrames.end(),
                      f + 1) != body_gait_model::kRepresentativeFrames.end();
        if (representative && frames == ProbeFrames::kInterpolated) continue;
        probe_models.push_back({&cycles->eta3.frames[f], f + 1});
      }
    }
    for (const auto& [model, true_frame] : probe_models) {
      ProbeResult probe;
      probe.true_subject = subjectId(person);
      probe.true_frame = true_frame;
      probe.enrolled = enrolled_person;
      const GaitFeatures features = gaitFeatures(*model, row.view);
      if (matcher) {
        for (const Match& m : matcher->rankSubjects(features))
          probe.candidates.push_back({m.subject_id, m.frame, m.score});
      } else if (robust) {
        probe.candidates = robust->rank(features);
      } else {
        probe.candidates = ranker->rank(features);
      }
      result.probes.push_back(std::move(probe));
    }
  }
  return result;
}

std::vector<FeatureRow> decompositionRows() {
  return {{"3D dynamic (joint angles)", View::k3D, FeatureSet::kDynamic, std::nullopt},
          {"3D static (segment lengths)", View::k3D, FeatureSet::kStatic, std::nullopt},
          {"3D shape (radii, widths, height)", View::k3D, FeatureSet::kShape, std::nullopt},
          {"3D static+shape (body size)", View::k3D, FeatureSet::kStaticShape, std::nullopt},
          {"3D dynamic+static", View::k3D, FeatureSet::kDynamicStatic, std::nullopt},
          {"3D dynamic+shape", View::k3D, FeatureSet::kDynamicShape, std::nullopt},
          {"3D dynamic+static+shape", View::k3D, FeatureSet::kDynamicStaticShape, std::nullopt}};
}

FeatureRow shapeRow() {
  return {"3D dynamic+static+shape", View::k3D, FeatureSet::kDynamicStaticShape, std::nullopt};
}

std::vector<NamedMetrics> thesisProtocol(const FittedWalks& walks,
                                         const std::vector<FeatureRow>& rows,
                                         const TransformOptions& transform, ProbeFrames frames) {
  std::vector<NamedMetrics> results;
  for (const FeatureRow& row : rows) {
    const ProbeSet set =
        identifyProbes(walks, row, 0, 0, static_cast<int>(walks.size()), frames, transform);
    results.push_back({row.name + transformSuffix(transform), evaluateRecognition(set.probes),
                       row.thesis, droppedNote(set.dropped_people)});
  }
  return results;
}

std::vector<NamedMetrics> crossWalkProtocol(const FittedWalks& walks,
                                            const std::vector<FeatureRow>& rows,
                                            const TransformOptions& transform, bool per_walk,
                                            int gallery_walks, ProbeFrames probes) {
  std::vector<NamedMetrics> results;
  const int people = static_cast<int>(walks.size());
  if (gallery_walks < 1)
    throw std::invalid_argument("gallery_walks must be >= 1, got " + std::to_string(gallery_walks));
  for (const auto& of_person : walks)
    if (static_cast<int>(of_person.size()) < gallery_walks + 1)
      throw std::invalid_argument("the cross-walk protocol with " + std::to_string(gallery_walks) +
                                  " gallery walk(s) needs " + std::to_string(gallery_walks + 1) +
                                  " walks per person; fit that many (fitWalks' trials)");
  std::vector<int> gallery_trials;
  for (int t = 0; t < gallery_walks; ++t) gallery_trials.push_back(t);
  const int probe_trial = gallery_walks;
  const std::string suffix =
      transformSuffix(transform) + (probes == ProbeFrames::kSingleScans ? " single scans" : "") +
      (per_walk ? " per walk" : "") +
      (gallery_walks > 1 ? ", " + std::to_string(gallery_walks) + " gallery walks" : "");
  auto decided = [per_walk](const ProbeSet& set) {
    return evaluateRecognition(per_walk ? perWalkProbes(set.probes) : set.probes);
  };
  for (const FeatureRow& row : rows) {
    const ProbeSet closed =
        identifyProbes(walks, row, gallery_trials, probe_trial, people, probes, transform);
    RecognitionMetrics metrics = decided(closed);
    if (people >= 2) {
      const ProbeSet open =
          identifyProbes(walks, row, gallery_trials, probe_trial, people / 2, probes, transform);
      metrics.open_set = decided(open).open_set;
      MetricsOptions strict;
      strict.target_fnir = 0.01;
      metrics.open_set_strict =
          evaluateRecognition(per_walk ? perWalkProbes(open.probes) : open.probes, strict).open_set;
    }
    results.push_back(
        {row.name + suffix, metrics, std::nullopt, droppedNote(closed.dropped_people)});
  }
  return results;
}

PersonSource bvhPeople(const std::vector<std::string>& items, const std::string& joint_map,
                       int trials, std::vector<std::string>* picked) {
  namespace sim = body_scan_driver::sim;
  struct Walk {
    std::shared_ptr<const sim::BvhSubject> subject;
    sim::GaitPoseFrames poses;
  };
  const sim::BvhJointMap map = sim::loadBvhJointMap(joint_map);
  auto walks = std::make_shared<std::vector<std::vector<Walk>>>();  // [person][trial]
  PersonSource people;
  std::map<std::string, size_t> index;
  for (const std::string& item : items) {
    const auto [person, walk, file] = sim::parseBvhWalkFile(item);
    if (!index.count(person)) {
      index[person] = people.names.size();
      people.names.push_back(person);
      walks->emplace_back();
    }
    Walk w;
    w.subject = std::make_shared<const sim::BvhSubject>(sim::loadBvh(file), map, walk);
    w.poses = sim::pickGaitPoses(*w.subject);
    std::vector<Walk>& of_person = (*walks)[index[person]];
    if (picked) {
      char line[200];
      std::snprintf(line, sizeof(line), "%s (person %s, walk %zu): poses 1-4 at frames %d %d %d %d",
                    walk.c_str(), person.c_str(), of_person.size(), w.poses.frame[0] + 1,
                    w.poses.frame[1] + 1, w.poses.frame[2] + 1, w.poses.frame[3] + 1);
      picked->push_back(line);
    }
    of_person.push_back(w);
  }
  for (size_t i = 0; i < people.names.size(); ++i)
    if (int((*walks)[i].size()) < trials)
      throw std::runtime_error(
          "person '" + people.names[i] + "' has " + std::to_string((*walks)[i].size()) +
          " walk(s); the protocol needs " + std::to_string(trials) + " (give more BVH files)");
  people.spec = [walks](int person, int pose, int trial, double heading) {
    const Walk& walk = (*walks)[person][trial];
    sim::HumanBodySpec spec = walk.subject->body(walk.poses.frame[pose - 1]);
    sim::moveBody(spec, heading, Eigen::Vector3d::Zero());
    return spec;
  };
  return people;
}

namespace {

// Candidate static measures of one fitted pose: the lengths r, chain sums (whose shared joints'
// errors cancel), the radii and the joint offsets.
std::vector<std::pair<std::string, double>> candidateMeasures(const body_gait_model::BodyModel& m) {
  using namespace body_gait_model;
  std::vector<std::pair<std::string, double>> v;
  for (int s = 0; s < kSegmentCount; ++s)
    v.push_back({std::string("r ") + segmentInfo(s).name, m.r[s]});
  const double leg_r = m.r[kRightUpperLeg] + m.r[kRightLowerLeg];
  const double leg_l = m.r[kLeftUpperLeg] + m.r[kLeftLowerLeg];
  const double arm_r = m.r[kRightUpperArm] + m.r[kRightLowerArm];
  const double arm_l = m.r[kLeftUpperArm] + m.r[kLeftLowerArm];
  v.push_back({"leg right", leg_r});
  v.push_back({"leg left", leg_l});
  v.push_back({"leg mean", (leg_r + leg_l) / 2});
  v.push_back({"arm right", arm_r});
  v.push_back({"arm left", arm_l});
  v.push_back({"arm mean", (arm_r + arm_l) / 2});
  v.push_back({"thigh mean", (m.r[kRightUpperLeg] + m.r[kLeftUpperLeg]) / 2});
  v.push_back({"shank mean", (m.r[kRightLowerLeg] + m.r[kLeftLowerLeg]) / 2});
  v.push_back({"upper arm mean", (m.r[kRightUpperArm] + m.r[kLeftUpperArm]) / 2});
  v.push_back({"lower arm mean", (m.r[kRightLowerArm] + m.r[kLeftLowerArm]) / 2});
  const double trunk = m.r[kLowerTorso] + m.r[kUpperTorso];
  v.push_back({"trunk", trunk});
  v.push_back({"trunk+neck+head", trunk + m.r[kNeck] + m.r[kHead]});
  v.push_back({"leg + trunk + neck + head", (leg_r + leg_l) / 2 + trunk + m.r[kNeck] + m.r[kHead]});
  v.push_back({"standing height (shape feature)", bodyShapeFeatures(m)[0]});
  for (int s = 0; s < kSegmentCount; ++s)
    v.push_back({std::string("rp ") + segmentInfo(s).name, m.shape.proximal_radius[s]});
  for (int s = 0; s < kSegmentCount; ++s)
    v.push_back({std::string("rd ") + segmentInfo(s).name, m.shape.distal_radius[s]});
  for (int s = 0; s < kSegmentCount; ++s)
    v.push_back({std::string("rmean ") + segmentInfo(s).name,
                 (m.shape.proximal_radius[s] + m.shape.distal_radius[s]) / 2});
  for (const auto& [name, field] : body_gait_model::kJointPlacements)
    v.push_back({name, m.shape.*field});
  return v;
}

}  // namespace

std::vector<MeasureNoise> bodyMeasureNoise(const FittedWalks& walks, int trial_a, int trial_b) {
  std::vector<MeasureNoise> result;
  std::vector<Eigen::VectorXd> a, b;  // per person: walk values
  for (const auto& person : walks) {
    if (!person.at(trial_a) || !person.at(trial_b)) continue;
    auto walkValue = [&result](const body_gait_model::RepresentativePoses& poses) {
      Eigen::VectorXd sum;
      for (const body_gait_model::BodyModel& m : poses) {
        const auto measures = candidateMeasures(m);
        if (result.empty())
          for (const auto& [name, value] : measures) result.push_back({name});
        Eigen::VectorXd v(measures.size());
        for (std::size_t i = 0; i < measures.size(); ++i) v[i] = measures[i].second;
        sum = sum.size() ? Eigen::VectorXd(sum + v) : v;
      }
      return Eigen::VectorXd(sum / 4.0);
    };
    a.push_back(walkValue(*person.at(trial_a)));
    b.push_back(walkValue(*person.at(trial_b)));
  }
  if (a.size() < 2) return {};
  const double n = static_cast<double>(a.size());
  for (std::size_t i = 0; i < result.size(); ++i) {
    double mean = 0, between = 0, within = 0;
    for (std::size_t p = 0; p < a.size(); ++p) mean += a[p][i] / n;
    for (std::size_t p = 0; p < a.size(); ++p) {
      between += (a[p][i] - mean) * (a[p][i] - mean) / (n - 1);
      within += (a[p][i] - b[p][i]) * (a[p][i] - b[p][i]) / (2 * n);
    }
    result[i].mean = mean;
    result[i].between_sd = std::sqrt(between);
    result[i].within_sd = std::sqrt(within);
    result[i].people = static_cast<int>(a.size());
  }
  return result;
}

FeatureNoise crossWalkNoise(const FittedWalks& walks, View view, int trial_a, int trial_b,
                            bool single_scans_b) {
  Eigen::VectorXd sum_d, sum_s, sum_b;
  int count = 0, people = 0;
  for (const auto& person : walks) {
    const std::optional<WalkCycles> a = cyclesOf(person.at(trial_a));
    const std::optional<WalkCycles> b = cyclesOf(person.at(trial_b));
    if (!a || !b) continue;
    ++people;
    // Pairs (walk a's model, walk b's model) of the same gait-cycle frame.
    std::vector<std::pair<const body_gait_model::BodyModel*, const body_gait_model::BodyModel*>>
        pairs;
    for (std::size_t f = 0; f < a->eta3.frames.size(); ++f)
      if (!single_scans_b) pairs.push_back({&a->eta3.frames[f], &b->eta3.frames[f]});
    if (single_scans_b)
      for (int k = 0; k < 4; ++k)
        pairs.push_back({&a->eta3.frames[body_gait_model::kRepresentativeFrames[k] - 1],
                         &(*person.at(trial_b))[k]});
    for (const auto& [model_a, model_b] : pairs) {
      const GaitFeatures fa = gaitFeatures(*model_a, view);
      const GaitFeatures fb = gaitFeatures(*model_b, view);
      const Eigen::VectorXd dd = (fa.dynamic - fb.dynamic).cwiseAbs2();
      const Eigen::VectorXd ds = (fa.statics - fb.statics).cwiseAbs2();
      const Eigen::VectorXd db = (fa.shape - fb.shape).cwiseAbs2();
      sum_d = sum_d.size() ? Eigen::VectorXd(sum_d + dd) : dd;
      sum_s = sum_s.size() ? Eigen::VectorXd(sum_s + ds) : ds;
      sum_b = sum_b.size() ? Eigen::VectorXd(sum_b + db) : db;
      ++count;
    }
  }
  if (people < 2)
    throw std::runtime_error(
        "cross-walk noise: fewer than 2 people with both walks fitted; use more people");
  const double n = 2.0 * count;  // E[(a - b)^2] = 2 sigma^2
  return {(sum_d / n).cwiseSqrt(), (sum_s / n).cwiseSqrt(), (sum_b / n).cwiseSqrt()};
}

FittedWalks withMedianBody(FittedWalks walks, int trials) {
  for (auto& person : walks)
    for (int t = 0; t < std::min<int>(trials, static_cast<int>(person.size())); ++t)
      if (person[t]) person[t] = body_gait_id::withMedianBody(*person[t]);
  return walks;
}

std::vector<std::string> featureNames3D() {
  using namespace body_gait_model;
  std::vector<std::string> names;
  for (int s = 0; s < kSegmentCount; ++s)
    if (jointAngleIndex(s) >= 0) {
      names.push_back(std::string(segmentInfo(s).name) + " x");
      names.push_back(std::string(segmentInfo(s).name) + " z");
    }
  for (int s = 0; s < kSegmentCount; ++s) names.push_back(std::string("r ") + segmentInfo(s).name);
  names.insert(names.end(), {"height", "shoulder_half_width", "hip_half_width", "rp upper_torso",
                             "rd upper_torso", "rd lower_torso", "radius neck", "radius head"});
  for (int s : {kRightUpperArm, kRightLowerArm, kLeftUpperArm, kLeftLowerArm, kRightUpperLeg,
                kRightLowerLeg, kLeftUpperLeg, kLeftLowerLeg}) {
    names.push_back(std::string("rp ") + segmentInfo(s).name);
    names.push_back(std::string("rd ") + segmentInfo(s).name);
  }
  return names;
}

namespace {

Eigen::VectorXd stacked(const GaitFeatures& f) {
  Eigen::VectorXd v(f.dynamic.size() + f.statics.size() + f.shape.size());
  v << f.dynamic, f.statics, f.shape;
  return v;
}

}  // namespace

std::vector<FeatureScatter> featureScatter(const FittedWalks& walks, const FeatureNoise* reference,
                                           int trial_a, int trial_b) {
  const FeatureNoise noise = crossWalkNoise(walks, View::k3D, trial_a, trial_b);
  const std::vector<std::string> names = featureNames3D();
  // Per eta3 frame: sum and sum of squares over the people of walk a.
  std::vector<Eigen::VectorXd> sum(body_gait_model::kGaitCycleFrames),
      sum_sq(body_gait_model::kGaitCycleFrames);
  int people = 0;
  for (const auto& person : walks) {
    const std::optional<WalkCycles> a = cyclesOf(person.at(trial_a));
    if (!a) continue;
    ++people;
    for (std::size_t f = 0; f < a->eta3.frames.size(); ++f) {
      const Eigen::VectorXd v = stacked(gaitFeatures(a->eta3.frames[f]));
      sum[f] = sum[f].size() ? Eigen::VectorXd(sum[f] + v) : v;
      sum_sq[f] = sum_sq[f].size() ? Eigen::VectorXd(sum_sq[f] + v.cwiseAbs2())
                                   : Eigen::VectorXd(v.cwiseAbs2());
    }
  }
  Eigen::VectorXd between = Eigen::VectorXd::Zero(static_cast<int>(names.size()));
  for (std::size_t f = 0; f < sum.size(); ++f)
    between += ((sum_sq[f] - sum[f].cwiseAbs2() / people) / (people - 1)).cwiseMax(0.0);
  between = (between / static_cast<double>(sum.size())).cwiseSqrt();
  const Eigen::VectorXd within = stacked({noise.dynamic, noise.statics, noise.shape});
  Eigen::VectorXd ref = Eigen::VectorXd::Zero(within.size());
  if (reference) ref = stacked({reference->dynamic, reference->statics, reference->shape});
  std::vector<FeatureScatter> result;
  for (std::size_t i = 0; i < names.size(); ++i)
    result.push_back({names[i], between[i], within[i], ref[i]});
  return result;
}

std::string walkFeaturesCsv(const FittedWalks& walks) {
  std::ostringstream out;
  out << "person,walk,pose";
  for (const std::string& name : featureNames3D()) out << ',' << name;
  out << '\n';
  for (std::size_t p = 0; p < walks.size(); ++p)
    for (std::size_t t = 0; t < walks[p].size(); ++t)
      if (walks[p][t])
        for (int k = 0; k < 4; ++k) {
          out << p << ',' << t << ',' << k + 1;
          const Eigen::VectorXd v = stacked(gaitFeatures((*walks[p][t])[k]));
          for (int i = 0; i < v.size(); ++i) out << ',' << v[i];
          out << '\n';
        }
  return out.str();
}

}  // namespace body_gait_id::eval
