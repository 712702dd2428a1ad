// End-to-end evaluation of gait recognition on simulated people (thesis 5.8.3-5.8.4 and beyond):
// scanner simulation -> body fit (body_gait_model::fitBody) -> gait cycles (eqs 5.11-5.13) ->
// features (5.7) -> nearest-neighbour identification (eq 5.16) -> metrics. Reads simulator
// truth only to know who and which frame a probe is; the fitter and matcher never see it.
#pragma once

#include <body_gait_id/eval/recognition_metrics.h>
#include <body_gait_id/eval/recognition_report.h>
#include <body_gait_id/gait_features.h>
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <body_gait_model/gait_cycle.h>
#include <body_scan_driver/sim/human_body.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace body_gait_id::eval {

// Who walks through the scanner: person i's body in representative pose `pose` (1..4, thesis
// 5.3) of walk `trial` (0, 1, ...), facing `heading` (rad about world z).
struct PersonSource {
  std::vector<std::string> names;
  std::function<body_scan_driver::sim::HumanBodySpec(int person, int pose, int trial,
                                                     double heading)>
      spec;
};

// Motion-capture walks as the people: items "[PERSON=]WALK.bvh" (PERSON defaults to
// the file name up to its first '_', CMU: 07_02.bvh -> 07), people in order of first appearance,
// walk t of a person is trial t, its poses 1-4 the frames body_scan_driver's pickGaitPoses finds,
// each turned to the protocol's heading. `picked` (optional) gets one line per walk with its
// frames. Throws std::runtime_error naming a bad file or a person with fewer than `trials` walks.
PersonSource bvhPeople(const std::vector<std::string>& items, const std::string& joint_map,
                       int trials, std::vector<std::string>* picked = nullptr);

enum class ScannerKind {
  kFull,  // the 12-pair scanner simulation (body_gait_model::eval::scanBodyWithFullScanner, ~4 s)
  kSampler,  // rays cast into the scene from the same viewpoints
             // (body_gait_model::eval::sampleBody)
  // No scan and no fit: the model read off the simulator's skeleton (modelFromSkeleton). The
  // upper bound of the features on these people: what a perfect fitter would give.
  kTruth,
};

// How a walk's 4 scans are fitted: together (body_gait_model::fitWalk: one body for the walk, a
// pose per scan), as the body fitter fits a live walk and so as gait_id_node's walks are fitted,
// or each alone (fitBody), as a single scan is. The two are cached apart.
enum class FitLevel { kWalk, kScan };

struct ScanOptions {
  ScannerKind scanner = ScannerKind::kSampler;
  FitLevel fit = FitLevel::kWalk;  // kTruth fits nothing, so it ignores this
  int sampler_columns = 320;       // ray grid per viewpoint (sampler only)
  double sampler_noise = 0.002;    // m along the ray (sampler only)
  int threads = 2;
  // The simulated body scanned: ellipsoids or the mesh human (body_gait_model::eval::BodyKind).
  body_gait_model::eval::BodyKind body = body_gait_model::eval::BodyKind::kEllipsoid;
  std::string cache_folder;  // empty: no cache
  bool progress = true;      // one line per scan on stderr
};

struct FitSummary {
  int scans = 0, cached = 0, failed = 0, low_quality = 0;
  double seconds = 0;                 // wall time of the scans and fits
  std::vector<std::string> failures;  // "<person> walk <t> pose <k>: <reason>"
};

// The fitted representative poses s1..s4 of every walk: walks[person][trial]; nullopt when a
// pose could not be fitted.
using FittedWalks = std::vector<std::vector<std::optional<body_gait_model::RepresentativePoses>>>;

// Scans and fits every person's four poses of walks 0 .. trials - 1 (options.fit: a walk's 4
// together or each alone) on options.threads threads (a walk each), through the cache. Throws
// std::runtime_error naming the file when the cache cannot be written.
FittedWalks fitWalks(const PersonSource& people, int trials, const ScanOptions& options,
                     FitSummary* summary = nullptr);

// A row of Tables 5.3 / 5.4: a view and a feature set, with the thesis's figures.
struct FeatureRow {
  std::string name;
  View view = View::k3D;
  FeatureSet set = FeatureSet::kDynamicStatic;
  std::optional<ThesisFigures> thesis;
};
std::vector<FeatureRow> thesisRows();  // 3D, frontal, side x dynamic, dynamic+static
// Beyond the thesis: 3D dynamic + static + body shape (bodyShapeFeatures).
FeatureRow shapeRow();
// How much is gait and how much body size: 3D dynamic only (joint angles), static only (segment
// lengths), shape only (radii, half widths, height), static + shape (body size without gait),
// and the combinations with the dynamic feature.
std::vector<FeatureRow> decompositionRows();

// Optional learned projection of the normalized features (the thesis's future work), fitted on
// the gallery: PCA keeps `components` (0: half the dimension), LDA subjects - 1 (capped at the
// dimension). With a transform the ranking is a brute-force L2 scan of the projected vectors.
// kNoiseWeighted: no projection, each normalized component weighted by its between / within-
// subject SD ratio (noiseWeights), with the within-subject noise learned beforehand on other
// people (`noise`, from crossWalkNoise); the ranking is the indexed Matcher's.
enum class FeatureTransform { kNone, kPca, kLda, kNoiseWeighted };
struct TransformOptions {
  FeatureTransform kind = FeatureTransform::kNone;
  int components = 0;
  FeatureNoise noise;  // kNoiseWeighted only
  // kNoiseWeighted only, > 0: a robust distance instead of eq 5.16's L2: each component's
  // difference (in noise SDs, which the weighted components are) counts at most this many
  // SDs, so one failed component of a fit (a heavy-tailed error) cannot outweigh the rest.
  // Ranked by a brute-force scan (the k-d tree's bounds are for L2).
  double truncate_sigmas = 0;
};

// Which frames of eta3 probe: the 16 interpolated ones, or all 20 (with the representative
// frames 1, 6, 11, 16, whose poses s1..s4 are also in eta1 / eta2). kSingleScans: not a
// reconstructed walk but the probe walk's 4 fits as they are (true frames 1, 6, 11, 16): what
// the node identifies of each scan (fitted alone, FitLevel::kScan: a person scanned once).
enum class ProbeFrames { kInterpolated, kAll, kSingleScans };

// The probes of one evaluation. Gallery: eta1 and eta2 of walk `gallery_trial` (40 poses, 5.8.3)
// of the first `enrolled` people; probes: frames of eta3 of walk `probe_trial` of every person
// whose walk was fitted (people from `enrolled` on are not in the gallery: open set). People
// whose gallery walk failed are left out entirely; `dropped_people` counts them and the people
// whose probe walk failed.
struct ProbeSet {
  std::vector<ProbeResult> probes;
  int dropped_people = 0;
};
ProbeSet identifyProbes(const FittedWalks& walks, const FeatureRow& row, int gallery_trial,
                        int probe_trial, int enrolled, ProbeFrames frames,
                        const TransformOptions& transform = {});
// The same with several gallery walks per person (eta1 and eta2 of each: sequences 2k, 2k + 1);
// a person any of whose gallery walks failed is left out.
ProbeSet identifyProbes(const FittedWalks& walks, const FeatureRow& row,
                        const std::vector<int>& gallery_trials, int probe_trial, int enrolled,
                        ProbeFrames frames, const TransformOptions& transform = {});

// Thesis protocol (5.8.3): gallery and probes from walk 0 of every person, one result per row.
// The thesis tests 96 poses of 6 subjects, i.e. the 16 interpolated frames per subject ("not
// included in the training data ... absolutely no overlap"; 98.96 % = 95 / 96), so the default
// probes are kInterpolated.
std::vector<NamedMetrics> thesisProtocol(const FittedWalks& walks,
                                         const std::vector<FeatureRow>& rows,
                                         const TransformOptions& transform = {},
                                         ProbeFrames frames = ProbeFrames::kInterpolated);
// Cross-walk protocol: gallery from walk 0, probes all 20 frames of eta3 of walk 1 of the same
// people (rank-1, CMC, ROC / EER); the open-set figures come from a second run that enrols only
// the first half of the people and probes with all (the other half must be rejected).
// per_walk: one decision per probe walk (perWalkProbes: mean frame scores), rows named
// "... per walk". gallery_walks > 1: enrolment from walks 0 .. gallery_walks - 1 and probes from
// walk gallery_walks (rows named "..., N gallery walks"); walks must hold that many + 1 trials
// (std::invalid_argument otherwise).
std::vector<NamedMetrics> crossWalkProtocol(const FittedWalks& walks,
                                            const std::vector<FeatureRow>& rows,
                                            const TransformOptions& transform = {},
                                            bool per_walk = false, int gallery_walks = 1,
                                            ProbeFrames probes = ProbeFrames::kAll);

}  // namespace body_gait_id::eval

namespace body_gait_id::eval {

// How steady a static body measure is across a person's walks, against how much it differs
// between people (cross-walk identification is limited by the fits' noise). A walk's
// value is the mean over its four fitted poses (as r in eq 5.13); between_sd is the SD over
// people of walk trial_a's value, within_sd the SD of one walk's value about the person's own
// (RMS of (walk a - walk b) / sqrt 2). Fisher ratio = (between / within)^2.
struct MeasureNoise {
  std::string name;
  double mean = 0, between_sd = 0, within_sd = 0;
  int people = 0;
};
// The within-subject noise of every raw feature component of a view between walks trial_a and
// trial_b of the same people: RMS over people and eta3 frames of (frame f of walk a - frame f of
// walk b) / sqrt 2. single_scans_b: walk b's 4 fits as single scans
// against walk a's eta3 frames 1, 6, 11, 16: the noise of single-scan probes. Throws
// std::runtime_error when fewer than 2 people have both walks.
FeatureNoise crossWalkNoise(const FittedWalks& walks, View view = View::k3D, int trial_a = 0,
                            int trial_b = 1, bool single_scans_b = false);

// body_gait_id::withMedianBody (enrollment.h) applied to every fitted walk of trials
// 0 .. trials - 1 (all by default; single-scan probes keep their own bodies).
FittedWalks withMedianBody(FittedWalks walks, int trials = 1 << 30);

std::vector<MeasureNoise> bodyMeasureNoise(const FittedWalks& walks, int trial_a = 0,
                                           int trial_b = 1);

// Names of the 3D feature components in the order of gaitFeatures' blocks: q ("<segment> x",
// "<segment> z"), r ("r <segment>"), bodyShapeFeatures ("height", "shoulder_half_width", ...).
std::vector<std::string> featureNames3D();

// Which components of the recognition vector a person's walks disagree on: per 3D component,
// the SD between people (over the people of walk trial_a's eta3 frame, RMS over the 20 frames)
// and the within-person SD between walks (crossWalkNoise). `reference` (optional) is a noise
// the weights were learned on: its SD per component, so that within / reference says how much
// larger a genuine walk's difference is in the weighted distance than the weights expect.
struct FeatureScatter {
  std::string name;
  double between_sd = 0, within_sd = 0, reference_sd = 0;
};
std::vector<FeatureScatter> featureScatter(const FittedWalks& walks,
                                           const FeatureNoise* reference = nullptr, int trial_a = 0,
                                           int trial_b = 1);
// Every fitted pose's 3D features as CSV (person, walk, pose, then featureNames3D's columns; a
// failed walk has no rows): the raw material of featureScatter for a closer look.
std::string walkFeaturesCsv(const FittedWalks& walks);

}  // namespace body_gait_id::eval
