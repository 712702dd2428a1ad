// Rig design (plan_rig): searches pole and pair layouts for the fewest timing groups that still
// cover the subject. Every candidate is scored on the coarse proxy of timing_groups.h (its
// conflicts and the body surface some pair lights and sees, standing and in two walking
// stances); the best candidates per group count are then scanned by the simulator
// (simulateScan + evaluateScan) on the given subjects. Deterministic for a seed. Evaluation and
// design only (it reads the simulator's ground truth): library body_scan_rig_design.
#pragma once

#include <body_scan_driver/sim/rig.h>
#include <body_scan_driver/sim/scene.h>
#include <body_scan_merge/eval/scan_accuracy.h>
#include <body_scan_merge/simulated_scan.h>
#include <body_scan_merge/timing_groups.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace body_scan_merge::design {

struct Range {
  double min = 0, max = 0;
  double at(double unit) const { return min + unit * (max - min); }  // unit in [0, 1]
};

// The family of rigs searched. Poles stand on a circle around the subject's axis, symmetric
// about its front (+x): 3 poles = two in front at +-front_azimuth and one behind; 4 poles = two
// in front and two behind at 180 -+ back_azimuth. Every pole holds the same pairs (level 1 on
// top), each looking at the axis.
struct RigTemplate {
  int poles = 3;
  int pairs_per_pole = 4;
  Range pole_distance{0.95, 1.15};  // m, pole to the subject's axis
  Range front_azimuth_deg{30, 60};  // of the front poles
  Range back_azimuth_deg{30, 60};   // 4 poles: the back poles' offset from straight behind
  std::vector<Range> heights;       // m, camera height per level (top first)
  std::vector<Range> pitches_deg;   // per level, > 0 looks down
  Range sweep_deg{40, 40};          // projector sweep, centred 16 deg below the camera axis
  int bits = 8;                     // stripes = 2^bits
  double focal_px = 810;            // camera (640 x 480): the field of view
  // Heights and pitches for the pair count, pole count and sweep given above: levels spread
  // from 0.30 to 1.85 m, the top looking down, the bottom up. Throws std::invalid_argument for
  // fewer than 2 or more than 8 pairs per pole, or fewer than 3 or more than 4 poles.
  static RigTemplate standard(int poles, int pairs_per_pole, Range sweep_deg = {40, 40});
};

// One layout of the template.
struct RigLayoutChoice {
  int poles = 3, pairs_per_pole = 4;
  double pole_distance = 1.0, front_azimuth_deg = 35, back_azimuth_deg = 0;
  std::vector<double> heights, pitches_deg;
  double sweep_deg = 40;
  int bits = 8;
  double focal_px = 810;
};

// The pair models and poses (pole_a, pole_b, ... and pair_1 ... on each; seeds 100 x pole + pair).
body_scan_driver::sim::Rig buildRig(const RigLayoutChoice& choice, const std::string& name);
// The rig file (config/rigs format) of the choice; `comment` goes on top as # lines.
std::string rigFileYaml(const RigLayoutChoice& choice, const std::string& name,
                        const std::string& comment);

// Proxy subjects: standing (InterferenceProxy's default) and two walking stances (one arm and
// the opposite leg forward, and the mirror image).
std::vector<InterferenceProxy> proxySubjects(double spacing);

struct ProxyScore {
  int pairs = 0;
  int groups = 0;
  double coverage = 0;  // the least proxyCoverage over proxySubjects
};
// floor_radius: the planner's floor disc (InterferenceProxy::floor_radius; the ScanCoordinator's
// ~floor_radius).
ProxyScore scoreOnProxy(const body_scan_driver::sim::Rig& rig, double spacing = 0.02,
                        double floor_radius = InterferenceProxy{}.floor_radius);

// What the simulator measures for one rig.
struct SimulatedScore {
  TimingGroupList groups;
  double min_coverage = 0;           // least body coverage over the subjects
  double min_standing_coverage = 1;  // least over subjects whose name starts with "standing"
  double min_region_coverage = 0;    // least over subjects and hard regions
  double mean_distance = 0;          // m, mean over subjects
  size_t outliers = 0;               // points beyond 20 mm of the truth, all subjects
  std::vector<std::pair<std::string, eval::ScanAccuracy>> per_subject;
};

struct Subject {
  std::string name;
  std::shared_ptr<const body_scan_driver::sim::Scene> scene;
};

// Scans every subject with the rig's planned timing groups (planTimingGroups on its factory
// geometry) and evaluates the clouds.
SimulatedScore scoreInSimulator(const body_scan_driver::sim::Rig& rig,
                                const std::vector<Subject>& subjects,
                                double floor_radius = InterferenceProxy{}.floor_radius);

// The worst fraction of wrong stripes on the person of any pair projecting with its timing
// group, and alone (test_timing_groups' measure), on one subject.
struct InterferenceScore {
  double worst_grouped = 0, worst_alone = 0;
};
InterferenceScore measureInterference(
    const body_scan_driver::sim::Rig& rig, const TimingGroupList& groups,
    const std::shared_ptr<const body_scan_driver::sim::Scene>& scene);

struct DesignOptions {
  int candidates = 200;   // random layouts per template (plus the template's centre)
  int refine_steps = 60;  // local search steps from each of the 3 fewest group counts' best
  uint32_t seed = 1;
  int finalists = 2;  // per group count, the best by proxy coverage go to the simulator
  // Candidates below are not finalists. The proxy counts less than the simulator sees (the
  // thesis rig: 85 % on the proxy, 91-98 % simulated).
  double min_proxy_coverage = 0.8;
  double proxy_spacing = 0.02;
  double floor_radius = InterferenceProxy{}.floor_radius;  // the planner's floor disc (m)
};

struct Candidate {
  RigLayoutChoice choice;
  ProxyScore proxy;
  bool simulated = false;
  SimulatedScore simulation;
};

struct DesignResult {
  std::vector<Candidate> candidates;  // every one scored, simulated ones with their figures
  // Index into candidates of the pick: the fewest groups among the simulated candidates that
  // meet the coverage targets, then the most coverage; -1 when none does.
  int chosen = -1;
  // When none does: the simulated candidate with the most least-body-coverage (-1: none).
  int closest = -1;
};

struct CoverageTargets {
  double body = 0.95, standing = 0.98, region = 0.90;
};

// Progress lines go to `log` (may be empty).
DesignResult designRig(const std::vector<RigTemplate>& templates,
                       const std::vector<Subject>& subjects, const DesignOptions& options,
                       const CoverageTargets& targets,
                       const std::function<void(const std::string&)>& log = {});

// The trade-off: per template and group count, the best candidate (simulated first, then by
// proxy coverage). A markdown table.
std::string tradeOffTable(const DesignResult& result);
// The same as a PNG plot (groups on x, coverage on y, one marker per candidate, the simulated
// ones filled). Throws std::runtime_error if it cannot be written.
void writeTradeOffPlot(const DesignResult& result, const std::string& path);

}  // namespace body_scan_merge::design
