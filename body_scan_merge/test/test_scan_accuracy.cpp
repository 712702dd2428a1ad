// The accuracy evaluator against clouds of known error and coverage, made from the true surface.
#include <body_scan_merge/eval/scan_accuracy.h>
#include <gtest/gtest.h>

#include <random>

using namespace body_scan_merge;
using namespace body_scan_merge::eval;

namespace {

const std::string kDriverConfig = BODY_SCAN_DRIVER_CONFIG_DIR;

// A cloud from the true samples, each moved `offset` along its normal (+ Gaussian noise),
// keeping those keep() accepts.
template <typename Keep>
std::vector<float> cloudFrom(const std::vector<SurfaceSample>& samples, double offset, double noise,
                             Keep keep) {
  std::mt19937 generator(3);
  std::normal_distribution<double> jitter(0, noise > 0 ? noise : 1e-15);
  std::vector<float> cloud;
  for (const SurfaceSample& s : samples) {
    if (!keep(s)) continue;
    const Eigen::Vector3d p =
        s.position + (offset + (noise > 0 ? jitter(generator) : 0)) * s.normal;
    cloud.insert(cloud.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()),
                               static_cast<float>(p.z()), 0.f});
  }
  return cloud;
}

}  // namespace

class ScanAccuracyTest : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new body_scan_driver::sim::Scene(
        body_scan_driver::sim::loadScene(kDriverConfig + "/scenes/standing_person.yaml"));
    samples_ = new std::vector<SurfaceSample>(sampleBodySurface(*scene_));
  }
  static void TearDownTestSuite() {
    delete samples_;
    delete scene_;
  }
  static body_scan_driver::sim::Scene* scene_;
  static std::vector<SurfaceSample>* samples_;
};
body_scan_driver::sim::Scene* ScanAccuracyTest::scene_ = nullptr;
std::vector<SurfaceSample>* ScanAccuracyTest::samples_ = nullptr;

TEST_F(ScanAccuracyTest, TheSampledSkinHasABodysAreaAndEveryRegion) {
  double area = 0;
  std::map<Region, double> region_area;
  for (const auto& s : *samples_) area += s.area, region_area[s.region] += s.area;
  std::cout << "[ figure ] true skin of the 1.75 m subject: " << area << " m^2 in "
            << samples_->size() << " samples\n";
  EXPECT_GT(area, 1.5);  // an adult's body surface area: 1.6-2.0 m^2 (DuBois)
  EXPECT_LT(area, 2.3);
  for (Region r : {Region::kSoles, Region::kUnderChin, Region::kArmpitLeft, Region::kArmpitRight,
                   Region::kGroin, Region::kTorsoSideLeft, Region::kTorsoSideRight})
    EXPECT_GT(region_area[r], 0.002) << regionName(r);
}

TEST_F(ScanAccuracyTest, ACloudOnTheSurfaceCoversItAndItsDistanceIsTheNoise) {
  const auto cloud = cloudFrom(*samples_, 0.0, 0.001, [](auto&) { return true; });
  const ScanAccuracy accuracy = evaluateScan(cloud, *scene_);
  EXPECT_NEAR(accuracy.mean_distance, 0.001 * std::sqrt(2 / M_PI), 0.0002);  // E|N(0, 1 mm)|
  EXPECT_GT(accuracy.body.fraction(), 0.99);
  for (const auto& [region, coverage] : accuracy.regions)
    EXPECT_GT(coverage.fraction(), 0.99) << regionName(region);
  EXPECT_EQ(accuracy.outliers, 0u);
}

TEST_F(ScanAccuracyTest, AnOffsetCloudMeasuresTheOffsetAndStrayPointsAreOutliers) {
  auto cloud = cloudFrom(*samples_, 0.003, 0.0, [](auto&) { return true; });
  cloud.insert(cloud.end(), {0.5f, 0.5f, 1.0f, 0.f});  // in the air, far from the body
  const ScanAccuracy accuracy = evaluateScan(cloud, *scene_);
  EXPECT_NEAR(accuracy.mean_distance_inliers, 0.003, 0.0002);
  EXPECT_NEAR(accuracy.median_distance, 0.003, 0.0002);
  EXPECT_EQ(accuracy.outliers, 1u);
}

TEST_F(ScanAccuracyTest, MissingRegionsAreReportedMissing) {
  // No points under the arms or on the back half of the body.
  const auto cloud = cloudFrom(*samples_, 0.0, 0.0, [](const SurfaceSample& s) {
    return s.region != Region::kArmpitLeft && s.region != Region::kArmpitRight &&
           s.position.x() > 0;
  });
  const ScanAccuracy accuracy = evaluateScan(cloud, *scene_);
  std::cout << "[ figure ] front half only: body coverage " << accuracy.body.fraction()
            << ", armpits " << accuracy.regions.at(Region::kArmpitLeft).fraction() << " / "
            << accuracy.regions.at(Region::kArmpitRight).fraction() << "\n";
  EXPECT_NEAR(accuracy.body.fraction(), 0.5, 0.08);
  EXPECT_LT(accuracy.regions.at(Region::kArmpitLeft).fraction(), 0.3);
  EXPECT_LT(accuracy.regions.at(Region::kArmpitRight).fraction(), 0.3);
}
