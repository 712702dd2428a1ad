// Torso cross-sections (5.5.2): polygon areas against analytic ellipses, interpolation over
// holes, and the torso's ends and direction (eqs 5.5-5.8) against the simulator's skeleton.
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <body_gait_model/torso_fit.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<Eigen::Vector2d> ellipse(double a, double b, double hole_from = 0, double hole_to = 0) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 3600; ++i) {
    const double t = -kPi + 2 * kPi * i / 3600;
    if (t >= hole_from && t < hole_to) continue;
    points.emplace_back(a * std::cos(t), b * std::sin(t));
  }
  return points;
}

TEST(TorsoFit, CrossSectionAreaMatchesAnEllipseAndBridgesHoles) {
  const double a = 0.18, b = 0.13, exact = kPi * a * b;
  const CrossSection full = crossSection(ellipse(a, b), 0.0, 36);
  EXPECT_EQ(full.filled_sectors, 36);
  EXPECT_NEAR(full.area / exact, 1.0, 0.015);  // closest points: an inscribed polygon
  EXPECT_LT(full.centre.norm(), 1e-3);
  // A 60-degree hole (e.g. the side hidden under an arm): interpolated, within 3 %.
  const CrossSection holed = crossSection(ellipse(a, b, 0.2, 0.2 + kPi / 3), 0.0, 36);
  EXPECT_LE(holed.filled_sectors, 31);
  std::printf("[ figure ] ellipse area error %.2f %% full, %.2f %% with a 60 deg hole\n",
              100 * (full.area / exact - 1), 100 * (holed.area / exact - 1));
  EXPECT_NEAR(holed.area / exact, 1.0, 0.03);
  EXPECT_EQ(crossSection({{0.1, 0}, {0, 0.1}}, 0.0, 36).area, 0.0);  // < 3 sectors
  EXPECT_THROW(crossSection({}, 0.0, 2), std::invalid_argument);
}

TEST(TorsoFit, TorsoEndsAndLeanMatchTheSimulatedBody) {
  auto spec = eval::simulatedSubjects(2)[1];
  eval::ScanRig rig;
  rig.columns = 200;
  rig.rows = 162;
  for (double lean : {0.0, 0.2}) {
    spec.pose = eval::gaitPose(2, 0.8);
    spec.pose.torso_lean = lean;
    const auto body = eval::sampleBody(spec, rig);
    const BodyAxes axes = estimateBodyAxes(body.points);
    std::vector<Eigen::Vector3d> model_points;
    for (const auto& p : body.points) model_points.push_back(axes.toModel(p));
    const TorsoFit torso = fitTorso(model_points, axes);
    const double shoulder_line = axes.toModel(eval::trueJoint(body, "neck")).y();
    const double hips = axes.toModel(eval::trueJoint(body, "pelvis")).y();
    const double knees = axes.toModel(eval::trueJoint(body, "left_knee")).y();
    // Upper torso: tilt of n_ut forward (toward +Z_m) against the true lean.
    const double tilt = std::atan2(torso.upper_direction.z(), torso.upper_direction.y());
    std::printf(
        "[ figure ] lean %.1f deg: n_ut tilt %.1f deg; top %.0f mm above the shoulder "
        "line, base %.0f mm below the hip joints\n",
        lean * 180 / kPi, tilt * 180 / kPi, 1000 * (torso.top - shoulder_line),
        1000 * (hips - torso.base));
    // The pelvis, which does not lean and sits in front of the hips as a real one does, reaches
    // above the waist into the upper torso's lowest sections: n_ut 3.0 deg back standing, 5.8 deg
    // short of an 11.5 deg lean (2.1 and 0.0 with the pelvis centred behind the hips).
    EXPECT_NEAR(tilt, lean, 6.5 * kPi / 180);
    EXPECT_GT(torso.top, shoulder_line - 0.05);  // the torso's top: about the neck's base
    EXPECT_LT(torso.top, shoulder_line + 0.10);
    EXPECT_LT(torso.base, hips);  // the lower torso ends at the crotch, above the knees
    EXPECT_GT(torso.base, knees + 0.2);
  }
}

TEST(TorsoFit, DarkTrunksLeaveTheLowerTorsoDirectionNearTheTruth) {
  // Trunks that return no light leave only the thighs' and hands' points around the hips: the
  // open sections' centroids must not steer n_lt (they tilted it by up to 51 deg, and the
  // legs, split at the lower torso's axis, then got no points). Under these trunks no closed
  // section lies 5 cm below the waist, so n_lt falls back to the vertical, which the simulated
  // (always upright) pelvis has.
  eval::ScanRig rig;
  rig.columns = 200;
  rig.rows = 162;
  rig.min_albedo = 0.3;
  double worst = 0;
  for (const auto& subject : eval::simulatedSubjects(4)) {
    for (int pose = 1; pose <= 4; ++pose) {
      auto spec = subject;
      spec.pose = eval::gaitPose(pose, 0.5 + 1.3 * pose);
      const auto body = eval::sampleBody(spec, rig);
      const BodyAxes axes = estimateBodyAxes(body.points);
      std::vector<Eigen::Vector3d> model_points;
      for (const auto& p : body.points) model_points.push_back(axes.toModel(p));
      const TorsoFit torso = fitTorso(model_points, axes);
      // The simulated pelvis stays upright (a lean turns the torso above it): n_lt = -Y_m.
      const double angle = std::acos(std::clamp(-torso.lower_direction.y(), -1.0, 1.0)) * 180 / kPi;
      worst = std::max(worst, angle);
    }
  }
  std::printf("[ figure ] dark trunks, 4 subjects x 4 poses: n_lt within %.1f deg of the truth\n",
              worst);
  EXPECT_LT(worst, 15.0);
}

TEST(TorsoFit, MeshPeoplesCrotchStaysPutAcrossTheirWalks) {
  // In a stride the thighs apart (and the hands beside them) span sections larger than the
  // pelvis below the crotch: a base taken only where the sections fall below delta_lt a_g
  // dropped to min_base_height in some scans (mesh people: 220-250 mm below the hip joints,
  // 80-140 mm in the person's other scans). The base's height below the true hip joints over
  // 2 walks x 4 poses of each person, SD averaged over 6 people: 50 mm before, 33 mm with the
  // crotch also found where the sections widen again.
  eval::ScanRig rig;
  rig.columns = 200;
  rig.rows = 162;
  rig.body = eval::BodyKind::kMesh;
  double mean_sd = 0;
  const auto people = eval::simulatedPeople(6, 3);
  for (const auto& person : people) {
    std::vector<double> below_hips;
    for (int trial = 0; trial < 2; ++trial)
      for (int pose = 1; pose <= 4; ++pose) {
        const auto body = eval::sampleBody(eval::walkingSubject(person, pose, trial), rig);
        const BodyAxes axes = estimateBodyAxes(body.points);
        std::vector<Eigen::Vector3d> model_points;
        for (const auto& p : body.points) model_points.push_back(axes.toModel(p));
        const TorsoFit torso = fitTorso(model_points, axes);
        below_hips.push_back(axes.toModel(eval::trueJoint(body, "pelvis")).y() - torso.base);
      }
    double mean = 0, square = 0;
    for (double b : below_hips) mean += b / below_hips.size();
    for (double b : below_hips) square += (b - mean) * (b - mean) / below_hips.size();
    mean_sd += std::sqrt(square) / people.size();
  }
  std::printf("[ figure ] mesh people, 6 x 2 walks x 4 poses: the base's SD %.0f mm\n",
              1000 * mean_sd);
  EXPECT_LT(mean_sd, 0.04);
}

// A column of horizontal ellipses from -1.0 to 0.75 m (model frame, g at 0), two in each 10 mm
// slice; area_at(slice height) is each one's area as a fraction of a_g (0.15 x 0.10 m at g).
std::vector<Eigen::Vector3d> stackedSections(const std::function<double(double)>& area_at) {
  std::vector<Eigen::Vector3d> points;
  for (int k = -100; k <= 75; ++k) {
    const double scale = std::sqrt(area_at(0.01 * k));
    const auto outline = ellipse(0.15 * scale, 0.10 * scale);
    for (double y : {0.01 * k - 0.002, 0.01 * k + 0.002})
      for (size_t i = 0; i < outline.size(); i += 10)
        points.emplace_back(outline[i].x(), y, outline[i].y());
  }
  return points;
}

TEST(TorsoFit, OneWiderSliceBelowANarrowingIsNotTheCrotchButLastingWideningIs) {
  BodyAxes axes;
  axes.lowest = -1.0;
  axes.highest = 0.75;
  axes.stature = axes.height();
  axes.shoulder_top = 0.45;
  // Head and neck, trunk, a narrowing (< 0.75 a_g, not < delta_lt a_g), wider again down to
  // wide_to, then the legs (< delta_lt a_g).
  auto body = [](double y, double wide_to) {
    if (y > 0.505) return 0.15;
    if (y > -0.145) return 1.0;
    if (y > -0.175) return 0.7;
    if (y > wide_to) return 1.3;
    return 0.2;
  };
  // One wider slice (-0.18 m; CMU walk 07_08 had such a one), the crotch at -0.19 m.
  const TorsoFit one = fitTorso(stackedSections([&](double y) { return body(y, -0.185); }), axes);
  // The thighs apart: wider down to -0.25 m.
  const TorsoFit lasting =
      fitTorso(stackedSections([&](double y) { return body(y, -0.255); }), axes);
  std::printf("[ figure ] base %.3f m after one wider slice, %.3f m above lasting widening\n",
              one.base, lasting.base);
  EXPECT_NEAR(one.base, -0.19, 0.001);      // -0.17 when one wider slice counts
  EXPECT_NEAR(lasting.base, -0.17, 0.001);  // -0.26 without the widening rule
}

}  // namespace
}  // namespace body_gait_model
