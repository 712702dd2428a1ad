// Decode + triangulate one 640x480 pattern set (8 bits + inverses + lit + dark = 18 frames),
// single thread, three contenders on the same frames:
//   .../ours                 our decoder (shadow mask, bits, subpixel) + triangulation
//   .../opencv_getProjPixel  OpenCV structured_light decoding the same frames (no subpixel,
//                            no triangulation)
//   .../ours_reference       the same with DecoderParams::Implementation::kReference
//   .../copy                 a plain copy of the same bytes (the memory-bound floor)
//   .../triangulate_only     our triangulation alone (hot only)
//   .../read_frames_write_outputs  read every frame byte and write every output byte (stripe
//                            ids, coordinates, the 4-float cloud): the floor for any decoder
//                            with our outputs
// Scenes: "plane" fills the view (every pixel decodes: the worst case); "person" is the
// single_pair scene. Cache: "hot" repeats one set (it stays in cache); "stream" cycles through
// 8 sets (44 MB, more than the last-level cache), as pattern sets arriving from a camera do.
// RenderPatternSet times the virtual pair (2 threads), on the plane also with the optics of real
// captures (.../plane_real_optics: a 2.5-stripe line, blooming, stray light, shot noise; ratio
// against .../plane); RenderPersonSet1Thread one person's set on one thread, the mesh human (ours)
// against the ellipsoid body. Every case runs kRepetitions times; scripts/bench_report.py takes the
// medians and prints the ratios against .../ours.
#include <benchmark/benchmark.h>
#include <body_scan_driver/pair_device.h>
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>

#include <cstring>
#include <map>
#include <opencv2/core/utility.hpp>
#include <opencv2/structured_light/graycodepattern.hpp>

using namespace body_scan_driver;

namespace {

constexpr int kStreamSets = 8;
constexpr int kRepetitions = 5;

struct SceneSets {
  std::unique_ptr<sim::VirtualPair> pair;
  std::vector<std::vector<cv::Mat>> sets;  // kStreamSets copies in separate memory
};

const SceneSets& scene(const std::string& name) {
  static std::map<std::string, SceneSets> scenes;
  SceneSets& entry = scenes[name];
  if (entry.pair) return entry;
  std::shared_ptr<sim::Scene> world;
  sim::VirtualPairConfig config;
  if (name == "plane" || name == "plane_real_optics") {
    world = std::make_shared<sim::Scene>();
    world->add(std::make_unique<sim::Plane>(Eigen::Vector3d(1.0, 0, 0), Eigen::Vector3d(-1, 0, 0),
                                            sim::Material{0.8, {0.8, 0.8, 0.8}}));
    config.world_from_camera = sim::cameraPose({0, 0, 0}, 0, 0);
    if (name == "plane_real_optics") config = sim::withRealCaptureOptics(config);
  } else {
    // "person": the ellipsoid body; "mesh_person": the mesh human in the same pose.
    world = std::make_shared<sim::Scene>(sim::loadScene(
        sim::driverConfigDir() +
        (name == "mesh_person" ? "/scenes/mesh_person.yaml" : "/scenes/standing_person.yaml")));
    config = sim::loadVirtualPairConfig(sim::driverConfigDir() + "/pairs/default_pair.yaml");
  }
  entry.pair = std::make_unique<sim::VirtualPair>(config, world);
  const std::vector<cv::Mat> frames = entry.pair->render(1).frames;
  for (int i = 0; i < kStreamSets; ++i) {
    std::vector<cv::Mat> copy;
    for (const cv::Mat& frame : frames) copy.push_back(frame.clone());
    entry.sets.push_back(std::move(copy));
  }
  return entry;
}

int setCount(const benchmark::State& state) { return state.range(1) ? kStreamSets : 1; }
const char* sceneName(const benchmark::State& state) { return state.range(0) ? "person" : "plane"; }

void decodeTriangulate(benchmark::State& state, DecoderParams::Implementation implementation) {
  cv::setNumThreads(1);
  const SceneSets& s = scene(sceneName(state));
  DecoderParams params;
  params.implementation = implementation;
  const StripeDecoder decoder(s.pair->layout(), params);
  const Triangulator triangulator(s.pair->factoryCalibration());
  StripeImage stripes;
  std::vector<float> cloud(640 * 480 * 4);
  size_t valid = 0, next = 0;
  for (auto _ : state) {
    decoder.decode(s.sets[next++ % setCount(state)], stripes);
    valid = triangulator.triangulate(stripes.coordinate, cloud.data(), 4);
    benchmark::DoNotOptimize(cloud.data());
  }
  state.counters["points"] = static_cast<double>(valid);
}

void ours(benchmark::State& state) {
  decodeTriangulate(state, DecoderParams::Implementation::kFast);
  state.SetLabel(simdLevelName(detectedSimdLevel()));
}

// Our triangulation alone (the set decoded once before timing), for the roofline.
void triangulateOnly(benchmark::State& state) {
  const SceneSets& s = scene(sceneName(state));
  StripeImage stripes;
  StripeDecoder(s.pair->layout()).decode(s.sets[0], stripes);
  const Triangulator triangulator(s.pair->factoryCalibration());
  std::vector<float> cloud(640 * 480 * 4);
  for (auto _ : state) {
    benchmark::DoNotOptimize(triangulator.triangulate(stripes.coordinate, cloud.data(), 4));
    benchmark::ClobberMemory();
  }
}

void oursReference(benchmark::State& state) {
  decodeTriangulate(state, DecoderParams::Implementation::kReference);
}

void opencvGetProjPixel(benchmark::State& state) {
  cv::setNumThreads(1);
  const SceneSets& s = scene(sceneName(state));
  // 256 x 2 projector: x from our 8 pattern/inverse pairs, a 1-bit y from a repeated pair.
  auto opencv = cv::structured_light::GrayCodePattern::create(256, 2);
  std::vector<std::vector<cv::Mat>> sets;
  for (const auto& set : s.sets) {
    std::vector<cv::Mat> frames(set.begin() + 2, set.end());
    frames.insert(frames.end(), set.begin() + 2, set.begin() + 4);
    sets.push_back(std::move(frames));
  }
  cv::Mat1w stripe(480, 640);
  size_t next = 0;
  for (auto _ : state) {
    const std::vector<cv::Mat>& frames = sets[next++ % setCount(state)];
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
  const SceneSets& s = scene(sceneName(state));
  const size_t frame_bytes = 640 * 480;
  std::vector<uint8_t> destination(frame_bytes * s.sets[0].size());
  size_t next = 0;
  for (auto _ : state) {
    const std::vector<cv::Mat>& frames = s.sets[next++ % setCount(state)];
    for (size_t i = 0; i < frames.size(); ++i)
      std::memcpy(destination.data() + i * frame_bytes, frames[i].data, frame_bytes);
    benchmark::DoNotOptimize(destination.data());
    benchmark::ClobberMemory();
  }
}

void readFramesWriteOutputs(benchmark::State& state) {
  const SceneSets& s = scene(sceneName(state));
  const size_t pixels = 640 * 480;
  cv::Mat1w stripe(480, 640);
  cv::Mat1f coordinate(480, 640);
  std::vector<float> cloud(pixels * 4);
  size_t next = 0;
  for (auto _ : state) {
    const std::vector<cv::Mat>& frames = s.sets[next++ % setCount(state)];
    uint8_t any = 0;  // every byte is read (the OR cannot stop early) ...
    for (const cv::Mat& frame : frames) {
      const uint8_t* bytes = frame.data;
      for (size_t i = 0; i < pixels; ++i) any |= bytes[i];
    }
    // ... and every output byte written, with a value that depends on what was read.
    std::fill_n(stripe.ptr<uint16_t>(), pixels, static_cast<uint16_t>(any));
    std::fill_n(coordinate.ptr<float>(), pixels, static_cast<float>(any));
    std::fill(cloud.begin(), cloud.end(), static_cast<float>(any));
    benchmark::DoNotOptimize(stripe.data);
    benchmark::DoNotOptimize(coordinate.data);
    benchmark::DoNotOptimize(cloud.data());
    benchmark::ClobberMemory();
  }
}

void render(benchmark::State& state) {
  cv::setNumThreads(2);
  const SceneSets& s = scene(state.range(0) == 2 ? "plane_real_optics"
                             : state.range(0)    ? "person"
                                                 : "plane");
  uint32_t scan = 2;
  for (auto _ : state) benchmark::DoNotOptimize(s.pair->render(scan++).frames.data());
}

// One person's pattern set on one thread: the mesh human (.../ours) against the ellipsoid body
// (.../ellipsoid), same pair and pose.
void renderOneThread(benchmark::State& state) {
  cv::setNumThreads(1);
  const SceneSets& s = scene(state.range(0) ? "mesh_person" : "person");
  uint32_t scan = 2;
  for (auto _ : state) benchmark::DoNotOptimize(s.pair->render(scan++).frames.data());
  cv::setNumThreads(2);
}

void registerAll() {
  for (int person : {0, 1})
    for (int stream : {0, 1}) {
      const std::string group = std::string("DecodeTriangulate/") + (person ? "person" : "plane") +
                                (stream ? "/stream" : "/hot");
      auto add = [&](const char* name, void (*function)(benchmark::State&)) {
        return benchmark::RegisterBenchmark((group + "/" + name).c_str(), function)
            ->Args({person, stream})
            ->Unit(benchmark::kMillisecond)
            ->Repetitions(kRepetitions)
            ->ReportAggregatesOnly(true);
      };
      add("ours", ours);
      add("ours_reference", oursReference);
      add("opencv_getProjPixel", opencvGetProjPixel)->Iterations(16);
      add("copy", copy);
      add("read_frames_write_outputs", readFramesWriteOutputs);
      if (!stream) add("triangulate_only", triangulateOnly);
    }
  for (int scene : {0, 1, 2})
    benchmark::RegisterBenchmark(scene == 2   ? "RenderPatternSet/plane_real_optics"
                                 : scene == 1 ? "RenderPatternSet/person"
                                              : "RenderPatternSet/plane",
                                 render)
        ->Args({scene, 0})
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Iterations(10)
        ->Repetitions(3)
        ->ReportAggregatesOnly(true);
  for (int mesh : {1, 0})
    benchmark::RegisterBenchmark(
        mesh ? "RenderPersonSet1Thread/ours" : "RenderPersonSet1Thread/ellipsoid", renderOneThread)
        ->Args({mesh})
        ->Unit(benchmark::kMillisecond)
        ->Iterations(5)
        ->Repetitions(3)
        ->ReportAggregatesOnly(true);
}

}  // namespace

int main(int argc, char** argv) {
  registerAll();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
