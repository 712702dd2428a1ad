// Decode + triangulate + merge of one whole-body scan of the default rig (12 pairs, 18 frames
// each, the standing subject), on 2 threads (pairs split between them), then the merge
// (world transform, crop, 1.5 mm voxel grid; no outlier removal, the launch default):
//   FullScan/ours                 our decoder (kFast) + triangulation + merge, each pair's cloud
//                                 transformed and cropped as soon as it is triangulated
//   FullScan/opencv_getProjPixel  the same pipeline with OpenCV structured_light decoding
//                                 (integer stripes: stripe centres instead of subpixel)
//   FullScan/decode_triangulate   our 12 decodes + triangulations alone
//   FullScan/merge                the merge alone
//   FullScan/merge_pcl_voxel      the merge with PCL's VoxelGrid instead of ours
//   FullScan/merge_fresh          the merge with a new CloudMerger every time (a node's first
//                                 scan): its buffers are touched for the first time
// scripts/bench_report.py prints every case's median over FullScan/ours.
#include <benchmark/benchmark.h>
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>
#include <body_scan_merge/cloud_merge.h>

#include <opencv2/core/utility.hpp>
#include <opencv2/structured_light/graycodepattern.hpp>
#include <thread>

using namespace body_scan_merge;
using namespace body_scan_driver;

namespace {

struct RigScan {
  std::vector<std::vector<cv::Mat>> frames;  // per pair
  std::vector<std::unique_ptr<body_scan_driver::Triangulator>> triangulators;
  std::vector<Eigen::Isometry3d> poses;
  body_scan_driver::PatternLayout layout{8, true};
  std::vector<std::vector<float>> clouds;  // per pair, x y z rgb
};

RigScan& rigScan() {
  static RigScan scan = [] {
    cv::setNumThreads(2);
    RigScan s;
    const body_scan_driver::sim::Rig rig = body_scan_driver::sim::loadRig(
        body_scan_driver::sim::driverConfigDir() + "/rigs/thesis_rig.yaml");
    auto scene = std::make_shared<body_scan_driver::sim::Scene>(body_scan_driver::sim::loadScene(
        body_scan_driver::sim::driverConfigDir() + "/scenes/standing_person.yaml"));
    for (const body_scan_driver::sim::VirtualPairConfig& config : rig.pairs) {
      const body_scan_driver::sim::VirtualPair pair(config, scene);
      s.frames.push_back(pair.render(1).frames);
      s.triangulators.push_back(
          std::make_unique<body_scan_driver::Triangulator>(pair.factoryCalibration()));
      s.poses.push_back(config.world_from_camera);
      s.clouds.emplace_back(640 * 480 * 4, 0.f);
    }
    cv::setNumThreads(1);
    return s;
  }();
  return scan;
}

// Runs work(pair) for every pair, the pairs split between 2 threads.
template <typename Work>
void forEachPairOnTwoThreads(size_t pairs, Work work) {
  std::thread second([&] {
    for (size_t i = 1; i < pairs; i += 2) work(i);
  });
  for (size_t i = 0; i < pairs; i += 2) work(i);
  second.join();
}

// One merger for the whole run, as the Merge nodelet keeps one from scan to scan.
CloudMerger& merger() {
  static CloudMerger merger;
  return merger;
}

CloudView viewOf(const RigScan& s, size_t pair) {
  return CloudView{s.clouds[pair].data(), 640 * 480, 4, 3, s.poses[pair]};
}

MergedCloud merge(const RigScan& s, const MergeOptions& options = {}) {
  std::vector<CloudView> views;
  for (size_t i = 0; i < s.clouds.size(); ++i) views.push_back(viewOf(s, i));
  return merger().merge(views, options);
}

// decodeTriangulate(pair) on 2 threads, each pair's cloud handed to the merger as soon as it is
// made (still in cache), then the voxel grid.
template <typename DecodeTriangulate>
MergedCloud scanAndMerge(RigScan& s, DecodeTriangulate decode_triangulate) {
  merger().begin(s.frames.size(), MergeOptions());
  forEachPairOnTwoThreads(s.frames.size(), [&](size_t i) {
    decode_triangulate(i);
    merger().addPart(i, viewOf(s, i));
  });
  return merger().finish();
}

void decodeTriangulateOurs(RigScan& s, size_t pair) {
  thread_local body_scan_driver::StripeImage stripes;  // one per thread, reused like Triangulate's
  thread_local body_scan_driver::StripeDecoder decoder(body_scan_driver::PatternLayout(8, true));
  decoder.decode(s.frames[pair], stripes);
  s.triangulators[pair]->triangulate(stripes.coordinate, s.clouds[pair].data(), 4);
}

void decodeTriangulateOurs(RigScan& s) {
  forEachPairOnTwoThreads(s.frames.size(), [&](size_t i) { decodeTriangulateOurs(s, i); });
}

void ours(benchmark::State& state) {
  RigScan& s = rigScan();
  size_t points = 0;
  for (auto _ : state)
    points = scanAndMerge(s, [&](size_t i) { decodeTriangulateOurs(s, i); }).size();
  state.counters["points"] = static_cast<double>(points);
  state.SetLabel(body_scan_driver::simdLevelName(body_scan_driver::detectedSimdLevel()));
}

void decodeTriangulate(benchmark::State& state) {
  RigScan& s = rigScan();
  for (auto _ : state) decodeTriangulateOurs(s);
}

void mergeOnly(benchmark::State& state) {
  RigScan& s = rigScan();
  decodeTriangulateOurs(s);
  size_t points = 0;
  double transform = 0, voxel = 0;
  for (auto _ : state) {
    const MergedCloud merged = merge(s);
    points = merged.size();
    for (const auto& [stage, seconds] : merged.stage_seconds)
      (stage == "voxel" ? voxel : transform) += seconds;
  }
  state.counters["points"] = static_cast<double>(points);
  state.counters["transform_crop_ms"] = 1000 * transform / state.iterations();
  state.counters["voxel_ms"] = 1000 * voxel / state.iterations();
}

void mergePclVoxel(benchmark::State& state) {
  RigScan& s = rigScan();
  decodeTriangulateOurs(s);
  MergeOptions options;
  options.voxel_grid = MergeOptions::VoxelGrid::kPcl;
  size_t points = 0;
  for (auto _ : state) points = merge(s, options).size();
  state.counters["points"] = static_cast<double>(points);
}

void mergeFresh(benchmark::State& state) {
  RigScan& s = rigScan();
  decodeTriangulateOurs(s);
  size_t points = 0;
  double transform = 0, voxel = 0;
  for (auto _ : state) {
    std::vector<CloudView> views;
    for (size_t i = 0; i < s.clouds.size(); ++i) views.push_back(viewOf(s, i));
    const MergedCloud merged = mergeClouds(views, MergeOptions());
    points = merged.size();
    for (const auto& [stage, seconds] : merged.stage_seconds)
      (stage == "voxel" ? voxel : transform) += seconds;
  }
  state.counters["points"] = static_cast<double>(points);
  state.counters["transform_crop_ms"] = 1000 * transform / state.iterations();
  state.counters["voxel_ms"] = 1000 * voxel / state.iterations();
}

void opencvGetProjPixel(benchmark::State& state) {
  RigScan& s = rigScan();
  // 256 x 2 projector: x from our 8 pattern/inverse pairs, a 1-bit y from a repeated pair.
  std::vector<std::vector<cv::Mat>> sets;
  for (const auto& set : s.frames) {
    std::vector<cv::Mat> frames(set.begin() + 2, set.end());
    frames.insert(frames.end(), set.begin() + 2, set.begin() + 4);
    sets.push_back(std::move(frames));
  }
  size_t points = 0;
  for (auto _ : state)
    points = scanAndMerge(s, [&](size_t i) {
               thread_local auto opencv = cv::structured_light::GrayCodePattern::create(256, 2);
               thread_local cv::Mat1f coordinate(480, 640);
               cv::Point projector_pixel;
               for (int v = 0; v < 480; ++v)
                 for (int u = 0; u < 640; ++u)
                   // getProjPixel returns true when the pixel is not decodable (shadow).
                   coordinate(v, u) = opencv->getProjPixel(sets[i], u, v, projector_pixel)
                                          ? std::numeric_limits<float>::quiet_NaN()
                                          : projector_pixel.x + 0.5f;
               s.triangulators[i]->triangulate(coordinate, s.clouds[i].data(), 4);
             }).size();
  state.counters["points"] = static_cast<double>(points);
}

void registerAll() {
  auto add = [](const char* name, void (*function)(benchmark::State&)) {
    return benchmark::RegisterBenchmark((std::string("FullScan/") + name).c_str(), function)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Repetitions(5)
        ->ReportAggregatesOnly(true);
  };
  add("ours", ours);
  add("opencv_getProjPixel", opencvGetProjPixel)->Iterations(2)->Repetitions(3);
  add("decode_triangulate", decodeTriangulate);
  add("merge", mergeOnly);
  add("merge_pcl_voxel", mergePclVoxel);
  add("merge_fresh", mergeFresh);
}

}  // namespace

int main(int argc, char** argv) {
  registerAll();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
