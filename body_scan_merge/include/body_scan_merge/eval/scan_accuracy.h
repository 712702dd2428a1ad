// Accuracy of a whole-body scan against the simulator's true surface: evaluation
// only - it reads ground truth (the scene's body surfaces and skeleton), so nothing in the
// scanning pipeline may use it. Library body_scan_merge_eval.
#pragma once

#include <body_scan_driver/sim/scene.h>

#include <map>
#include <string>
#include <vector>

namespace body_scan_merge::eval {

// Body regions of the report. Soles are excluded from coverage (no pair looks up at them).
enum class Region {
  kOther,
  kSoles,
  kUnderChin,
  kArmpitLeft,
  kArmpitRight,
  kGroin,
  kTorsoSideLeft,
  kTorsoSideRight
};
const char* regionName(Region region);

struct SurfaceSample {
  Eigen::Vector3d position, normal;  // world
  double area = 0;                   // m^2 this sample stands for
  Region region = Region::kOther;
  int segment = -1;  // index into the body's segment names (sampleBodySurface's segments)
};

// Area-weighted samples (about one per spacing^2) of the outer skin of the body named
// `body_name` (its surfaces are "<body_name>/..."): points inside another of its surfaces are
// dropped. Regions from the true skeleton (definitions in scan_accuracy.cpp).
std::vector<SurfaceSample> sampleBodySurface(const body_scan_driver::sim::Scene& scene,
                                             const std::string& body_name = "person",
                                             double spacing = 0.002,
                                             std::vector<std::string>* segments = nullptr);

struct AccuracyOptions {
  double coverage_distance = 0.005;  // a surface sample is covered by a point within this
  double outlier_distance = 0.02;    // points farther than this from the body and the floor
  double spacing = 0.002;            // of the true-surface samples
};

struct RegionCoverage {
  double area = 0;          // m^2 of true surface in the region
  double covered_area = 0;  // of which within coverage_distance of a cloud point
  double fraction() const { return area > 0 ? covered_area / area : 0; }
};

struct ScanAccuracy {
  size_t points = 0;
  size_t outliers = 0;                  // farther than outlier_distance from every true surface
  std::vector<size_t> outlier_indices;  // which points (evaluate_scan --outliers writes them)
  double mean_distance = 0;  // m, point to true surface (body or floor), outliers included
  double median_distance = 0;
  double p95_distance = 0;
  double mean_distance_inliers = 0;
  RegionCoverage body;  // everything but the soles
  std::map<Region, RegionCoverage> regions;
  std::map<std::string, RegionCoverage> segments;  // per body segment (head, chest, left_foot...)
};

// cloud: world points, 4 floats each (x y z rgb) as the merge writes them. The floor is the
// plane z = 0 (DESIGN.md section 3) when the scene has one.
ScanAccuracy evaluateScan(const std::vector<float>& cloud,
                          const body_scan_driver::sim::Scene& scene,
                          const AccuracyOptions& options = {},
                          const std::string& body_name = "person");

// YAML report (atomic write); throws FileWriteError naming the path.
void writeAccuracyReport(const std::string& path, const ScanAccuracy& accuracy,
                         const std::string& description);
std::string accuracyReportYaml(const ScanAccuracy& accuracy, const std::string& description);

}  // namespace body_scan_merge::eval
