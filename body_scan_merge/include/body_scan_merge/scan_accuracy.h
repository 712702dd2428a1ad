// Accuracy of a whole-body scan against the simulator's true surface (issue 4): point-to-
// surface distances of the cloud and the area of the outer skin it covers, overall and in the
// hard-to-see regions (under the chin, armpits, groin, sides of the torso). Evaluation only:
// it reads the simulator's ground truth (sim::Scene ellipsoids and skeleton).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace body_scan {
namespace sim {
class Scene;
}

enum class BodyRegion {
  kOther,
  kSoles,  // excluded from coverage: the subject stands on them
  kUnderChin,
  kArmpitLeft,
  kArmpitRight,
  kGroin,
  kTorsoSideLeft,
  kTorsoSideRight,
};
constexpr int kBodyRegionCount = 8;
const char* bodyRegionName(BodyRegion region);

// One area-uniform sample of the outer skin.
struct TrueSurfaceSample {
  Eigen::Vector3f point;   // world
  Eigen::Vector3f normal;  // unit, outward
  float area = 0;          // m^2 this sample stands for
  BodyRegion region = BodyRegion::kOther;
  int surface_index = -1;  // into Scene::surfaces()
};

struct ScanAccuracyOptions {
  double sample_spacing = 0.0025;  // m between true surface samples (area per sample spacing^2)
  std::string body_prefix = "person/";
  double near_body = 0.010;         // cloud points within this of the true surface are evaluated
  double outlier_distance = 0.005;  // evaluated points farther than this are counted outliers
  double coverage_radius = 0.005;   // a true sample is covered by a cloud point this close
  double floor_height = 0.005;      // cloud points below this world z are the floor: skipped
  unsigned seed = 1;
};

// Samples of the outer skin of every surface named body_prefix* (ellipsoids): area-uniform
// with on average one sample per spacing^2, dropping samples inside another body surface.
// Regions from the true skeleton (see scan_accuracy.cpp for their definitions).
// Throws std::runtime_error if the scene has no such ellipsoid or no skeleton.
std::vector<TrueSurfaceSample> sampleTrueSurface(const sim::Scene& scene,
                                                 const ScanAccuracyOptions& options = {});

struct RegionCoverage {
  double area = 0;          // m^2 of the true outer skin in the region
  double covered_area = 0;  // of it with a cloud point within coverage_radius
  double fraction() const { return area > 0 ? covered_area / area : 0.0; }
};

struct ScanAccuracy {
  size_t points = 0;        // in the cloud (finite)
  size_t floor_points = 0;  // below floor_height
  size_t far_points = 0;    // farther than near_body from the body (background, not scored)
  size_t evaluated_points = 0;
  size_t outliers = 0;       // evaluated, farther than outlier_distance
  double mean_distance = 0;  // m, point-to-plane at the nearest true sample, evaluated points
  double median_distance = 0;
  double p95_distance = 0;
  double body_area = 0;  // m^2, soles excluded
  double coverage = 0;   // area fraction of body_area covered
  std::array<RegionCoverage, kBodyRegionCount> regions;
  std::map<int, RegionCoverage> surfaces;  // by Scene::surfaces() index: where coverage is lost
};

ScanAccuracy evaluateScan(const std::vector<Eigen::Vector3f>& cloud,
                          const std::vector<TrueSurfaceSample>& samples,
                          const ScanAccuracyOptions& options = {});
ScanAccuracy evaluateScan(const std::vector<Eigen::Vector3f>& cloud, const sim::Scene& scene,
                          const ScanAccuracyOptions& options = {});

// The report as YAML text (distances in mm, coverage in %), and written atomically. With the
// scene, the coverage of each body surface is listed by name too.
std::string scanAccuracyYaml(const ScanAccuracy& accuracy, const ScanAccuracyOptions& options,
                             const sim::Scene* scene = nullptr);
void writeScanAccuracyReport(const std::string& path, const ScanAccuracy& accuracy,
                             const ScanAccuracyOptions& options, const sim::Scene* scene = nullptr);

}  // namespace body_scan
