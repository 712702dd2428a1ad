// A small version of evaluate_gait_id end to end (3 people, the ray-cast sampler, 2 walks each:
// 24 scans, each walk's 4 fitted together as the body fitter fits a live walk): the thesis and
// cross-walk protocols' measured rates, the cache, the single-scan fit level, and the PCA / LDA
// rows. Asserts on what was measured (README: evaluate_gait_id), with margins for
// the fitter's run-to-run stability only.
#include <body_gait_id/eval/gait_id_evaluation.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <body_scan_driver/sim/data_paths.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace body_gait_id::eval {
namespace {

namespace fs = std::filesystem;

struct SmallRun {
  std::vector<body_gait_model::eval::SimulatedPerson> persons =
      body_gait_model::eval::simulatedPeople(3, 1);
  PersonSource people;
  fs::path cache = fs::temp_directory_path() / ("test_gait_id_eval_" + std::to_string(getpid()));
  ScanOptions options;
  FitSummary first, second;
  FittedWalks walks, cached_walks;

  SmallRun() {
    for (const auto& person : persons) people.names.push_back(person.name);
    people.spec = [this](int person, int pose, int trial, double heading) {
      return body_gait_model::eval::walkingSubject(persons[person], pose, trial, heading);
    };
    options.cache_folder = cache.string();
    options.progress = false;
    fs::remove_all(cache);
    walks = fitWalks(people, 2, options, &first);
    cached_walks = fitWalks(people, 2, options, &second);  // every fit from the cache
  }
  ~SmallRun() { fs::remove_all(cache); }
};

const SmallRun& smallRun() {
  static const SmallRun run;
  return run;
}

const NamedMetrics& row(const std::vector<NamedMetrics>& results, const std::string& name) {
  for (const NamedMetrics& r : results)
    if (r.name == name) return r;
  throw std::invalid_argument("no row " + name);
}

// The measured table in the test's output (what the assertions below were set from).
void print(const std::vector<NamedMetrics>& results) {
  std::printf("%s", recognitionTable(results).c_str());
}

TEST(GaitIdEvaluation, EveryPoseIsScannedFittedAndCached) {
  const SmallRun& run = smallRun();
  EXPECT_EQ(run.first.scans, 24);
  EXPECT_EQ(run.first.failed, 0);
  EXPECT_EQ(run.first.cached, 0);
  EXPECT_EQ(run.second.cached, 24);
  for (std::size_t person = 0; person < run.walks.size(); ++person)
    for (int trial = 0; trial < 2; ++trial) {
      ASSERT_TRUE(run.walks[person][trial].has_value());
      ASSERT_TRUE(run.cached_walks[person][trial].has_value());
      for (int pose = 0; pose < 4; ++pose) {
        EXPECT_EQ((*run.walks[person][trial])[pose].q, (*run.cached_walks[person][trial])[pose].q);
        // The walk-level fit (the default): one body for the walk's 4 scans.
        EXPECT_EQ((*run.walks[person][trial])[pose].r, (*run.walks[person][trial])[0].r);
        EXPECT_EQ((*run.walks[person][trial])[pose].shape.proximal_radius,
                  (*run.walks[person][trial])[0].shape.proximal_radius);
      }
    }
}

// FitLevel::kScan fits each scan alone (fitBody): one body per scan, cached apart from the
// walk-level fits of the same scans (the small run's cache holds those). Person 0's walk 0 only.
TEST(GaitIdEvaluation, SingleScanFitLevelFitsEachScanAloneAndIsCachedApart) {
  const SmallRun& run = smallRun();
  PersonSource first_person = run.people;
  first_person.names.resize(1);
  ScanOptions options = run.options;
  options.fit = FitLevel::kScan;
  FitSummary first, again;
  const FittedWalks scan_fits = fitWalks(first_person, 1, options, &first);
  fitWalks(first_person, 1, options, &again);
  EXPECT_EQ(first.scans, 4);
  EXPECT_EQ(first.cached, 0);  // the walk-level entries are not the single scans'
  EXPECT_EQ(again.cached, 4);
  ASSERT_TRUE(scan_fits[0][0].has_value());
  const body_gait_model::RepresentativePoses& scans = *scan_fits[0][0];
  EXPECT_NE(scans[0].r, scans[1].r);  // a body per scan
  EXPECT_NE(scans[0].r, (*run.walks[0][0])[0].r);
}

TEST(GaitIdEvaluation, ThesisProtocolOnThreePeople) {
  const std::vector<NamedMetrics> results = thesisProtocol(smallRun().walks, thesisRows());
  print(results);
  ASSERT_EQ(results.size(), 6u);
  for (const NamedMetrics& r : results) {
    EXPECT_EQ(r.metrics.enrolled_probes, 48) << r.name;  // 3 people x eta3's 16 interpolated
    ASSERT_EQ(r.metrics.cmc.size(), 3u) << r.name;
    EXPECT_DOUBLE_EQ(r.metrics.cmc.back().rate, 1.0) << r.name;  // rank 3 of 3 finds everyone
  }
  // Measured (seed 1, walk-level fits): 48 / 48 for both 3D rows; pose error 0.44 plain, 0.10
  // cyclic.
  const RecognitionMetrics& both = row(results, "3D dynamic+static").metrics;
  const RecognitionMetrics& dynamic = row(results, "3D dynamic").metrics;
  EXPECT_EQ(both.identification.count, 48);
  EXPECT_EQ(dynamic.identification.count, 48);
  EXPECT_LE(dynamic.average_pose_error, 0.6);
  EXPECT_LE(dynamic.average_cyclic_pose_error, 0.2);
  // With the representative frames (in the gallery too) the dynamic probes of frames 1, 6, 11,
  // 16 match their own training pose: pose error 0 there.
  std::vector<FeatureRow> rows_3d = thesisRows();
  rows_3d.resize(1);
  const RecognitionMetrics all =
      thesisProtocol(smallRun().walks, rows_3d, {}, ProbeFrames::kAll)[0].metrics;
  EXPECT_EQ(all.enrolled_probes, 60);
  EXPECT_NEAR(all.average_pose_error * 60, dynamic.average_pose_error * 48, 1e-9);
}

TEST(GaitIdEvaluation, CrossWalkProtocolOnThreePeople) {
  const std::vector<NamedMetrics> results = crossWalkProtocol(smallRun().walks, thesisRows());
  print(results);
  // Another walk is harder than the thesis protocol: measured (seed 1, walk-level fits) 3D
  // dynamic 53 / 60, dynamic+static 60 / 60. The 50-person figures, with body shape and noise
  // weights, are in docs/RESULTS.md.
  const RecognitionMetrics& both = row(results, "3D dynamic+static").metrics;
  const RecognitionMetrics& dynamic = row(results, "3D dynamic").metrics;
  EXPECT_EQ(both.enrolled_probes, 60);  // walk 1's eta3, all 20 frames, of 3 people
  EXPECT_GE(dynamic.identification.rate, 0.8);
  EXPECT_GE(both.identification.rate, 0.9);
  EXPECT_DOUBLE_EQ(both.cmc.back().rate, 1.0);
  ASSERT_TRUE(both.open_set.has_value());  // 1 person enrolled, 2 to reject
  EXPECT_EQ(both.open_set->fnir.n, 20);
  EXPECT_EQ(both.open_set->fpir.n, 40);
}

TEST(GaitIdEvaluation, SingleScanProbesAreTheWalksOwnFits) {
  // The probes are walk 1's 4 fits themselves (what gait_id_node identifies of each scan of a
  // walk), at their true frames 1, 6, 11, 16; the gallery's walks take the median body.
  const FittedWalks walks = withMedianBody(smallRun().walks, 1);
  const std::vector<FeatureRow> rows = thesisRows();
  const ProbeSet probes = identifyProbes(walks, rows[1], 0, 1, 3, ProbeFrames::kSingleScans);
  ASSERT_EQ(probes.probes.size(), 12u);  // 3 people x 4 scans
  for (std::size_t i = 0; i < probes.probes.size(); ++i)
    EXPECT_EQ(probes.probes[i].true_frame, body_gait_model::kRepresentativeFrames[i % 4]);
  // Walk 1 kept its fits' lengths (a walk-level fit's: one body for its 4 scans, so the median
  // body of walk 0 is its fits' body too).
  const body_gait_model::RepresentativePoses& raw = *smallRun().walks[0][1];
  EXPECT_EQ((*walks[0][1])[0].r, raw[0].r);
  EXPECT_EQ((*walks[0][0])[2].r, (*smallRun().walks[0][0])[2].r);
  const std::vector<NamedMetrics> results =
      crossWalkProtocol(walks, rows, {}, false, 1, ProbeFrames::kSingleScans);
  print(results);
  // Measured (3 people, seed 1, walk-level fits): 3D dynamic 10 / 12, dynamic+static 12 / 12
  // (chance 4 / 12).
  const RecognitionMetrics& both = row(results, "3D dynamic+static single scans").metrics;
  const RecognitionMetrics& dynamic = row(results, "3D dynamic single scans").metrics;
  EXPECT_EQ(both.enrolled_probes, 12);
  EXPECT_GE(dynamic.identification.rate, 0.65);
  EXPECT_GE(both.identification.rate, 0.75);
  // The single-scan noise: walk 1's fits against walk 0's frames 1, 6, 11, 16.
  const FeatureNoise walk_noise = crossWalkNoise(walks, View::k3D, 0, 1);
  const FeatureNoise scan_noise = crossWalkNoise(walks, View::k3D, 0, 1, true);
  EXPECT_GT(scan_noise.statics.norm(), 0.0);
  EXPECT_NE(scan_noise.statics, walk_noise.statics);
}

TEST(GaitIdEvaluation, PeopleWhoseWalkFailedAreLeftOutAndSaidSo) {
  FittedWalks walks = smallRun().walks;
  walks[1][0].reset();  // person 1's gallery walk could not be fitted
  std::vector<FeatureRow> rows = thesisRows();
  rows.resize(1);
  const NamedMetrics result = thesisProtocol(walks, rows)[0];
  EXPECT_EQ(result.metrics.enrolled_probes, 32);  // 2 people x 16
  ASSERT_EQ(result.metrics.cmc.size(), 2u);       // 2 enrolled subjects
  EXPECT_NE(result.note.find("1 people left out"), std::string::npos) << result.note;
  // Cross-walk: person 2's probe walk missing leaves 2 people's probes; the gallery keeps 3.
  walks = smallRun().walks;
  walks[2][1].reset();
  const NamedMetrics cross = crossWalkProtocol(walks, rows)[0];
  EXPECT_EQ(cross.metrics.enrolled_probes, 40);
  EXPECT_EQ(cross.metrics.cmc.size(), 3u);
  EXPECT_NE(cross.note.find("1 people left out"), std::string::npos) << cross.note;
}

TEST(GaitIdEvaluation, EnrolmentFromTwoWalks) {
  // True skeletons (no scan, no fit: instant), 3 people x 3 walks.
  const SmallRun& run = smallRun();
  ScanOptions truth;
  truth.scanner = ScannerKind::kTruth;
  truth.progress = false;
  const FittedWalks walks = fitWalks(run.people, 3, truth);
  std::vector<FeatureRow> rows = thesisRows();
  rows.resize(2);
  const std::vector<NamedMetrics> results = crossWalkProtocol(walks, rows, {}, false, 2);
  print(results);
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[1].name, "3D dynamic+static, 2 gallery walks");
  EXPECT_EQ(results[1].metrics.enrolled_probes, 60);              // walk 2's eta3 of 3 people
  EXPECT_DOUBLE_EQ(results[1].metrics.identification.rate, 1.0);  // measured: 60 / 60
  // The small run fitted 2 walks: not enough for 2 gallery walks and a probe walk.
  EXPECT_THROW(crossWalkProtocol(run.walks, rows, {}, false, 2), std::invalid_argument);
}

TEST(GaitIdEvaluation, LearnedProjectionsIdentifyToo) {
  for (FeatureTransform kind : {FeatureTransform::kPca, FeatureTransform::kLda}) {
    std::vector<FeatureRow> rows = thesisRows();
    rows.resize(2);  // the 3D rows
    const std::vector<NamedMetrics> results = thesisProtocol(smallRun().walks, rows, {kind, 0, {}});
    print(results);
    ASSERT_EQ(results.size(), 2u);
    const std::string suffix = kind == FeatureTransform::kPca ? " PCA" : " LDA";
    EXPECT_EQ(results[1].name, "3D dynamic+static" + suffix);
    EXPECT_GE(results[1].metrics.identification.rate, 0.9) << results[1].name;
  }
}

// The CMU walks (body_scan_driver/data/cmu_walks) as the people, models read off
// their skeletons (no scan, no fit: fast, and the upper bound of the features on real walks).
// Every probe frame of another walk finds its person; a person with one walk is refused.
TEST(GaitIdEvaluation, MotionCaptureWalksAsPeople) {
  const std::string bvh = body_scan_driver::sim::cmuWalksDir();
  ASSERT_TRUE(std::filesystem::exists(bvh + "/07_02.bvh"))
      << "CMU walks not found in " << bvh
      << " (body_scan_driver/data/cmu_walks, or BODY_SCAN_BVH_DIR naming a folder with them)";
  const std::string map = body_scan_driver::sim::driverConfigDir() + "/bvh/cmu_joint_map.yaml";
  std::vector<std::string> files;
  for (const char* walk : {"07_02", "07_08", "08_03", "08_08", "35_01", "35_02"})
    files.push_back(bvh + "/" + walk + ".bvh");
  std::vector<std::string> picked;
  const PersonSource people = bvhPeople(files, map, 2, &picked);
  EXPECT_EQ(people.names, (std::vector<std::string>{"07", "08", "35"}));
  ASSERT_EQ(picked.size(), 6u);
  EXPECT_EQ(picked[0], "07_02 (person 07, walk 0): poses 1-4 at frames 11 39 75 108");
  // The pose faces the heading it is given (the BVH body's front is +x at heading 0).
  const body_scan_driver::sim::HumanBodySpec turned = people.spec(0, 1, 1, 0.5);
  EXPECT_DOUBLE_EQ(turned.pose.heading, 0.5);
  ScanOptions options;
  options.scanner = ScannerKind::kTruth;
  options.progress = false;
  const FittedWalks walks = fitWalks(people, 2, options);
  const std::vector<NamedMetrics> results = crossWalkProtocol(walks, thesisRows());
  print(results);
  const RecognitionMetrics& both = row(results, "3D dynamic+static").metrics;
  EXPECT_EQ(both.enrolled_probes, 60);
  EXPECT_DOUBLE_EQ(both.identification.rate, 1.0);  // measured 60 / 60
  EXPECT_DOUBLE_EQ(row(results, "3D dynamic").metrics.identification.rate, 1.0);
  EXPECT_THROW(bvhPeople({files[0], files[2], files[3]}, map, 2), std::runtime_error);
}

}  // namespace
}  // namespace body_gait_id::eval
