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

enum class View { k3D, kFrontal, kSide };  // 5.8.4: orthographic virtual views
// 5.7: phi = [q'] or [q', r']; beyond the thesis, [q', r', b'] with the body-shape measures b
// (bodyShapeFeatures), 3D only. The other subsets (static r alone, shape alone, ...) show how
// much of an identification is gait and how much body size (evaluate_gait_id's decomposition
// rows). Blocks always in the order q, r, b.
enum class FeatureSet {
  kDynamic,
  kDynamicStatic,
  kDynamicStaticShape,
  kStatic,
  kShape,
  kStaticShape,
  kDynamicShape
};
bool hasDynamic(FeatureSet set);
bool hasStatic(FeatureSet set);
bool hasShape(FeatureSet set);

// q (22-D) / r (12-D) in 3D; 11 + 12 in a 2D view. shape: bodyShapeFeatures in 3D, empty in the
// 2D views (a silhouette does not give girths).
struct GaitFeatures {
  Eigen::VectorXd dynamic, statics, shape;
};

// Dimensions of a view's features.
int dynamicSize(View view);
constexpr int kStaticSize = body_gait_model::kSegmentCount;

// Body-shape measures of a fitted model (beyond the thesis's r), the fitter's BodyShape without
// its duplicates: [0] the standing height sole to head top (mean leg + lower torso - hip rise +
// upper torso + neck + head: a chain whose shared joints' errors cancel, so it is steadier
// than its lengths), [1] shoulder and [2] hip half widths, [3..23] the distinct segment radii
// (upper torso proximal and distal, lower torso distal, neck, head, each limb's proximal and
// distal). Why: cross-walk, the radii and the height vary 3-10x less between a person's walks
// than between people, the limbs' lengths only 1.5-2.5x
// (`evaluate_gait_id --measure-noise`).
constexpr int kShapeSize = 24;
Eigen::VectorXd bodyShapeFeatures(const body_gait_model::BodyModel& model);

GaitFeatures gaitFeatures(const body_gait_model::BodyModel& model, View view = View::k3D);

// Eqs 5.14-5.15: per-component mean and standard deviation over the gallery (population SD,
// the thesis's 1/(MN)). A component that does not vary in the gallery (SD within 1e-6 of its
// mean's size, or below 1e-9) keeps sigma = 1 so it neither divides by zero nor weighs in.
struct FeatureNormalization {
  Eigen::VectorXd mean_dynamic, sigma_dynamic, mean_static, sigma_static;
  // Shape statistics: empty when the gallery's features have no shape (2D views).
  Eigen::VectorXd mean_shape, sigma_shape;
  // Optional weight of each normalized component (size(set) of the set in use; empty = 1, eq
  // 5.16 as written). noiseWeights() sets them to between / within-subject SD.
  Eigen::VectorXd weights;

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
// removal updates the statistics from that subject's poses alone. fit() uses them too. The
// shape sums are empty when the poses have no shape features (2D views); then so are the
// normalization's mean_shape / sigma_shape.
struct FeatureMoments {
  double count = 0;
  Eigen::VectorXd sum_dynamic, sum_sq_dynamic, sum_static, sum_sq_static, sum_shape, sum_sq_shape;

  // Adds a pose (weight 1) or takes one away (weight -1). Throws std::invalid_argument when
  // the sizes differ from the poses added before (mixed views, or shape features on some
  // poses only).
  void add(const GaitFeatures& f, double weight = 1.0);
  // Throws std::invalid_argument when no pose is left.
  FeatureNormalization normalization() const;
};

// Within-subject SD of each raw feature component between two walks of one person (fit noise
// plus walk-to-walk variation), learned from a development population with two walks each,
// not from the gallery's people: a gallery holds one walk per person, so it cannot show this
// scatter.
struct FeatureNoise {
  Eigen::VectorXd dynamic, statics, shape;
};

// Weights for FeatureNormalization::weights: sigma_i / noise_i per component of the set, i.e.
// each normalized component (eqs 5.14-5.15) weighted by its between-subject / within-subject
// SD ratio. Eq 5.16's L2 then measures the probe's distance in units of each component's
// noise (a Mahalanobis distance with a diagonal within-subject covariance: the nearest
// neighbour is the most likely subject for Gaussian noise). A noise below 1e-9 is taken as
// 1e-9; a noise of 0 (the learning walks never moved the component: an axis the fitter held)
// gives weight 0, the component left out. Throws std::invalid_argument when the sizes differ
// from the statistics'.
Eigen::VectorXd noiseWeights(const FeatureNormalization& normalization, const FeatureNoise& noise,
                             FeatureSet set);

}  // namespace body_gait_id
