#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include "sim_fixtures.h"
#include "sphere_fit.h"

using namespace body_scan_driver;

namespace {

std::vector<Eigen::Vector3d> reconstruct(const sim::VirtualPair& pair,
                                         const sim::RenderedPatternSet& set, bool subpixel) {
  DecoderParams params;
  params.subpixel = subpixel;
  StripeImage image;
  StripeDecoder(pair.layout(), params).decode(set.frames, image);
  cv::Mat4f points(image.coordinate.size());
  Triangulator(pair.factoryCalibration()).triangulate(image.coordinate, points.ptr<float>(), 4);
  std::vector<Eigen::Vector3d> valid;
  for (const cv::Vec4f& p : cv::Mat_<cv::Vec4f>(points))
    if (std::isfinite(p[2])) valid.emplace_back(p[0], p[1], p[2]);
  return valid;
}

}  // namespace

TEST(Triangulation, RayPlaneIntersectionIsExact) {
  const Eigen::Vector4d plane(0.1, -0.9, 0.3, -0.25);
  const Eigen::Vector3d point = intersectRayPlane({0.2, -0.1}, plane);
  EXPECT_NEAR(plane.head<3>().dot(point) + plane[3], 0.0, 1e-12);
  EXPECT_NEAR(point.x() / point.z(), 0.2, 1e-12);
  EXPECT_TRUE(std::isnan(intersectRayPlane({0.2, -0.1}, {0, 0, 1, 1}).z()));  // behind camera
}

TEST(Triangulation, PlaneAtOneMetreWithFactoryCalibration) {
  const sim::VirtualPair pair(test::pairLookingAlongX(), test::planeScene(1.0));
  const sim::RenderedPatternSet set = pair.render(21);
  double mean_error[2];
  for (bool subpixel : {false, true}) {
    const std::vector<Eigen::Vector3d> points = reconstruct(pair, set, subpixel);
    ASSERT_GT(points.size(), 250000u);
    double sum = 0;
    for (const Eigen::Vector3d& p : points) sum += std::abs(p.z() - 1.0);  // true plane z = 1
    mean_error[subpixel] = 1000 * sum / points.size();
    std::cout << "[ figure ] plane at 1.0 m, subpixel " << subpixel << ": " << points.size()
              << " points, mean |error| " << mean_error[subpixel] << " mm\n";
  }
  EXPECT_LE(mean_error[1], 1.0);
  EXPECT_LT(mean_error[1], mean_error[0]);
}

TEST(Triangulation, SphereOfRadius25mmAtOneMetre) {
  constexpr double kRadius = 0.025;
  auto scene = std::make_shared<sim::Scene>();
  scene->add(std::make_unique<sim::Sphere>(Eigen::Vector3d(1.0, 0.02, -0.03), kRadius,
                                           sim::Material{0.6, {0.9, 0.9, 0.9}}));
  const sim::VirtualPair pair(test::pairLookingAlongX(), scene);
  const sim::RenderedPatternSet set = pair.render(31);
  double radius_error[2];
  for (bool subpixel : {false, true}) {
    const std::vector<Eigen::Vector3d> points = reconstruct(pair, set, subpixel);
    ASSERT_GT(points.size(), 800u);
    const test::SphereFit fit = test::fitSphere(points);
    radius_error[subpixel] = 1000 * std::abs(fit.radius - kRadius);
    std::cout << "[ figure ] sphere r = 25 mm, subpixel " << subpixel << ": " << points.size()
              << " points, fitted r = " << 1000 * fit.radius << " mm, rms " << 1000 * fit.rms
              << " mm\n";
  }
  EXPECT_LE(radius_error[1], 0.5);
}

TEST(Triangulation, RejectsAStripeImageOfTheWrongSize) {
  const sim::VirtualPair pair(test::pairLookingAlongX(), test::planeScene(1.0));
  const Triangulator triangulator(pair.factoryCalibration());
  std::vector<float> out(320 * 240 * 3);
  try {
    triangulator.triangulate(cv::Mat1f(240, 320, 0.f), out.data(), 3);
    FAIL() << "size mismatch accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("640x480"), std::string::npos) << e.what();
  }
}

namespace {

// Every SIMD level must write the floats of the SSE2 baseline and nothing else.
void expectSimdLevelsAgree(const sim::VirtualPair& pair, StripeImage& image, size_t min_valid,
                           const std::string& what) {
  for (int v = 0; v < image.coordinate.rows; v += 7)  // some invalid pixels too
    image.coordinate(v, v % image.coordinate.cols) = std::numeric_limits<float>::quiet_NaN();
  for (size_t stride : {size_t{4}, size_t{3}}) {
    const size_t floats = stride * image.coordinate.total() + 1;
    std::vector<float> expected(floats, 42.f);
    const size_t expected_valid =
        Triangulator(pair.factoryCalibration(), 0.2, 5.0, SimdLevel::kSse2)
            .triangulate(image.coordinate, expected.data(), stride);
    EXPECT_GT(expected_valid, min_valid) << what;
    // The 4th float of stride-4 points and the float after the last point stay untouched.
    for (size_t i = 3; stride == 4 && i < floats; i += stride)
      ASSERT_EQ(expected[i], 42.f) << what << ": field " << i << " overwritten";
    ASSERT_EQ(expected.back(), 42.f) << what;
    for (SimdLevel level : availableSimdLevels()) {
      std::vector<float> points(floats, 42.f);
      EXPECT_EQ(Triangulator(pair.factoryCalibration(), 0.2, 5.0, level)
                    .triangulate(image.coordinate, points.data(), stride),
                expected_valid)
          << what;
      EXPECT_EQ(std::memcmp(points.data(), expected.data(), floats * sizeof(float)), 0)
          << what << ", " << simdLevelName(level) << ", stride " << stride;
    }
  }
}

}  // namespace

TEST(Triangulation, EverySimdLevelGivesTheSameFloatsAndKeepsOtherFields) {
  // A plane filling the view (one plane along most rows) and the person (planes change along
  // rows on the curved body), both with scattered invalid pixels; strides 4 and 3.
  const sim::VirtualPair plane(test::pairLookingAlongX(), test::planeScene(1.0));
  StripeImage image;
  StripeDecoder(plane.layout()).decode(plane.render(31).frames, image);
  expectSimdLevelsAgree(plane, image, 300000, "plane");
  const std::string config = sim::driverConfigDir();
  const sim::VirtualPair person(
      sim::loadVirtualPairConfig(config + "/pairs/default_pair.yaml"),
      std::make_shared<sim::Scene>(sim::loadScene(config + "/scenes/standing_person.yaml")));
  StripeDecoder(person.layout()).decode(person.render(37).frames, image);
  expectSimdLevelsAgree(person, image, 100000, "person");
}
