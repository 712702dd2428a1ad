// Gait features of thesis 5.7 and the 2D baselines of 5.8.4: what the matcher compares.
//
// 3D: the dynamic feature is the joint angles q (eq 5.2, 22-D), the static feature the segment
// lengths r (eq 5.3, 12-D). 2D (5.8.4): an orthographic virtual view of the model in its own
// body frame, so the heading does not matter: the frontal view projects onto the X_m-Y_m plane
// and every movable segment keeps one joint angle about Z_m (11-D, the neck is fixed), the side
// view projects onto Y_m-Z_m with one angle about X_m; the static feature is the 12 projected
// segment lengths.
#pragma once

#include <body_gait_model/kinematic_model.h>

#include <Eigen/Core>
#include <vector>

namespace body_gait_id {

enum class View { k3D, kFrontal, kSide };            // 5.8.4: orthographic virtual views
enum class FeatureSet { kDynamic, kDynamicStatic };  // 5.7: phi = [q'] or [q', r']

// q (22-D) / r (12-D) in 3D; 11 + 12 in a 2D view.
struct GaitFeatures {
  Eigen::VectorXd dynamic, statics;
};

// Dimensions of a view's features.
int dynamicSize(View view);
constexpr int kStaticSize = body_gait::kSegmentCount;

GaitFeatures gaitFeatures(const body_gait::BodyModel& model, View view = View::k3D);

// Eqs 5.14-5.15: per-component mean and standard deviation over the gallery (population SD,
// the thesis's 1/(MN)). A component that does not vary in the gallery (SD within 1e-6 of its
// mean's size, or below 1e-9) keeps sigma = 1 so it neither divides by zero nor weighs in.
struct FeatureNormalization {
  Eigen::VectorXd mean_dynamic, sigma_dynamic, mean_static, sigma_static;

  // Throws std::invalid_argument for an empty gallery or features of mixed sizes.
  static FeatureNormalization fit(const std::vector<GaitFeatures>& gallery);
  // phi = [q'] or [q', r'] (5.7). Throws std::invalid_argument when f's sizes differ from the
  // statistics' (a probe of another view than the gallery).
  Eigen::VectorXf apply(const GaitFeatures& f, FeatureSet set) const;
  // The same in double precision (the brute-force peer, exports).
  Eigen::VectorXd normalized(const GaitFeatures& f, FeatureSet set) const;
  // Length of apply()'s vector.
  int size(FeatureSet set) const;
};

// Running sums over a gallery (pose count, per-component sum and sum of squares), from which
// eqs 5.14-5.15's mean and SD follow: the gallery database keeps them so that an enrolment or a
// removal updates the statistics from that subject's poses alone. fit() uses them too.
struct FeatureMoments {
  double count = 0;
  Eigen::VectorXd sum_dynamic, sum_sq_dynamic, sum_static, sum_sq_static;

  // Adds a pose (weight 1) or takes one away (weight -1). Throws std::invalid_argument when
  // the sizes differ from the poses added before (mixed views).
  void add(const GaitFeatures& f, double weight = 1.0);
  // Throws std::invalid_argument when no pose is left.
  FeatureNormalization normalization() const;
};

}  // namespace body_gait_id
