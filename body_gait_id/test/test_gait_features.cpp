// Gait features (thesis 5.7), the 2D virtual views (5.8.4) on hand-made poses with known
// projected angles and lengths, and the normalization of eqs 5.14-5.15.
#include <body_gait_id/gait_features.h>
#include <gtest/gtest.h>

#include <cmath>

namespace body_gait_id {
namespace {

using body_gait_model::BodyModel;

// Index of a movable segment's angle in a 2D dynamic feature (the neck is left out).
int viewIndex(int segment) { return body_gait_model::jointAngleIndex(segment) / 2; }

BodyModel turnedModel(double heading) {
  BodyModel model = body_gait_model::standingModel(1.75);
  model.p << 0.3, 0.9, -0.2, 0, heading, 0;
  return model;
}

TEST(GaitFeatures, ThreeDIsJointAnglesAndLengths) {
  BodyModel model = turnedModel(0.4);
  model.setJointAngles(body_gait_model::kRightUpperLeg, 0.3, -0.1);
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
    model.setJointAngles(body_gait_model::kRightUpperArm, 0, -0.3);
    model.setJointAngles(body_gait_model::kRightLowerArm, 0, -0.2);
    model.setJointAngles(body_gait_model::kLeftUpperLeg, 0, 0.25);
    const GaitFeatures frontal = gaitFeatures(model, View::kFrontal);
    const GaitFeatures side = gaitFeatures(model, View::kSide);
    ASSERT_EQ(frontal.dynamic.size(), 11);
    ASSERT_EQ(frontal.statics.size(), 12);
    EXPECT_NEAR(frontal.dynamic[viewIndex(body_gait_model::kRightUpperArm)], -0.3, 1e-12);
    EXPECT_NEAR(frontal.dynamic[viewIndex(body_gait_model::kRightLowerArm)], -0.2, 1e-12);
    EXPECT_NEAR(frontal.dynamic[viewIndex(body_gait_model::kLeftUpperLeg)], 0.25, 1e-12);
    EXPECT_NEAR(frontal.dynamic[viewIndex(body_gait_model::kLeftLowerLeg)], 0.0, 1e-12);
    EXPECT_NEAR(side.dynamic.cwiseAbs().maxCoeff(), 0.0, 1e-12);
    // Lengths: whole in the frontal plane; the side view sees their vertical part only.
    const double arm = model.r[body_gait_model::kRightUpperArm];
    EXPECT_NEAR(frontal.statics[body_gait_model::kRightUpperArm], arm, 1e-12);
    EXPECT_NEAR(side.statics[body_gait_model::kRightUpperArm], arm * std::cos(0.3), 1e-12);
    // The forearm hangs at 0.5 rad from the vertical (0.3 + 0.2).
    const double forearm = model.r[body_gait_model::kRightLowerArm];
    EXPECT_NEAR(side.statics[body_gait_model::kRightLowerArm], forearm * std::cos(0.5), 1e-12);
  }
}

// Sagittal swings (theta_x: hip, knee, torso lean) are the side view's angles.
TEST(GaitFeatures, SideViewAnglesAreSagittalJointAngles) {
  for (double heading : {0.0, 0.7, 3.0}) {
    BodyModel model = turnedModel(heading);
    model.setJointAngles(body_gait_model::kUpperTorso, 0.1, 0);
    model.setJointAngles(body_gait_model::kRightUpperLeg, -0.4, 0);
    model.setJointAngles(body_gait_model::kRightLowerLeg, 0.6, 0);
    model.setJointAngles(body_gait_model::kLeftUpperArm, 0.35, 0);
    const GaitFeatures side = gaitFeatures(model, View::kSide);
    const GaitFeatures frontal = gaitFeatures(model, View::kFrontal);
    EXPECT_NEAR(side.dynamic[viewIndex(body_gait_model::kUpperTorso)], 0.1, 1e-12);
    EXPECT_NEAR(side.dynamic[viewIndex(body_gait_model::kRightUpperLeg)], -0.4, 1e-12);
    EXPECT_NEAR(side.dynamic[viewIndex(body_gait_model::kRightLowerLeg)], 0.6, 1e-12);
    // The arm hangs from the leaning upper torso: its joint angle, not its absolute one.
    EXPECT_NEAR(side.dynamic[viewIndex(body_gait_model::kLeftUpperArm)], 0.35, 1e-12);
    EXPECT_NEAR(frontal.dynamic.cwiseAbs().maxCoeff(), 0.0, 1e-12);
    // The shank's axis is 0.2 rad off the vertical: the frontal view sees cos(0.2) of it.
    const double shank = model.r[body_gait_model::kRightLowerLeg];
    EXPECT_NEAR(frontal.statics[body_gait_model::kRightLowerLeg], shank * std::cos(0.2), 1e-12);
    EXPECT_NEAR(side.statics[body_gait_model::kRightLowerLeg], shank, 1e-12);
  }
}

TEST(GaitFeatures, ViewsDoNotDependOnHeadingOrPlace) {
  BodyModel a = turnedModel(0.0);
  a.setJointAngles(body_gait_model::kRightUpperLeg, -0.3, 0.1);
  a.setJointAngles(body_gait_model::kLeftLowerArm, 0.4, -0.2);
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
                       (Eigen::VectorXd::LinSpaced(12, 0.093, 0.563).array() + 1.0 / 3).matrix(),
                       {}});
  const FeatureNormalization n = FeatureNormalization::fit(gallery);
  EXPECT_EQ(n.sigma_static, Eigen::VectorXd::Ones(12));
  EXPECT_NEAR(n.sigma_dynamic[0], 0.01 * std::sqrt((40.0 * 40.0 - 1) / 12), 1e-12);
}

// Adding poses and taking them away again gives the statistics of the poses that stay, the
// shape's too (checked against a two-pass mean and population SD).
TEST(FeatureMoments, RemovalLeavesTheStatisticsOfTheRest) {
  std::vector<GaitFeatures> kept, removed;
  for (int n = 0; n < 30; ++n) {
    GaitFeatures f{Eigen::VectorXd::Constant(3, std::sin(n)), Eigen::VectorXd::Constant(2, 0.4),
                   Eigen::VectorXd::Constant(2, 0.05)};
    f.statics[1] += 0.01 * std::cos(3 * n);
    f.shape[0] = 1.7 + 0.05 * std::sin(5 * n);
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
  double mean = 0, var = 0;
  for (const GaitFeatures& f : kept) mean += f.shape[0] / kept.size();
  for (const GaitFeatures& f : kept) var += (f.shape[0] - mean) * (f.shape[0] - mean) / kept.size();
  ASSERT_EQ(incremental.mean_shape.size(), 2);
  EXPECT_NEAR(incremental.mean_shape[0], mean, 1e-14);
  EXPECT_NEAR(incremental.sigma_shape[0], std::sqrt(var), 1e-10);
  EXPECT_EQ(incremental.sigma_shape[1], 1.0);  // constant: no spread
  // A pose without shape features among poses with them is refused (mixed views).
  EXPECT_THROW(moments.add({Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(2), {}}),
               std::invalid_argument);
  for (const GaitFeatures& f : kept) moments.add(f, -1);
  EXPECT_THROW(moments.normalization(), std::invalid_argument);
}

TEST(FeatureNormalization, BadInputGivesClearErrors) {
  EXPECT_THROW(FeatureNormalization::fit({}), std::invalid_argument);
  const body_gait_model::BodyModel model = turnedModel(0);
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

// The standing height of the shape features is the model's own sole-to-head-top extent when it
// stands upright, whatever its lengths and hip offset.
TEST(GaitFeatures, ShapeHeightIsTheUprightModelsExtent) {
  for (double stature : {1.55, 1.75, 1.95}) {
    BodyModel model = body_gait_model::standingModel(stature);
    model.r[body_gait_model::kLeftLowerLeg] += 0.02;  // legs of unequal length: their mean counts
    model.r[body_gait_model::kRightLowerLeg] -= 0.02;
    model.shape.hip_rise += 0.01;
    const body_gait_model::PosedModel posed = body_gait_model::forwardKinematics(model);
    const double top = posed.segments[body_gait_model::kHead].distal.z();
    const double sole = (posed.segments[body_gait_model::kLeftLowerLeg].distal.z() +
                         posed.segments[body_gait_model::kRightLowerLeg].distal.z()) /
                        2;
    const Eigen::VectorXd b = bodyShapeFeatures(model);
    ASSERT_EQ(b.size(), kShapeSize);
    EXPECT_NEAR(b[0], top - sole, 1e-9) << stature;
    EXPECT_EQ(b[1], model.shape.shoulder_half_width);
    EXPECT_EQ(b[2], model.shape.hip_half_width);
    EXPECT_EQ(b[3], model.shape.proximal_radius[body_gait_model::kUpperTorso]);
    EXPECT_EQ(b[kShapeSize - 1], model.shape.distal_radius[body_gait_model::kLeftLowerLeg]);
    EXPECT_EQ(gaitFeatures(model).shape, b);
    EXPECT_EQ(gaitFeatures(model, View::kSide).shape.size(), 0);  // no girths in a silhouette
  }
}

// dynamic_static_shape = [q', r', b'], each block normalized by its own statistics (5.14-5.15).
TEST(GaitFeatures, ShapeSetAppendsNormalizedShape) {
  std::vector<GaitFeatures> gallery;
  for (int i = 0; i < 3; ++i) gallery.push_back(gaitFeatures(turnedModel(0.1 * i)));
  for (int i = 0; i < 3; ++i) gallery[i].shape[1] = 0.15 + 0.01 * i;  // shoulder half widths
  const FeatureNormalization n = FeatureNormalization::fit(gallery);
  ASSERT_EQ(n.size(FeatureSet::kDynamicStaticShape), 22 + 12 + kShapeSize);
  const Eigen::VectorXd phi = n.normalized(gallery[2], FeatureSet::kDynamicStaticShape);
  EXPECT_NEAR(phi[34 + 1], 0.01 / std::sqrt(2.0 / 3.0 * 1e-4), 1e-9);  // (x - mu) / sigma
  EXPECT_EQ(phi[34 + 2], 0.0);  // constant component: sigma 1, no weight
  // A 2D view's gallery has no shape: the set names its problem.
  std::vector<GaitFeatures> frontal{gaitFeatures(turnedModel(0.0), View::kFrontal)};
  const FeatureNormalization nf = FeatureNormalization::fit(frontal);
  try {
    nf.normalized(frontal[0], FeatureSet::kDynamicStaticShape);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("dynamic_static_shape"), std::string::npos) << e.what();
  }
}

// Statistics of two dynamic components and one static one, every mean 0.
FeatureNormalization zeroMeanNormalization(const Eigen::Vector2d& sigma_dynamic,
                                           double sigma_static) {
  FeatureNormalization n;
  n.mean_dynamic = Eigen::VectorXd::Zero(2);
  n.sigma_dynamic = sigma_dynamic;
  n.mean_static = Eigen::VectorXd::Zero(1);
  n.sigma_static = Eigen::VectorXd::Constant(1, sigma_static);
  return n;
}

// Weights sigma / noise: a difference of one noise SD in a component scores 1 whatever the
// component's spread between people.
TEST(GaitFeatures, NoiseWeightsMeasureInNoiseUnits) {
  FeatureNormalization n = zeroMeanNormalization(Eigen::Vector2d(2.0, 0.5), 0.1);
  FeatureNoise noise{Eigen::Vector2d(0.5, 0.5), Eigen::VectorXd::Constant(1, 0.01), {}};
  const Eigen::VectorXd w = noiseWeights(n, noise, FeatureSet::kDynamicStatic);
  ASSERT_EQ(w.size(), 3);
  EXPECT_DOUBLE_EQ(w[0], 4.0);
  EXPECT_DOUBLE_EQ(w[1], 1.0);
  EXPECT_DOUBLE_EQ(w[2], 10.0);
  n.weights = w;
  const GaitFeatures a{Eigen::Vector2d(0.5, 0.0), Eigen::VectorXd::Zero(1), {}};
  const GaitFeatures b{Eigen::Vector2d(0.0, 0.0), Eigen::VectorXd::Constant(1, 0.01), {}};
  const GaitFeatures origin{Eigen::Vector2d::Zero(), Eigen::VectorXd::Zero(1), {}};
  const Eigen::VectorXd o = n.normalized(origin, FeatureSet::kDynamicStatic);
  EXPECT_NEAR((n.normalized(a, FeatureSet::kDynamicStatic) - o).norm(), 1.0, 1e-12);
  EXPECT_NEAR((n.normalized(b, FeatureSet::kDynamicStatic) - o).norm(), 1.0, 1e-12);
  // Weights of another set, or noise of another size, are refused with the fix.
  EXPECT_THROW(n.normalized(a, FeatureSet::kDynamic), std::invalid_argument);
  EXPECT_THROW(
      noiseWeights(n, FeatureNoise{Eigen::VectorXd::Ones(3), {}, {}}, FeatureSet::kDynamic),
      std::invalid_argument);
}

// A component whose learned noise is 0 (the fitter held it on every learning walk) is left out:
// a fitter that frees the axis must not make it outweigh every other component.
TEST(GaitFeatures, ZeroNoiseLeavesTheComponentOut) {
  FeatureNormalization n = zeroMeanNormalization(Eigen::Vector2d(0.2, 0.2), 0.1);
  const FeatureNoise noise{Eigen::Vector2d(0.1, 0.0), Eigen::VectorXd::Constant(1, 1e-12), {}};
  n.weights = noiseWeights(n, noise, FeatureSet::kDynamicStatic);
  EXPECT_DOUBLE_EQ(n.weights[0], 2.0);
  EXPECT_DOUBLE_EQ(n.weights[1], 0.0);
  EXPECT_DOUBLE_EQ(n.weights[2], 0.1 / 1e-9);  // tiny but measured: floored, still weighed
  const GaitFeatures moved{Eigen::Vector2d(0.1, 0.3), Eigen::VectorXd::Zero(1), {}};
  const GaitFeatures origin{Eigen::Vector2d::Zero(), Eigen::VectorXd::Zero(1), {}};
  EXPECT_NEAR((n.normalized(moved, FeatureSet::kDynamicStatic) -
               n.normalized(origin, FeatureSet::kDynamicStatic))
                  .norm(),
              1.0, 1e-12);
}

}  // namespace
}  // namespace body_gait_id
