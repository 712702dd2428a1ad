#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/sim/decoding_errors.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <body_scan_merge/eval/rig_design.h>
#include <body_scan_merge/simulated_scan.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <tuple>

namespace body_scan_merge::design {
namespace {

constexpr double kDegree = M_PI / 180;
// The thesis projector's sweep: 4 deg above to 36 deg below its camera's axis (config/pairs).
constexpr double kThesisSweepDeg = 40, kSweepCentreDeg = 16;

const eval::Region kHardRegions[] = {eval::Region::kUnderChin,     eval::Region::kArmpitLeft,
                                     eval::Region::kArmpitRight,   eval::Region::kGroin,
                                     eval::Region::kTorsoSideLeft, eval::Region::kTorsoSideRight};

double round(double value, double step) { return std::round(value / step) * step; }

// Uniform in [0, 1) from the generator's bits: the same on every standard library.
double unit(std::mt19937& generator) { return (generator() >> 8) * (1.0 / 16777216.0); }

std::vector<double> poleAzimuthsDeg(const RigLayoutChoice& c) {
  if (c.poles == 3) return {c.front_azimuth_deg, -c.front_azimuth_deg, 180};
  return {c.front_azimuth_deg, -c.front_azimuth_deg, 180 - c.back_azimuth_deg,
          180 + c.back_azimuth_deg};
}

std::string number(double value) {
  std::ostringstream out;
  out << std::setprecision(6) << value;
  return out.str();
}

// The template's dimensions, each a unit coordinate in [0, 1].
int dimensions(const RigTemplate& t) { return 4 + 2 * t.pairs_per_pole; }

RigLayoutChoice choiceAt(const RigTemplate& t, const std::vector<double>& units) {
  size_t next = 0;
  auto pick = [&](const Range& range) { return range.at(units[next++]); };
  RigLayoutChoice c;
  c.poles = t.poles;
  c.pairs_per_pole = t.pairs_per_pole;
  c.pole_distance = round(pick(t.pole_distance), 0.01);
  c.front_azimuth_deg = round(pick(t.front_azimuth_deg), 0.5);
  const double back = round(pick(t.back_azimuth_deg), 0.5);
  c.back_azimuth_deg = t.poles == 4 ? back : 0;
  for (int level = 0; level < t.pairs_per_pole; ++level) {
    c.heights.push_back(round(pick(t.heights[level]), 0.01));
    c.pitches_deg.push_back(round(pick(t.pitches_deg[level]), 0.5));
  }
  c.sweep_deg = round(pick(t.sweep_deg), 1);
  c.bits = t.bits;
  c.focal_px = t.focal_px;
  return c;
}

}  // namespace

RigTemplate RigTemplate::standard(int poles, int pairs_per_pole, Range sweep_deg) {
  if (poles < 3 || poles > 4)
    throw std::invalid_argument("rig template: " + std::to_string(poles) +
                                " poles; the layouts searched have 3 or 4");
  if (pairs_per_pole < 2 || pairs_per_pole > 8)
    throw std::invalid_argument("rig template: " + std::to_string(pairs_per_pole) +
                                " pairs per pole; 2 to 8 cover a standing adult");
  RigTemplate t;
  t.poles = poles;
  t.pairs_per_pole = pairs_per_pole;
  t.sweep_deg = sweep_deg;
  const double top = 1.85, bottom = 0.30, step = (top - bottom) / (pairs_per_pole - 1);
  for (int level = 0; level < pairs_per_pole; ++level) {
    const double height = top - level * step;
    t.heights.push_back({std::max(0.2, height - 0.4 * step), std::min(2.0, height + 0.4 * step)});
    // The top pair looks down at the head, the others anywhere from up under the chin to down.
    t.pitches_deg.push_back(level == 0 ? Range{8, 30} : Range{-15, 20});
  }
  return t;
}

std::string rigFileYaml(const RigLayoutChoice& c, const std::string& name,
                        const std::string& comment) {
  std::ostringstream out;
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) out << "# " << line << "\n";
  out << "name: " << name << "\n";
  std::vector<std::string> defaults;
  const body_scan_driver::sim::VirtualPairConfig standard;
  if (c.bits != standard.bits)
    defaults.push_back("pattern: {bits: " + std::to_string(c.bits) + "}");
  if (c.focal_px != standard.camera.alpha)
    defaults.push_back("camera: {alpha: " + number(c.focal_px) + ", beta: " + number(c.focal_px) +
                       "}");
  if (c.sweep_deg != kThesisSweepDeg) {
    // The beam leaves at twice the mirror angle: beam angle below the axis = 2 mirror - 90.
    const double first = (90 + kSweepCentreDeg - c.sweep_deg / 2) / 2;
    const double last = (90 + kSweepCentreDeg + c.sweep_deg / 2) / 2;
    defaults.push_back("projector: {first_mirror_angle_deg: " + number(first) +
                       ", last_mirror_angle_deg: " + number(last) + "}");
  }
  out << "pair_defaults: {";
  for (size_t i = 0; i < defaults.size(); ++i) out << (i ? ", " : "") << defaults[i];
  out << "}\npoles:\n";
  const std::vector<double> azimuths = poleAzimuthsDeg(c);
  for (int pole = 0; pole < c.poles; ++pole) {
    const double azimuth = azimuths[pole] * kDegree;
    out << "  - name: pole_" << static_cast<char>('a' + pole) << "\n";
    out << "    position: [" << number(round(c.pole_distance * std::cos(azimuth), 0.001)) << ", "
        << number(round(c.pole_distance * std::sin(azimuth), 0.001)) << "]\n";
    out << "    pairs:\n";
    for (int level = 0; level < c.pairs_per_pole; ++level)
      out << "      - {name: pair_" << level + 1 << ", height: " << number(c.heights[level])
          << ", pitch_deg: " << number(c.pitches_deg[level])
          << ", seed: " << 100 * (pole + 1) + level + 1 << "}\n";
  }
  return out.str();
}

body_scan_driver::sim::Rig buildRig(const RigLayoutChoice& choice, const std::string& name) {
  // Through the rig file itself: what the tool writes is what was scored.
  static std::atomic<int> counter{0};
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("plan_rig_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".yaml");
  std::ofstream(path) << rigFileYaml(choice, name, "");
  try {
    body_scan_driver::sim::Rig rig = body_scan_driver::sim::loadRig(path.string());
    std::filesystem::remove(path);
    return rig;
  } catch (...) {
    std::filesystem::remove(path);
    throw;
  }
}

std::vector<InterferenceProxy> proxySubjects(double spacing) {
  InterferenceProxy standing;
  standing.spacing = spacing;
  standing.floor_radius = 0;
  // Heel strike: the left arm and the right leg forward, the other two back.
  InterferenceProxy walking = standing;
  walking.parts = {{0, 0, 0.15, 0.21, 0.80, 1.50},         {0.14, 0.30, 0.06, 0.06, 0.80, 1.45},
                   {-0.14, -0.30, 0.06, 0.06, 0.80, 1.45}, {-0.13, 0.10, 0.08, 0.08, 0.0, 0.85},
                   {0.15, -0.10, 0.08, 0.08, 0.0, 0.85},   {0, 0, 0.10, 0.09, 1.45, 1.95}};
  InterferenceProxy mirrored = walking;
  for (ProxyCylinder& part : mirrored.parts) part.center_y = -part.center_y;
  return {standing, walking, mirrored};
}

ProxyScore scoreOnProxy(const body_scan_driver::sim::Rig& rig, double spacing,
                        double floor_radius) {
  const std::vector<PairGeometry> geometry = rigFactoryGeometry(rig);
  InterferenceProxy proxy;
  proxy.spacing = spacing;
  proxy.floor_radius = floor_radius;
  ProxyScore score;
  score.pairs = static_cast<int>(rig.pairs.size());
  score.groups = static_cast<int>(minimumGroups(lightConflicts(geometry, proxy)).size());
  score.coverage = 1;
  for (const InterferenceProxy& subject : proxySubjects(spacing))
    score.coverage = std::min(score.coverage, proxyCoverage(geometry, subject));
  return score;
}

SimulatedScore scoreInSimulator(const body_scan_driver::sim::Rig& rig,
                                const std::vector<Subject>& subjects, double floor_radius) {
  SimulatedScore score;
  InterferenceProxy planner;
  planner.floor_radius = floor_radius;
  score.groups = planTimingGroups(rigFactoryGeometry(rig), planner).groups;
  score.per_subject.resize(subjects.size());
  // Subjects on 2 threads (each scan renders its pairs one after another).
  std::atomic<size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto work = [&] {
    for (size_t i; (i = next++) < subjects.size();) {
      try {
        const SimulatedScan scan = simulateScan(rig, subjects[i].scene, score.groups);
        score.per_subject[i] = {subjects[i].name,
                                eval::evaluateScan(scan.cloud.xyzrgb, *subjects[i].scene)};
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        failure = std::current_exception();
      }
    }
  };
  std::thread helper(work);
  work();
  helper.join();
  if (failure) std::rethrow_exception(failure);
  score.min_coverage = score.min_region_coverage = 1;
  for (const auto& [name, accuracy] : score.per_subject) {
    score.min_coverage = std::min(score.min_coverage, accuracy.body.fraction());
    if (name.rfind("standing", 0) == 0)
      score.min_standing_coverage = std::min(score.min_standing_coverage, accuracy.body.fraction());
    for (eval::Region region : kHardRegions)
      if (accuracy.regions.count(region) && accuracy.regions.at(region).area > 0)
        score.min_region_coverage =
            std::min(score.min_region_coverage, accuracy.regions.at(region).fraction());
    score.mean_distance += accuracy.mean_distance / score.per_subject.size();
    score.outliers += accuracy.outliers;
  }
  return score;
}

InterferenceScore measureInterference(
    const body_scan_driver::sim::Rig& rig, const TimingGroupList& groups,
    const std::shared_ptr<const body_scan_driver::sim::Scene>& scene) {
  std::vector<body_scan_driver::sim::VirtualPair> projectors;
  projectors.reserve(rig.pairs.size());
  for (const auto& config : rig.pairs)
    projectors.push_back(body_scan_driver::sim::VirtualPair::projectorOnly(config, scene));
  auto projector = [&](const std::string& id) {
    for (const auto& p : projectors)
      if (p.config().pair_id == id) return &p;
    throw std::invalid_argument("measureInterference: '" + id + "' is not in the rig");
  };
  InterferenceScore score;
  for (const auto& group : groups)
    for (const auto& id : group) {
      const body_scan_driver::sim::VirtualPair pair(rig.pair(id), scene);
      std::vector<const body_scan_driver::sim::VirtualPair*> others;
      for (const auto& other : group)
        if (other != id) others.push_back(projector(other));
      score.worst_grouped =
          std::max(score.worst_grouped, body_scan_driver::sim::wrongStripeFraction(
                                            pair.render(1, others), *scene, pair.layout()));
      score.worst_alone = std::max(score.worst_alone, body_scan_driver::sim::wrongStripeFraction(
                                                          pair.render(1), *scene, pair.layout()));
    }
  return score;
}

namespace {

bool meets(const SimulatedScore& s, const CoverageTargets& targets) {
  return s.min_coverage >= targets.body && s.min_standing_coverage >= targets.standing &&
         s.min_region_coverage >= targets.region;
}

int plannedGroups(const Candidate& c) {
  return c.simulated ? static_cast<int>(c.simulation.groups.size()) : c.proxy.groups;
}

}  // namespace

DesignResult designRig(const std::vector<RigTemplate>& templates,
                       const std::vector<Subject>& subjects, const DesignOptions& options,
                       const CoverageTargets& targets,
                       const std::function<void(const std::string&)>& log) {
  auto say = [&](const std::string& line) {
    if (log) log(line);
  };
  DesignResult result;
  std::mt19937 generator(options.seed);
  for (const RigTemplate& t : templates) {
    if (static_cast<int>(t.heights.size()) != t.pairs_per_pole ||
        static_cast<int>(t.pitches_deg.size()) != t.pairs_per_pole)
      throw std::invalid_argument("rig template: heights and pitches need one range per level (" +
                                  std::to_string(t.pairs_per_pole) + ")");
    const size_t first = result.candidates.size();
    std::vector<std::vector<double>> units;  // of each candidate of this template
    auto evaluate = [&](const std::vector<double>& at) {
      Candidate candidate;
      candidate.choice = choiceAt(t, at);
      candidate.proxy = scoreOnProxy(buildRig(candidate.choice, "candidate"), options.proxy_spacing,
                                     options.floor_radius);
      result.candidates.push_back(std::move(candidate));
      units.push_back(at);
      return result.candidates.back().proxy;
    };
    // Random layouts (the template's centre first), ...
    for (int k = 0; k <= options.candidates; ++k) {
      std::vector<double> at(dimensions(t), 0.5);
      if (k > 0)
        for (double& u : at) u = unit(generator);
      evaluate(at);
    }
    // ... then, for the 3 fewest group counts found, a local search from the best-covering
    // layout with at most that many groups: a random step in a few coordinates, kept when it
    // covers more without more groups.
    std::map<int, size_t> best_with;  // group count -> candidate index (most coverage)
    for (size_t i = first; i < result.candidates.size(); ++i) {
      const ProxyScore& p = result.candidates[i].proxy;
      auto found = best_with.find(p.groups);
      if (found == best_with.end() || p.coverage > result.candidates[found->second].proxy.coverage)
        best_with[p.groups] = i;
    }
    int refined = 0;
    for (const auto& [groups, start] : std::map<int, size_t>(best_with)) {
      if (refined++ >= 3) break;
      std::vector<double> current = units[start - first];
      double coverage = result.candidates[start].proxy.coverage;
      for (int step = 0; step < options.refine_steps; ++step) {
        std::vector<double> at = current;
        for (double& u : at)
          if (unit(generator) < 0.3) u = std::clamp(u + 0.3 * (unit(generator) - 0.5), 0.0, 1.0);
        const ProxyScore score = evaluate(at);
        if (score.groups <= groups && score.coverage > coverage) {
          current = at;
          coverage = score.coverage;
        }
      }
    }
    // Finalists: per proxy group count (fewest first), the best by proxy coverage.
    std::map<int, std::vector<size_t>> by_groups;
    for (size_t i = first; i < result.candidates.size(); ++i)
      if (result.candidates[i].proxy.coverage >= options.min_proxy_coverage)
        by_groups[result.candidates[i].proxy.groups].push_back(i);
    std::ostringstream summary;
    summary << t.poles << " poles x " << t.pairs_per_pole
            << " pairs: " << result.candidates.size() - first << " layouts on the proxy;";
    for (const auto& [groups, members] : by_groups)
      summary << " " << members.size() << " with " << groups << " groups";
    say(summary.str());
    bool met = false;
    int group_counts = 0;
    for (auto& [groups, members] : by_groups) {
      if (met || group_counts++ >= 3) break;
      std::stable_sort(members.begin(), members.end(), [&](size_t a, size_t b) {
        return result.candidates[a].proxy.coverage > result.candidates[b].proxy.coverage;
      });
      for (int f = 0; f < options.finalists && f < static_cast<int>(members.size()); ++f) {
        Candidate& candidate = result.candidates[members[f]];
        candidate.simulation = scoreInSimulator(buildRig(candidate.choice, "candidate"), subjects,
                                                options.floor_radius);
        candidate.simulated = true;
        met = met || meets(candidate.simulation, targets);
        std::ostringstream line;
        line << "  simulated: proxy " << groups << " groups / " << std::fixed
             << std::setprecision(1) << 100 * candidate.proxy.coverage << " % -> planned "
             << candidate.simulation.groups.size() << " groups, coverage min "
             << 100 * candidate.simulation.min_coverage << " %, regions min "
             << 100 * candidate.simulation.min_region_coverage << " %, mean "
             << std::setprecision(3) << 1000 * candidate.simulation.mean_distance << " mm, "
             << candidate.simulation.outliers << " points beyond 20 mm";
        say(line.str());
      }
    }
  }
  for (size_t i = 0; i < result.candidates.size(); ++i) {
    const Candidate& c = result.candidates[i];
    if (!c.simulated || !meets(c.simulation, targets)) continue;
    if (result.chosen < 0) {
      result.chosen = static_cast<int>(i);
      continue;
    }
    const Candidate& best = result.candidates[result.chosen];
    const auto key = [](const Candidate& x) {
      return std::make_tuple(plannedGroups(x), x.proxy.pairs, -x.simulation.min_coverage);
    };
    if (key(c) < key(best)) result.chosen = static_cast<int>(i);
  }
  for (size_t i = 0; i < result.candidates.size(); ++i) {
    const Candidate& c = result.candidates[i];
    if (c.simulated &&
        (result.closest < 0 ||
         c.simulation.min_coverage > result.candidates[result.closest].simulation.min_coverage))
      result.closest = static_cast<int>(i);
  }
  return result;
}

namespace {

// Per (poles, pairs per pole, planned groups): the best candidate, simulated ones first.
std::map<std::tuple<int, int, int>, size_t> bestPerCell(const DesignResult& result) {
  std::map<std::tuple<int, int, int>, size_t> best;
  for (size_t i = 0; i < result.candidates.size(); ++i) {
    const Candidate& c = result.candidates[i];
    const auto cell = std::make_tuple(c.choice.poles, c.choice.pairs_per_pole, plannedGroups(c));
    auto found = best.find(cell);
    if (found == best.end()) {
      best[cell] = i;
      continue;
    }
    const Candidate& other = result.candidates[found->second];
    const auto rank = [](const Candidate& x) {
      return std::make_pair(x.simulated,
                            x.simulated ? x.simulation.min_coverage : x.proxy.coverage);
    };
    if (rank(c) > rank(other)) found->second = i;
  }
  return best;
}

std::string millimetres(double metres) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(3) << 1000 * metres << " mm";
  return out.str();
}

std::string percent(double fraction) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << 100 * fraction << " %";
  return out.str();
}

}  // namespace

std::string tradeOffTable(const DesignResult& result) {
  std::ostringstream out;
  out << "| poles x pairs | groups | acquisition (0.5 s/group) | sweep | proxy coverage | "
         "simulated: least body coverage | least standing | least hard region | mean distance "
         "| chosen |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& [cell, index] : bestPerCell(result)) {
    const Candidate& c = result.candidates[index];
    const int groups = plannedGroups(c);
    out << "| " << c.choice.poles << " x " << c.choice.pairs_per_pole << " | " << groups << " | "
        << 0.5 * groups << " s | " << c.choice.sweep_deg << " deg | " << percent(c.proxy.coverage)
        << " | ";
    if (c.simulated) {
      out << percent(c.simulation.min_coverage) << " | "
          << percent(c.simulation.min_standing_coverage) << " | "
          << percent(c.simulation.min_region_coverage) << " | "
          << millimetres(c.simulation.mean_distance) << " | ";
    } else {
      out << "- | - | - | - | ";
    }
    out << (static_cast<int>(index) == result.chosen ? "yes" : "") << " |\n";
  }
  return out.str();
}

void writeTradeOffPlot(const DesignResult& result, const std::string& path) {
  const int width = 720, height = 480, left = 70, right = 190, top = 30, bottom = 50;
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  int max_groups = 1;
  for (const Candidate& c : result.candidates) max_groups = std::max(max_groups, plannedGroups(c));
  const double low = 0.6, high = 1.0;
  auto x_of = [&](double groups) {
    return left + static_cast<int>((groups - 0.5) / max_groups * (width - left - right));
  };
  auto y_of = [&](double coverage) {
    coverage = std::clamp(coverage, low, high);
    return top + static_cast<int>((high - coverage) / (high - low) * (height - top - bottom));
  };
  const cv::Scalar black(0, 0, 0), grey(200, 200, 200);
  cv::line(image, {left, top}, {left, height - bottom}, black);
  cv::line(image, {left, height - bottom}, {width - right, height - bottom}, black);
  for (int g = 1; g <= max_groups; ++g)
    cv::putText(image, std::to_string(g), {x_of(g) - 5, height - bottom + 20},
                cv::FONT_HERSHEY_SIMPLEX, 0.45, black);
  for (double c = low; c <= high + 1e-9; c += 0.1) {
    cv::line(image, {left, y_of(c)}, {width - right, y_of(c)}, grey);
    cv::putText(image, std::to_string(static_cast<int>(std::round(100 * c))) + "%",
                {left - 45, y_of(c) + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, black);
  }
  cv::putText(image, "timing groups", {left + 150, height - 12}, cv::FONT_HERSHEY_SIMPLEX, 0.5,
              black);
  cv::putText(image, "coverage (hollow: proxy, filled: simulated)", {left, 20},
              cv::FONT_HERSHEY_SIMPLEX, 0.5, black);
  const cv::Scalar colours[] = {{200, 80, 0},  {0, 120, 220}, {0, 160, 0},
                                {160, 0, 160}, {0, 0, 200},   {120, 120, 0}};
  std::map<std::pair<int, int>, int> colour_of;
  for (const Candidate& c : result.candidates) {
    const auto key = std::make_pair(c.choice.poles, c.choice.pairs_per_pole);
    if (!colour_of.count(key)) {
      const int index = static_cast<int>(colour_of.size());
      colour_of[key] = index;
      const int y = top + 20 + 22 * index;
      cv::circle(image, {width - right + 20, y}, 5, colours[index % 6], cv::FILLED);
      cv::putText(image,
                  std::to_string(key.first) + " poles x " + std::to_string(key.second) + " pairs",
                  {width - right + 32, y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, black);
    }
    const cv::Scalar colour = colours[colour_of[key] % 6];
    // Spread the markers of one group count a little so they do not hide each other.
    const int jitter = (colour_of[key] - 1) * 6;
    cv::circle(image, {x_of(c.proxy.groups) + jitter, y_of(c.proxy.coverage)}, 3, colour, 1);
    if (c.simulated)
      cv::circle(image, {x_of(plannedGroups(c)) + jitter, y_of(c.simulation.min_coverage)}, 6,
                 colour, cv::FILLED);
  }
  if (result.chosen >= 0) {
    const Candidate& c = result.candidates[result.chosen];
    cv::circle(
        image,
        {x_of(plannedGroups(c)) + (colour_of[{c.choice.poles, c.choice.pairs_per_pole}] - 1) * 6,
         y_of(c.simulation.min_coverage)},
        10, black, 2);
  }
  std::vector<uchar> png;
  if (!cv::imencode(".png", image, png))
    throw std::runtime_error("trade-off plot: could not encode '" + path + "' as PNG");
  body_scan_driver::writeFileAtomically(path, std::string(png.begin(), png.end()));
}

}  // namespace body_scan_merge::design
