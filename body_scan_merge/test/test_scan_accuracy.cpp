// Scan accuracy against the true surface, on synthetic clouds whose answer is known: samples of
// the true surface drawn independently of the evaluation's (another seed), displaced and cut.
#include <body_scan_driver/sim/scene.h>
#include <body_scan_merge/cloud_reader.h>
#include <body_scan_merge/ply_writer.h>
#include <body_scan_merge/scan_accuracy.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <random>

using namespace body_scan;

namespace {

const std::string kDriverConfig = BODY_SCAN_DRIVER_CONFIG_DIR;

class ScanAccuracyTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new sim::Scene(sim::loadScene(kDriverConfig + "/scenes/standing_person.yaml"));
    samples_ = new std::vector<TrueSurfaceSample>(sampleTrueSurface(*scene_));
    ScanAccuracyOptions dense;
    dense.sample_spacing = 0.002;
    dense.seed = 7;
    cloud_samples_ = new std::vector<TrueSurfaceSample>(sampleTrueSurface(*scene_, dense));
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete samples_;
    delete cloud_samples_;
  }
  // The independent samples moved along their normal by offset + N(0, sigma).
  static std::vector<Eigen::Vector3f> cloud(double offset, double sigma) {
    std::mt19937 rng(3);
    std::normal_distribution<float> noise(0.f, static_cast<float>(sigma));
    std::vector<Eigen::Vector3f> points;
    for (const auto& s : *cloud_samples_)
      points.push_back(s.point + (static_cast<float>(offset) + noise(rng)) * s.normal);
    return points;
  }
  static double region(const ScanAccuracy& a, BodyRegion r) {
    return a.regions[static_cast<int>(r)].fraction();
  }
  static sim::Scene* scene_;
  static std::vector<TrueSurfaceSample>* samples_;
  static std::vector<TrueSurfaceSample>* cloud_samples_;
};
sim::Scene* ScanAccuracyTest::scene_ = nullptr;
std::vector<TrueSurfaceSample>* ScanAccuracyTest::samples_ = nullptr;
std::vector<TrueSurfaceSample>* ScanAccuracyTest::cloud_samples_ = nullptr;

const BodyRegion kHardRegions[] = {BodyRegion::kUnderChin,     BodyRegion::kArmpitLeft,
                                   BodyRegion::kArmpitRight,   BodyRegion::kGroin,
                                   BodyRegion::kTorsoSideLeft, BodyRegion::kTorsoSideRight};

}  // namespace

TEST_F(ScanAccuracyTest, TrueSurfaceHasPlausibleAreaAndEveryRegion) {
  double area = 0;
  for (const auto& s : *samples_) area += s.area;
  const ScanAccuracy a = evaluateScan({}, *samples_);
  std::cout << "[ figure ] outer skin " << area << " m^2 in " << samples_->size()
            << " samples; regions (m^2):";
  for (int r = 0; r < kBodyRegionCount; ++r)
    std::cout << " " << bodyRegionName(static_cast<BodyRegion>(r)) << " " << a.regions[r].area;
  std::cout << "\n";
  // Body surface area of a 1.75 m adult: 1.7-2.0 m^2 (Du Bois at 60-80 kg).
  EXPECT_GT(area, 1.5);
  EXPECT_LT(area, 2.2);
  for (BodyRegion r : kHardRegions) EXPECT_GT(a.regions[static_cast<int>(r)].area, 0.002) << int(r);
  EXPECT_GT(region(a, BodyRegion::kSoles) + a.regions[int(BodyRegion::kSoles)].area, 0.01);
  // Left and right regions mirror each other on the symmetric standing subject.
  EXPECT_NEAR(a.regions[int(BodyRegion::kArmpitLeft)].area,
              a.regions[int(BodyRegion::kArmpitRight)].area,
              0.2 * a.regions[int(BodyRegion::kArmpitLeft)].area);
  EXPECT_NEAR(a.regions[int(BodyRegion::kTorsoSideLeft)].area,
              a.regions[int(BodyRegion::kTorsoSideRight)].area,
              0.1 * a.regions[int(BodyRegion::kTorsoSideLeft)].area);
  EXPECT_EQ(a.coverage, 0.0);
}

TEST_F(ScanAccuracyTest, OneMillimetreNoiseGivesMeanAbsoluteNoiseAndFullCoverage) {
  const ScanAccuracy a = evaluateScan(cloud(0, 0.001), *samples_);
  // E|N(0, 1 mm)| = sqrt(2 / pi) mm = 0.798 mm.
  EXPECT_NEAR(a.mean_distance, 0.000798, 0.00006);
  EXPECT_NEAR(a.median_distance, 0.000674, 0.00006);
  EXPECT_NEAR(a.p95_distance, 0.00196, 0.00015);
  EXPECT_GT(a.coverage, 0.9999);
  for (BodyRegion r : kHardRegions) EXPECT_GT(region(a, r), 0.999) << bodyRegionName(r);
  EXPECT_EQ(a.far_points, 0u);
  EXPECT_LT(a.outliers, a.evaluated_points / 10000);
}

TEST_F(ScanAccuracyTest, PointsPushedOutThreeMillimetresGiveThreeMillimetres) {
  const ScanAccuracy a = evaluateScan(cloud(0.003, 0), *samples_);
  EXPECT_NEAR(a.mean_distance, 0.003, 0.0001);
  EXPECT_NEAR(a.median_distance, 0.003, 0.0001);
  EXPECT_GT(a.coverage, 0.999);
  // Outliers and far points: 7 mm and 30 mm off (a few land near another part in the folds).
  const ScanAccuracy b = evaluateScan(cloud(0.007, 0), *samples_);
  EXPECT_GT(b.outliers, 0.97 * b.evaluated_points);
  const ScanAccuracy c = evaluateScan(cloud(0.03, 0), *samples_);
  EXPECT_LT(c.evaluated_points, 0.08 * c.points);
  EXPECT_GT(c.far_points, 0.9 * c.points);
}

TEST_F(ScanAccuracyTest, HalfTheBodyDeletedHalvesCoverage) {
  auto points = cloud(0, 0.001);
  std::vector<Eigen::Vector3f> right;
  for (const auto& p : points)
    if (p.y() < 0) right.push_back(p);  // the subject faces +x: y > 0 is its left side
  const ScanAccuracy a = evaluateScan(right, *samples_);
  EXPECT_NEAR(a.coverage, 0.5, 0.03);
  EXPECT_LT(region(a, BodyRegion::kArmpitLeft), 0.01);
  EXPECT_LT(region(a, BodyRegion::kTorsoSideLeft), 0.01);
  EXPECT_GT(region(a, BodyRegion::kArmpitRight), 0.999);
  EXPECT_GT(region(a, BodyRegion::kTorsoSideRight), 0.999);
}

TEST_F(ScanAccuracyTest, ArmpitPointsRemovedLeaveArmpitsUncoveredAndTheRestCovered) {
  const auto points = cloud(0, 0.001);
  std::vector<Eigen::Vector3f> armpits;
  for (const auto& s : *samples_)
    if (s.region == BodyRegion::kArmpitLeft || s.region == BodyRegion::kArmpitRight)
      armpits.push_back(s.point);
  ASSERT_FALSE(armpits.empty());
  Eigen::AlignedBox3f box;
  for (const auto& p : armpits) box.extend(p);
  box.min().array() -= 0.006f;
  box.max().array() += 0.006f;
  std::vector<Eigen::Vector3f> kept;
  for (const auto& p : points) {
    bool near_armpit = false;
    if (box.contains(p))
      for (const auto& a : armpits)
        if ((a - p).squaredNorm() <= 0.005f * 0.005f) {
          near_armpit = true;
          break;
        }
    if (!near_armpit) kept.push_back(p);
  }
  const ScanAccuracy full = evaluateScan(points, *samples_);
  const ScanAccuracy a = evaluateScan(kept, *samples_);
  EXPECT_EQ(region(a, BodyRegion::kArmpitLeft), 0.0);
  EXPECT_EQ(region(a, BodyRegion::kArmpitRight), 0.0);
  for (BodyRegion r : {BodyRegion::kUnderChin, BodyRegion::kGroin, BodyRegion::kTorsoSideLeft,
                       BodyRegion::kTorsoSideRight})
    EXPECT_NEAR(region(a, r), region(full, r), 0.02) << bodyRegionName(r);
  EXPECT_GT(region(a, BodyRegion::kOther), 0.99);
}

TEST_F(ScanAccuracyTest, ReportIsWrittenAndCloudFilesReadBack) {
  const auto points = cloud(0, 0.001);
  char dir_template[] = "/tmp/test_scan_accuracy_XXXXXX";
  const std::string dir = mkdtemp(dir_template);
  for (const std::string name : {"cloud.ply", "cloud.pcd"}) {
    const std::string path = dir + "/" + name;
    if (name == "cloud.ply")
      writePly(path, points.front().data(), points.size(), 3, -1);
    else
      writePcd(path, points.front().data(), points.size(), 3, -1);
    const auto read = readPointCloud(path);
    ASSERT_EQ(read.size(), points.size()) << name;
    EXPECT_EQ(read[123], points[123]) << name;
    std::remove(path.c_str());
  }
  EXPECT_THROW(readPointCloud(dir + "/missing.ply"), std::runtime_error);
  const ScanAccuracy a = evaluateScan(points, *samples_);
  writeScanAccuracyReport(dir + "/report.yaml", a, {});
  std::ifstream in(dir + "/report.yaml");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("coverage_percent: 100"), std::string::npos) << text;
  EXPECT_NE(text.find("armpit_left:"), std::string::npos) << text;
  EXPECT_EQ(text.find("person/left_thigh:"), std::string::npos) << "no scene, no names";
  EXPECT_NE(scanAccuracyYaml(a, {}, scene_).find("person/left_thigh: {area_m2: 0.1"),
            std::string::npos)
      << scanAccuracyYaml(a, {}, scene_);
  std::remove((dir + "/report.yaml").c_str());
  rmdir(dir.c_str());
}
