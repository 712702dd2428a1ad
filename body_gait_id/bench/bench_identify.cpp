// Identification latency (eq 5.16) of the indexed Matcher against its named peer, the
// brute-force double scan (BruteForceMatcher), on synthetic galleries of 10 000 to 1 000 000
// poses (250 to 25 000 subjects x 40 training poses). Targets: <= 1 ms per query at
// 10 000 poses, <= 20 ms at 1 000 000.
//
// The synthetic people walk alike, as people do: one common cycle of 22 joint angles, personal
// amplitude (CV 15 %), phase (0.2 rad) and offset (0.05 rad) deviations, segment lengths with
// CV 5 %, 24 body-shape measures with CV 6 %; every training pose carries 0.02 rad / 5 mm / 2 mm
// fitting noise. A genuine probe is an enrolled person at a phase between the training frames
// (new noise); an impostor probe is a person not enrolled (open-set rejection queries, the slow
// case for any pruning).
#include <benchmark/benchmark.h>
#include <body_gait_id/matcher.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>

namespace body_gait_id {
namespace {

constexpr int kPosesPerSubject = 40;  // eta1 + eta2, 2 x 20 (5.8.3)
constexpr int kProbes = 512;

struct Person {
  Eigen::VectorXd amplitude, phase, offset, lengths, shape;
};

struct Population {
  Eigen::VectorXd amplitude, phase, lengths, shape;  // the common gait and body
  std::mt19937 rng{42};

  Population() {
    std::uniform_real_distribution<double> uniform(0, 1);
    amplitude.resize(22);
    phase.resize(22);
    for (int k = 0; k < 22; ++k) {
      amplitude[k] = 0.05 + 0.5 * uniform(rng);
      phase[k] = 2 * M_PI * uniform(rng);
    }
    lengths = (Eigen::VectorXd::LinSpaced(12, 0.1, 0.5));
    shape = Eigen::VectorXd::LinSpaced(kShapeSize, 0.03, 0.2);
    shape[0] = 1.7;  // standing height
  }
  Person person() {
    std::normal_distribution<double> normal;
    Person p{amplitude, phase, Eigen::VectorXd(22), lengths, shape};
    for (int k = 0; k < 22; ++k) {
      p.amplitude[k] *= 1 + 0.15 * normal(rng);
      p.phase[k] += 0.2 * normal(rng);
      p.offset[k] = 0.05 * normal(rng);
    }
    for (int k = 0; k < 12; ++k) p.lengths[k] *= 1 + 0.05 * normal(rng);
    for (int k = 0; k < kShapeSize; ++k) p.shape[k] *= 1 + 0.06 * normal(rng);
    return p;
  }
  GaitFeatures pose(const Person& p, double cycle_phase) {
    std::normal_distribution<double> normal;
    GaitFeatures f{Eigen::VectorXd(22), p.lengths, p.shape};
    for (int k = 0; k < 22; ++k)
      f.dynamic[k] =
          p.offset[k] + p.amplitude[k] * std::sin(cycle_phase + p.phase[k]) + 0.02 * normal(rng);
    for (int k = 0; k < 12; ++k) f.statics[k] += 0.005 * normal(rng);
    for (int k = 0; k < kShapeSize; ++k) f.shape[k] += 0.002 * normal(rng);
    return f;
  }
};

struct Fixture {
  std::vector<GalleryPose> gallery;
  std::vector<GaitFeatures> genuine, impostor;
};

const Fixture& fixture(int poses) {
  static std::map<int, std::unique_ptr<Fixture>> cache;
  auto& slot = cache[poses];
  if (!slot) {
    slot = std::make_unique<Fixture>();
    Population population;
    std::vector<Person> people;
    const int subjects = poses / kPosesPerSubject;
    for (int s = 0; s < subjects; ++s) {
      people.push_back(population.person());
      for (int n = 0; n < kPosesPerSubject; ++n)
        slot->gallery.push_back(
            {s, n / 20, n % 20 + 1, population.pose(people.back(), 2 * M_PI * (n % 20) / 20)});
    }
    std::uniform_int_distribution<int> pick(0, subjects - 1);
    std::uniform_real_distribution<double> phase(0, 2 * M_PI);
    for (int i = 0; i < kProbes; ++i) {
      slot->genuine.push_back(population.pose(people[pick(population.rng)], phase(population.rng)));
      slot->impostor.push_back(population.pose(population.person(), phase(population.rng)));
    }
  }
  return *slot;
}

template <typename M>
const M& cached(int poses, FeatureSet set) {
  static std::map<std::pair<int, FeatureSet>, std::unique_ptr<M>> cache;
  auto& slot = cache[{poses, set}];
  if (!slot) {
    if constexpr (std::is_same_v<M, Matcher>)
      slot = std::make_unique<M>(fixture(poses).gallery, set);
    else
      slot = std::make_unique<M>(fixture(poses).gallery, set,
                                 cached<Matcher>(poses, set).normalization());
  }
  return *slot;
}

template <typename M>
void identify(benchmark::State& state, bool genuine) {
  const int poses = static_cast<int>(state.range(0));
  const FeatureSet set = state.range(1) == 2   ? FeatureSet::kDynamicStaticShape
                         : state.range(1) == 1 ? FeatureSet::kDynamicStatic
                                               : FeatureSet::kDynamic;
  const Fixture& data = fixture(poses);
  const M& matcher = cached<M>(poses, set);
  const std::vector<GaitFeatures>& probes = genuine ? data.genuine : data.impostor;
  std::size_t i = 0;
  double score = 0;
  for (auto _ : state) {
    const Match m = matcher.identify(probes[i++ % probes.size()]);
    score += m.score;
    benchmark::DoNotOptimize(score);
  }
  state.counters["poses"] = poses;
  state.counters["mean_score"] = score / double(state.iterations());
}

void indexedGenuine(benchmark::State& state) { identify<Matcher>(state, true); }
void indexedImpostor(benchmark::State& state) { identify<Matcher>(state, false); }
void bruteDoubleGenuine(benchmark::State& state) { identify<BruteForceMatcher>(state, true); }
void bruteDoubleImpostor(benchmark::State& state) { identify<BruteForceMatcher>(state, false); }

// Building the index (normalization fit, principal axes, k-d tree): what a node pays after
// an enrolment, and a peer-less figure (the brute-force peer has no build).
void buildIndex(benchmark::State& state) {
  const int poses = static_cast<int>(state.range(0));
  const Fixture& data = fixture(poses);
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<GalleryPose> gallery = data.gallery;
    state.ResumeTiming();
    const Matcher matcher(std::move(gallery), FeatureSet::kDynamicStatic);
    benchmark::DoNotOptimize(matcher.size());
  }
}
BENCHMARK(buildIndex)->Arg(10'000)->Arg(1'000'000)->Unit(benchmark::kMillisecond);

// The best pose of every subject (CMC, ROC, open set): a full scan with a per-subject early
// exit, no index; the peer is one identify() of the same gallery.
void rankSubjects(benchmark::State& state) {
  const int poses = static_cast<int>(state.range(0));
  const Matcher& matcher = cached<Matcher>(poses, FeatureSet::kDynamicStatic);
  const std::vector<GaitFeatures>& probes = fixture(poses).genuine;
  std::size_t i = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(matcher.rankSubjects(probes[i++ % probes.size()]).size());
}
BENCHMARK(rankSubjects)->Arg(10'000)->Arg(100'000)->Unit(benchmark::kMicrosecond);

// Arguments: gallery poses, feature set (0 dynamic, 1 dynamic + static, 2 + body shape).
void sizes(benchmark::internal::Benchmark* b) {
  for (int set : {1, 0})
    for (int poses : {10'000, 100'000, 1'000'000}) b->Args({poses, set});
  for (int poses : {10'000, 100'000}) b->Args({poses, 2});
  b->Unit(benchmark::kMicrosecond);
}

BENCHMARK(indexedGenuine)->Apply(sizes);
BENCHMARK(bruteDoubleGenuine)->Apply(sizes);
BENCHMARK(indexedImpostor)->Apply(sizes);
BENCHMARK(bruteDoubleImpostor)->Apply(sizes);

}  // namespace
}  // namespace body_gait_id

BENCHMARK_MAIN();
