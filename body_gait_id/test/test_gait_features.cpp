// Gait features (thesis 5.7), the 2D virtual views (5.8.4) on hand-made poses with known
// projected angles and lengths, and the normalization of eqs 5.14-5.15.
#include <body_gait_id/gait_features.h>
#include <gtest/gtest.h>

#include <cmath>

namespace body_gait_id {
namespace {

using body_gait::BodyModel;

// Index of a movable segment's angle in a 2D dynamic feature (the neck is left out).
int viewIndex(int segment) { return body_gait::jointAngleIndex(segment) / 2; }

BodyModel turnedModel(double heading) {
  BodyModel model = body_gait::standingModel(1.75);
  model.p << 0.3, 0.9, -0.2, 0, heading, 0;
  return model;
}

TEST(GaitFeatures, ThreeDIsJointAnglesAndLengths) {
  BodyModel model = turnedModel(0.4);
  model.setJointAngles(body_gait::kRightUpperLeg, 0.3, -0.1);
  const GaitFeatures f = gaitFeatures(model);
  ASSERT_EQ(f.dynamic.size(), 22);
  ASSERT_EQ(f.statics.size(), 12);
  EXPECT_EQ(f.dynamic, model.q);
  EXPECT_EQ(f.statics, model.r);
}

// Coronal swings (theta_z) are the frontal view's angles, and vanish in the side view.
TEST(GaitFeatures, FrontalViewAnglesAreCoronalJointAngles) {
  for (double heading : {0.0, 1.3, -2.5}) {
    BodyModel model = turnedModel(heading);
    model.setJointAngles(body_gait::kRightUpperArm, 0, -0.3);
    model.setJointAngles(body_gait::kRightLowerArm, 0, -0.2);
    model.setJointAngles(body_gait::kLeftUpperLeg, 0, 0.25);
    const GaitFeatures frontal = gaitFeatures(model, View::kFrontal);
    const GaitFeatures side = gaitFeatures(model, View::kSide);
    ASSERT_EQ(frontal.dynamic.size(), 11);
    ASSERT_EQ(frontal.statics.size(), 12);
    EXPECT_NEAR(frontal.dynamic[viewIndex(body_gait::kRightUpperArm)], -0.3, 1e-12);
    EXPECT_NEAR(frontal.dynamic[viewIndex(body_gait::kRightLowerArm)], -0.2, 1e-12);
    EXPECT_NEAR(frontal.dynamic[viewIndex(body_gait::kLeftUpperLeg)], 0.25, 1e-12);
    EXPECT_NEAR(frontal.dynamic[viewIndex(body_gait::kLeftLowerLeg)], 0.0, 1e-12);
    EXPECT_NEAR(side.dynamic.cwiseAbs().maxCoeff(), 0.0, 1e-12);
    // Lengths: whole in the frontal plane; the side view sees their vertical part only.
    const double arm = model.r[body_gait::kRightUpperArm];
    EXPECT_NEAR(frontal.statics[body_gait::kRightUpperArm], arm, 1e-12);
    EXPECT_NEAR(side.statics[body_gait::kRightUpperArm], arm * std::cos(0.3), 1e-12);
    // The forearm hangs at 0.5 rad from the vertical (0.3 + 0.2).
    const double forearm = model.r[body_gait::kRightLowerArm];
    EXPECT_NEAR(side.statics[body_gait::kRightLowerArm], forearm * std::cos(0.5), 1e-12);
  }
}

// Sagittal swings (theta_x: hip, knee, torso lean) are the side view's angles.
TEST(GaitFeatures, SideViewAnglesAreSagittalJointAngles) {
  for (double heading : {0.0, 0.7, 3.0}) {
    BodyModel model = turnedModel(heading);
    model.setJointAngles(body_gait::kUpperTorso, 0.1, 0);
    model.setJointAngles(body_gait::kRightUpperLeg, -0.4, 0);
    model.setJointAngles(body_gait::kRightLowerLeg, 0.6, 0);
    model.setJointAngles(body_gait::kLeftUpperArm, 0.35, 0);
    const GaitFeatures side = gaitFeatures(model, View::kSide);
    const GaitFeatures frontal = gaitFeatures(model, View::kFrontal);
    EXPECT_NEAR(side.dynamic[viewIndex(body_gait::kUpperTorso)], 0.1, 1e-12);
    EXPECT_NEAR(side.dynamic[viewIndex(body_gait::kRightUpperLeg)], -0.4, 1e-12);
    EXPECT_NEAR(side.dynamic[viewIndex(body_gait::kRightLowerLeg)], 0.6, 1e-12);
    // The arm hangs from the leaning upper torso: its joint angle, not its absolute one.
    EXPECT_NEAR(side.dynamic[viewIndex(body_gait::kLeftUpperArm)], 0.35, 1e-12);
    EXPECT_NEAR(frontal.dynamic.cwiseAbs().maxCoeff(), 0.0, 1e-12);
    // The shank's axis is 0.2 rad off the vertical: the frontal view sees cos(0.2) of it.
    const double shank = model.r[body_gait::kRightLowerLeg];
    EXPECT_NEAR(frontal.statics[body_gait::kRightLowerLeg], shank * std::cos(0.2), 1e-12);
    EXPECT_NEAR(side.statics[body_gait::kRightLowerLeg], shank, 1e-12);
  }
}

TEST(GaitFeatures, ViewsDoNotDependOnHeadingOrPlace) {
  BodyModel a = turnedModel(0.0);
  a.setJointAngles(body_gait::kRightUpperLeg, -0.3, 0.1);
  a.setJointAngles(body_gait::kLeftLowerArm, 0.4, -0.2);
  BodyModel b = a;
  b.p << -1.0, 2.0, 0.5, 0, 2.2, 0;
  for (View view : {View::kFrontal, View::kSide}) {
    const GaitFeatures fa = gaitFeatures(a, view), fb = gaitFeatures(b, view);
    EXPECT_LT((fa.dynamic - fb.dynamic).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((fa.statics - fb.statics).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(FeatureNormalization, MeanAndPopulationSigmaPerComponent) {
  std::vector<GaitFeatures> gallery;
  for (double v : {1.0, 2.0, 3.0, 6.0}) {
    GaitFeatures f;
    f.dynamic = Eigen::Vector2d(v, 5.0);  // second component constant
    f.statics = Eigen::Vector3d(-v, 2 * v, 0.1);
    gallery.push_back(f);
  }
  const FeatureNormalization n = FeatureNormalization::fit(gallery);
  // mean 3, population variance (4 + 1 + 0 + 9) / 4 = 3.5
  EXPECT_DOUBLE_EQ(n.mean_dynamic[0], 3.0);
  EXPECT_DOUBLE_EQ(n.sigma_dynamic[0], std::sqrt(3.5));
  EXPECT_DOUBLE_EQ(n.mean_dynamic[1], 5.0);
  EXPECT_DOUBLE_EQ(n.sigma_dynamic[1], 1.0);  // constant: left unscaled
  EXPECT_DOUBLE_EQ(n.sigma_static[1], 2 * std::sqrt(3.5));
  EXPECT_EQ(n.size(FeatureSet::kDynamic), 2);
  EXPECT_EQ(n.size(FeatureSet::kDynamicStatic), 5);
  const Eigen::VectorXf phi = n.apply(gallery[3], FeatureSet::kDynamicStatic);
  ASSERT_EQ(phi.size(), 5);
  EXPECT_NEAR(phi[0], 3.0 / std::sqrt(3.5), 1e-6);
  EXPECT_NEAR(phi[1], 0.0, 1e-6);
  EXPECT_NEAR(phi[2], -3.0 / std::sqrt(3.5), 1e-6);
  EXPECT_NEAR(phi[3], 3.0 / std::sqrt(3.5), 1e-6);
  EXPECT_EQ(n.apply(gallery[3], FeatureSet::kDynamic).size(), 2);
}

// One subject's poses share r exactly (eq 5.13): no spread, sigma 1, not a rounding residue.
TEST(FeatureNormalization, ConstantComponentsKeepSigmaOne) {
  std::vector<GaitFeatures> gallery;
  for (int n = 0; n < 40; ++n)
    gallery.push_back({Eigen::VectorXd::Constant(22, 0.01 * n),
                       (Eigen::VectorXd::LinSpaced(12, 0.093, 0.563).array() + 1.0 / 3).matrix()});
  const FeatureNormalization n = FeatureNormalization::fit(gallery);
  EXPECT_EQ(n.sigma_static, Eigen::VectorXd::Ones(12));
  EXPECT_NEAR(n.sigma_dynamic[0], 0.01 * std::sqrt((40.0 * 40.0 - 1) / 12), 1e-12);
}

// Adding poses and taking them away again gives the statistics of the poses that stay.
TEST(FeatureMoments, RemovalLeavesTheStatisticsOfTheRest) {
  std::vector<GaitFeatures> kept, removed;
  for (int n = 0; n < 30; ++n) {
    GaitFeatures f{Eigen::VectorXd::Constant(3, std::sin(n)), Eigen::VectorXd::Constant(2, 0.4)};
    f.statics[1] += 0.01 * std::cos(3 * n);
    (n % 3 == 0 ? removed : kept).push_back(f);
  }
  FeatureMoments moments;
  for (int n = 0; n < 30; ++n) moments.add(n % 3 == 0 ? removed[n / 3] : kept[n - n / 3 - 1]);
  for (const GaitFeatures& f : removed) moments.add(f, -1);
  const FeatureNormalization incremental = moments.normalization(),
                             direct = FeatureNormalization::fit(kept);
  EXPECT_LT((incremental.mean_dynamic - direct.mean_dynamic).norm(), 1e-14);
  EXPECT_LT((incremental.sigma_dynamic - direct.sigma_dynamic).norm(), 1e-12);
  EXPECT_LT((incremental.sigma_static - direct.sigma_static).norm(), 1e-12);
  EXPECT_NE(direct.sigma_static[1], 1.0);
  for (const GaitFeatures& f : kept) moments.add(f, -1);
  EXPECT_THROW(moments.normalization(), std::invalid_argument);
}

TEST(FeatureNormalization, BadInputGivesClearErrors) {
  EXPECT_THROW(FeatureNormalization::fit({}), std::invalid_argument);
  const body_gait::BodyModel model = turnedModel(0);
  const FeatureNormalization n = FeatureNormalization::fit({gaitFeatures(model)});
  try {
    n.apply(gaitFeatures(model, View::kFrontal), FeatureSet::kDynamic);
    FAIL() << "a frontal probe against a 3D gallery must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("same view"), std::string::npos) << e.what();
  }
  EXPECT_THROW(FeatureNormalization::fit({gaitFeatures(model), gaitFeatures(model, View::kSide)}),
               std::invalid_argument);
}

}  // namespace
}  // namespace body_gait_id
