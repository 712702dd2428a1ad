// Fitting a 1 M point whole-body cloud (thesis 5.5), against named peers in the same run:
//   fit/full          fitBody with the default options (direct fit + Ceres refinement + quality)
//   fit/no_refinement the direct fit of 5.5 alone (peer: what refinement costs)
//   fit/all_points    fitBody without the internal subsample (max_fit_points = 0; peer: what
//                     subsampling the fitting stages saves)
//   axes/pca          estimateBodyAxes alone (peer: the PCA a cylinder baseline would need)
//   fit/walk          fitWalk of the subject's 4 gait poses, 1 M points each (one body, one
//                     Ceres problem; peer: 4 x fit/full)
// Targets: fit/full <= 200 ms on 1 M points; fit/walk <= 1 s.
#include <benchmark/benchmark.h>
#include <body_gait_model/body_fitter.h>
#include <body_gait_model/eval/body_cloud_sampler.h>

namespace {

using namespace body_gait_model;

// One simulated subject in a gait pose (1..4), sampled densely and trimmed to 1,000,000 points.
Cloud millionPointsInPose(int pose) {
  auto spec = eval::simulatedSubjects(2)[1];
  spec.pose = eval::gaitPose(pose, 0.4);
  eval::ScanRig rig;
  rig.columns = 700;
  rig.rows = 570;
  rig.noise_sigma = 0.002;
  Cloud points = eval::sampleBody(spec, rig).points;
  if (points.size() > 1000000) {  // keep an even subsample: every viewpoint stays
    Cloud even;
    even.reserve(1000000);
    for (size_t i = 0; i < 1000000; ++i) even.push_back(points[i * points.size() / 1000000]);
    points.swap(even);
  }
  return points;
}

const Cloud& millionPoints() {
  static const Cloud cloud = millionPointsInPose(1);
  return cloud;
}

void fitWalkOfFourScans(benchmark::State& state) {
  static const std::vector<Cloud> walk = {millionPoints(), millionPointsInPose(2),
                                          millionPointsInPose(3), millionPointsInPose(4)};
  for (auto _ : state) {
    WalkFit result = fitWalk(walk);
    benchmark::DoNotOptimize(result);
  }
  state.counters["points"] = static_cast<double>(4 * walk.front().size());
}

void fit(benchmark::State& state, bool refine, bool subsample = true) {
  const Cloud& cloud = millionPoints();
  FitOptions options;
  options.refine = refine;
  if (!subsample) options.max_fit_points = 0;
  for (auto _ : state) {
    BodyFit result = fitBody(cloud, options);
    benchmark::DoNotOptimize(result);
  }
  state.counters["points"] = static_cast<double>(cloud.size());
}

void fitFull(benchmark::State& state) { fit(state, true); }
void fitNoRefinement(benchmark::State& state) { fit(state, false); }
void fitAllPoints(benchmark::State& state) { fit(state, true, false); }

void axesPca(benchmark::State& state) {
  const Cloud& cloud = millionPoints();
  for (auto _ : state) {
    BodyAxes axes = estimateBodyAxes(cloud);
    benchmark::DoNotOptimize(axes);
  }
  state.counters["points"] = static_cast<double>(cloud.size());
}

}  // namespace

BENCHMARK(fitFull)->Name("fit/full")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(fitNoRefinement)->Name("fit/no_refinement")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(fitAllPoints)->Name("fit/all_points")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(axesPca)->Name("axes/pca")->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(fitWalkOfFourScans)->Name("fit/walk")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_MAIN();
