// Projector calibration pieces against exact synthetic geometry: eq 3.30 lifting, stripe-centre
// extraction, the plane fit, the pinhole baseline and the ideal-sphere fit.
#include <body_scan_calib/pinhole_projector.h>
#include <body_scan_calib/projector_calibration.h>
#include <body_scan_calib/sphere_accuracy.h>
#include <gtest/gtest.h>

#include <random>

using namespace body_scan_driver;
using namespace body_scan_calib;

namespace {

Eigen::Isometry3d tiltedBoardPose() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) *
                   Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()))
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(-0.2, -0.1, 1.1);
  return pose;
}

}  // namespace

TEST(ImageToCameraTransform, LiftsProjectedBoardPointsBackOntoTheBoard) {
  const body_scan_driver::PinholeCamera camera{640, 480, 805, 812, 0.4, 322, 236, -0.09, 0.04};
  const Eigen::Isometry3d pose = tiltedBoardPose();
  std::vector<StripeCentreSample> samples;
  std::vector<Eigen::Vector3d> truth;
  for (double x = 0; x <= 0.4; x += 0.05)
    for (double y = 0; y <= 0.3; y += 0.05) {
      truth.push_back(pose * Eigen::Vector3d(x, y, 0));
      samples.push_back({0, camera.project(truth.back())});
    }
  const std::vector<Eigen::Vector3d> lifted = liftStripePixels(camera, pose, samples);
  ASSERT_EQ(lifted.size(), truth.size());
  for (size_t i = 0; i < truth.size(); ++i) EXPECT_LT((lifted[i] - truth[i]).norm(), 1e-9);
}

TEST(StripeCentres, InterpolatesWhereTheCoordinateCrossesEachStripeCentre) {
  // Coordinate grows down the rows by 0.37 stripes per row from 3.1: centre of stripe i where
  // 3.1 + 0.37 v = i + 0.5.
  cv::Mat1f coordinate(50, 20);
  for (int v = 0; v < coordinate.rows; ++v)
    for (int u = 0; u < coordinate.cols; ++u) coordinate(v, u) = 3.1f + 0.37f * v;
  coordinate(10, 5) = std::numeric_limits<float>::quiet_NaN();
  const std::vector<StripeCentreSample> samples = extractStripeCentres(coordinate, 256);
  ASSERT_FALSE(samples.empty());
  int in_column_0 = 0;
  for (const StripeCentreSample& sample : samples) {
    const double expected_row = (sample.stripe + 0.5 - 3.1) / 0.37;
    EXPECT_NEAR(sample.pixel.y(), expected_row, 1e-4);
    if (sample.pixel.x() == 0) ++in_column_0;
  }
  // Stripes 3 (3.5) .. 20 (20.5 <= 3.1 + 0.37 * 49 = 21.23) in a full column.
  EXPECT_EQ(in_column_0, 18);
}

TEST(PlaneFit, RecoversAPlaneFromNoisyPoints) {
  const Eigen::Vector3d normal = Eigen::Vector3d(0.1, 0.9, -0.4).normalized();
  const double offset = 0.25;
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0, 1e-4);
  const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 500; ++i)
    points.push_back(-offset * normal + (i % 25 - 12) * 0.02 * u + (i / 25 - 10) * 0.02 * v +
                     noise(random) * normal);
  const PlaneFit fit = fitPlane(points);
  // The fit follows the suite's orientation: the truth's dominant (y) component is positive.
  EXPECT_NEAR(fit.plane.head<3>().dot(normal), -1.0, 1e-6);
  EXPECT_NEAR(fit.plane[3], -offset, 2e-5);
  EXPECT_NEAR(fit.rms, 1e-4, 2e-5);
}

TEST(PinholeProjector, DltAndGaussNewtonRecoverAnExactPinholeProjector) {
  // A line camera 0.33 m above the camera: s = (p1 . X) / (p2 . X).
  Eigen::Matrix<double, 2, 4> truth;
  truth << 0, 400, 60, 132, 0, 0.3, 1, 0.0;
  truth /= truth.norm();
  std::vector<Eigen::Vector3d> points;
  std::vector<double> stripes;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> lateral(-0.3, 0.3), depth(0.8, 1.4);
  for (int i = 0; i < 400; ++i) {
    points.emplace_back(lateral(random), lateral(random), depth(random));
    stripes.push_back(PinholeProjector{truth}.stripeAt(points.back()));
  }
  const PinholeProjectorFit fit = estimatePinholeProjector(points, stripes);
  EXPECT_LT(fit.rms_stripes, 1e-6);
  const double sign = fit.projector.projection(0, 1) * truth(0, 1) > 0 ? 1 : -1;
  EXPECT_LT((sign * fit.projector.projection - truth).norm(), 1e-6);
  // Its stripe planes, interpolated as the Triangulator does, are exactly planeAt(s).
  const body_scan_driver::StripePlaneProjector planes = fit.projector.toStripePlanes(256);
  const Eigen::Vector4d interpolated = planes.planeAt(100.3), exact = fit.projector.planeAt(100.3);
  ASSERT_TRUE(interpolated.allFinite());
  EXPECT_NEAR(std::abs(interpolated.normalized().dot(exact.normalized())), 1.0, 1e-12);
}

TEST(IdealSphere, EsMeasuresTheRadialNoiseAndTheCentreIsFound) {
  const Eigen::Vector3d center(0.1, -0.05, 1.0);
  const double radius = 0.025, sigma = 2e-4;
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0, sigma);
  std::vector<Eigen::Vector3d> cap;  // the half the camera sees
  for (int i = 0; i < 3000; ++i) {
    const double polar = 1.4 * (i % 60) / 60.0, azimuth = 2 * M_PI * (i / 60) / 50.0;
    const Eigen::Vector3d direction(std::sin(polar) * std::cos(azimuth),
                                    std::sin(polar) * std::sin(azimuth), -std::cos(polar));
    cap.push_back(center + (radius + noise(random)) * direction);
  }
  const IdealSphereFit fit = fitIdealSphere(cap, radius);
  EXPECT_LT((fit.center - center).norm(), 2e-5);
  EXPECT_NEAR(fit.e_s_m2, sigma * sigma, 0.1 * sigma * sigma);
  EXPECT_EQ(fit.points, 3000);
  EXPECT_THROW(fitIdealSphere({center, center, center}, radius), std::invalid_argument);
}
