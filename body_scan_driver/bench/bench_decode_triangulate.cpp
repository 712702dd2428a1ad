// One 640x480 pattern set (8 bits + inverses + lit + dark = 18 frames) of a plane filling the
// view (every pixel decodes: the worst case), single thread:
//   DecodeTriangulate/ours             our decode (shadow mask, bits, subpixel) + triangulation
//   DecodeTriangulate/opencv_getProjPixel  OpenCV structured_light decoding the same frames
//   DecodeTriangulate/copy             a plain copy of the same bytes (memory-bound floor)
//   RenderPatternSet                   the virtual pair rendering the set (2 threads)
// scripts/bench_report.py turns the JSON into ratios against .../ours.
#include <benchmark/benchmark.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>
#include <body_scan_driver/sim/virtual_pair.h>

#include <cstring>
#include <opencv2/core/utility.hpp>
#include <opencv2/structured_light/graycodepattern.hpp>

using namespace body_scan;

namespace {

struct Fixture {
  Fixture() {
    auto scene = std::make_shared<sim::Scene>();
    scene->add(std::make_unique<sim::Plane>(Eigen::Vector3d(1.0, 0, 0), Eigen::Vector3d(-1, 0, 0),
                                            sim::Material{0.8, {0.8, 0.8, 0.8}}));
    sim::VirtualPairConfig config;
    config.world_from_camera = sim::cameraPose({0, 0, 0}, 0, 0);
    pair = std::make_unique<sim::VirtualPair>(config, scene);
    frames = pair->render(1).frames;
  }
  std::unique_ptr<sim::VirtualPair> pair;
  std::vector<cv::Mat> frames;
};

const Fixture& fixture() {
  static const Fixture instance;
  return instance;
}

void ours(benchmark::State& state) {
  cv::setNumThreads(1);
  const Fixture& f = fixture();
  const StripeDecoder decoder(f.pair->layout());
  const Triangulator triangulator(f.pair->factoryCalibration());
  StripeImage stripes;
  std::vector<float> cloud(640 * 480 * 4);
  size_t valid = 0;
  for (auto _ : state) {
    decoder.decode(f.frames, stripes);
    valid = triangulator.triangulate(stripes.coordinate, cloud.data(), 4);
    benchmark::DoNotOptimize(cloud.data());
  }
  state.counters["points"] = static_cast<double>(valid);
}

void opencvGetProjPixel(benchmark::State& state) {
  cv::setNumThreads(1);
  const Fixture& f = fixture();
  // 256 x 2 projector: x from our 8 pattern/inverse pairs, a 1-bit y from a repeated pair.
  auto opencv = cv::structured_light::GrayCodePattern::create(256, 2);
  std::vector<cv::Mat> frames(f.frames.begin() + 2, f.frames.end());
  frames.insert(frames.end(), f.frames.begin() + 2, f.frames.begin() + 4);
  cv::Mat1w stripe(480, 640);
  for (auto _ : state) {
    cv::Point projector_pixel;
    for (int v = 0; v < 480; ++v)
      for (int u = 0; u < 640; ++u) {
        opencv->getProjPixel(frames, u, v, projector_pixel);
        stripe(v, u) = static_cast<uint16_t>(projector_pixel.x);
      }
    benchmark::DoNotOptimize(stripe.data);
  }
}

void copy(benchmark::State& state) {
  const Fixture& f = fixture();
  const size_t frame_bytes = 640 * 480;
  std::vector<uint8_t> destination(frame_bytes * f.frames.size());
  for (auto _ : state) {
    for (size_t i = 0; i < f.frames.size(); ++i)
      std::memcpy(destination.data() + i * frame_bytes, f.frames[i].data, frame_bytes);
    benchmark::DoNotOptimize(destination.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * destination.size()));
}

void render(benchmark::State& state) {
  cv::setNumThreads(2);
  const Fixture& f = fixture();
  uint32_t scan = 2;
  for (auto _ : state) benchmark::DoNotOptimize(f.pair->render(scan++).frames.data());
}

}  // namespace

BENCHMARK(ours)->Name("DecodeTriangulate/ours")->Unit(benchmark::kMillisecond);
BENCHMARK(opencvGetProjPixel)
    ->Name("DecodeTriangulate/opencv_getProjPixel")
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);
BENCHMARK(copy)->Name("DecodeTriangulate/copy")->Unit(benchmark::kMillisecond);
BENCHMARK(render)->Name("RenderPatternSet")->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
