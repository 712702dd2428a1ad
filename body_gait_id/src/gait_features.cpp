// Gait features (thesis 5.7) and the orthographic virtual views of 5.8.4.
#include <body_gait_id/gait_features.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace body_gait_id {
namespace {

using body_gait_model::BodyModel;
using body_gait_model::kSegmentCount;
using body_gait_model::PosedModel;

constexpr int kMovableSegments = kSegmentCount - 1;  // the neck has no joint (5.4)

// The 2D joint angle of a segment in a view: the signed angle, about the view's normal, from
// the segment's rest direction (its parent's +-Y axis, where a zero joint would point it) to
// its axis, both projected onto the view plane. For a planar pose (all joints turning about the
// normal) this is exactly the 3D joint angle about that axis.
double projectedJointAngle(const Eigen::Vector3d& rest, const Eigen::Vector3d& axis, int normal) {
  Eigen::Vector3d a = rest, b = axis;
  a[normal] = 0;
  b[normal] = 0;
  return std::atan2(a.cross(b)[normal], a.dot(b));
}

GaitFeatures viewFeatures(const BodyModel& model, int normal) {
  const PosedModel posed = body_gait_model::forwardKinematics(model);
  // Body frame (model axes X_m, Y_m, Z_m): the view does not depend on where the subject stands
  // or which way they face.
  const Eigen::Matrix3d world_to_body = posed.whole_body.linear().transpose();
  GaitFeatures f;
  f.dynamic.resize(kMovableSegments);
  f.statics.resize(kSegmentCount);
  int angle = 0;
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    const body_gait_model::SegmentInfo& info = body_gait_model::segmentInfo(segment);
    const body_gait_model::PosedSegment& s = posed.segments[segment];
    Eigen::Vector3d axis = world_to_body * (s.distal - s.proximal);
    axis[normal] = 0;
    f.statics[segment] = axis.norm();
    if (info.fixed) continue;
    const Eigen::Matrix3d parent = info.parent == body_gait_model::kWholeBody
                                       ? posed.whole_body.linear()
                                       : posed.segments[info.parent].frame.linear();
    const Eigen::Vector3d rest = world_to_body * parent.col(1) * (info.points_up ? 1.0 : -1.0);
    f.dynamic[angle++] = projectedJointAngle(rest, axis, normal);
  }
  return f;
}

void checkSizes(const char* what, const Eigen::VectorXd& value, const Eigen::VectorXd& expected) {
  if (value.size() != expected.size())
    throw std::invalid_argument(
        std::string("gait features: ") + what + " has " + std::to_string(value.size()) +
        " components but the normalization " + std::to_string(expected.size()) +
        "; probe and gallery must use the same view (3D, frontal or side)");
}

}  // namespace

int dynamicSize(View view) { return view == View::k3D ? 2 * kMovableSegments : kMovableSegments; }

GaitFeatures gaitFeatures(const BodyModel& model, View view) {
  switch (view) {
    case View::kFrontal:
      return viewFeatures(model, 2);  // X_m-Y_m plane, angles about Z_m
    case View::kSide:
      return viewFeatures(model, 0);  // Y_m-Z_m plane, angles about X_m
    case View::k3D:
      break;
  }
  return {model.q, model.r, bodyShapeFeatures(model)};  // eqs 5.2, 5.3; shape beyond the thesis
}

Eigen::VectorXd bodyShapeFeatures(const BodyModel& model) {
  using namespace body_gait_model;
  const SegmentLengths& r = model.r;
  const BodyShape& shape = model.shape;
  Eigen::VectorXd b(kShapeSize);
  const double leg =
      (r[kRightUpperLeg] + r[kRightLowerLeg] + r[kLeftUpperLeg] + r[kLeftLowerLeg]) / 2;
  b[0] = leg + r[kLowerTorso] - shape.hip_rise + r[kUpperTorso] + r[kNeck] + r[kHead];
  b[1] = shape.shoulder_half_width;
  b[2] = shape.hip_half_width;
  int k = 3;
  // The lower torso's proximal radius is the upper torso's, neck and head are cylinders.
  b[k++] = shape.proximal_radius[kUpperTorso];
  b[k++] = shape.distal_radius[kUpperTorso];
  b[k++] = shape.distal_radius[kLowerTorso];
  b[k++] = shape.proximal_radius[kNeck];
  b[k++] = shape.proximal_radius[kHead];
  for (int s : {kRightUpperArm, kRightLowerArm, kLeftUpperArm, kLeftLowerArm, kRightUpperLeg,
                kRightLowerLeg, kLeftUpperLeg, kLeftLowerLeg}) {
    b[k++] = shape.proximal_radius[s];
    b[k++] = shape.distal_radius[s];
  }
  return b;
}

FeatureNormalization FeatureNormalization::fit(const std::vector<GaitFeatures>& gallery) {
  if (gallery.empty())
    throw std::invalid_argument(
        "feature normalization: the gallery is empty; enrol at least one subject first");
  FeatureMoments moments;
  for (const GaitFeatures& f : gallery) moments.add(f);
  return moments.normalization();
}

void FeatureMoments::add(const GaitFeatures& f, double weight) {
  if (count == 0 && sum_dynamic.size() == 0) {
    sum_dynamic = sum_sq_dynamic = Eigen::VectorXd::Zero(f.dynamic.size());
    sum_static = sum_sq_static = Eigen::VectorXd::Zero(f.statics.size());
    sum_shape = sum_sq_shape = Eigen::VectorXd::Zero(f.shape.size());
  }
  if (f.dynamic.size() != sum_dynamic.size() || f.statics.size() != sum_static.size() ||
      f.shape.size() != sum_shape.size())
    throw std::invalid_argument(
        "feature normalization: gallery features of different sizes (mixed views, or shape "
        "features on some poses only?)");
  count += weight;
  sum_dynamic += weight * f.dynamic;
  sum_sq_dynamic += weight * f.dynamic.cwiseAbs2();
  sum_static += weight * f.statics;
  sum_sq_static += weight * f.statics.cwiseAbs2();
  sum_shape += weight * f.shape;
  sum_sq_shape += weight * f.shape.cwiseAbs2();
}

FeatureNormalization FeatureMoments::normalization() const {
  if (!(count > 0.5))
    throw std::invalid_argument(
        "feature normalization: the gallery is empty; enrol at least one subject first");
  // Var = E[x^2] - E[x]^2: gait features are O(1) with SDs >= ~1 % of their means, so the
  // cancellation costs at most ~1e-12 relative in double. It also leaves ~1e-17 where a
  // component does not vary at all (r of a single subject, eq 5.13), so an SD within 1e-6 of
  // the mean's size counts as none: sigma = 1.
  const auto sigma = [this](const Eigen::VectorXd& sum, const Eigen::VectorXd& sum_sq) {
    const Eigen::VectorXd mean = sum / count;
    const Eigen::VectorXd var = sum_sq / count - mean.cwiseAbs2();
    Eigen::VectorXd s(var.size());
    for (Eigen::Index i = 0; i < s.size(); ++i)
      s[i] = var[i] > 1e-12 * mean[i] * mean[i] + 1e-18 ? std::sqrt(var[i]) : 1.0;
    return s;
  };
  FeatureNormalization n;
  n.mean_dynamic = sum_dynamic / count;  // mu_q, mu_r of eqs 5.14-5.15
  n.mean_static = sum_static / count;
  n.sigma_dynamic = sigma(sum_dynamic, sum_sq_dynamic);  // diagonal of the covariance (E, d)
  n.sigma_static = sigma(sum_static, sum_sq_static);
  if (sum_shape.size() > 0) {
    n.mean_shape = sum_shape / count;
    n.sigma_shape = sigma(sum_shape, sum_sq_shape);
  }
  return n;
}

bool hasDynamic(FeatureSet set) {
  return set == FeatureSet::kDynamic || set == FeatureSet::kDynamicStatic ||
         set == FeatureSet::kDynamicStaticShape || set == FeatureSet::kDynamicShape;
}
bool hasStatic(FeatureSet set) {
  return set == FeatureSet::kDynamicStatic || set == FeatureSet::kDynamicStaticShape ||
         set == FeatureSet::kStatic || set == FeatureSet::kStaticShape;
}
bool hasShape(FeatureSet set) {
  return set == FeatureSet::kDynamicStaticShape || set == FeatureSet::kShape ||
         set == FeatureSet::kStaticShape || set == FeatureSet::kDynamicShape;
}

int FeatureNormalization::size(FeatureSet set) const {
  Eigen::Index n = 0;
  if (hasDynamic(set)) n += mean_dynamic.size();
  if (hasStatic(set)) n += mean_static.size();
  if (hasShape(set)) n += kShapeSize;
  return static_cast<int>(n);
}

Eigen::VectorXd FeatureNormalization::normalized(const GaitFeatures& f, FeatureSet set) const {
  checkSizes("the dynamic feature", f.dynamic, mean_dynamic);
  Eigen::VectorXd phi(size(set));
  Eigen::Index at = 0;
  if (hasDynamic(set)) {
    phi.segment(at, mean_dynamic.size()) = (f.dynamic - mean_dynamic).cwiseQuotient(sigma_dynamic);
    at += mean_dynamic.size();
  }
  if (hasStatic(set)) {
    checkSizes("the static feature", f.statics, mean_static);
    phi.segment(at, mean_static.size()) = (f.statics - mean_static).cwiseQuotient(sigma_static);
    at += mean_static.size();
  }
  if (hasShape(set)) {
    if (mean_shape.size() != kShapeSize)
      throw std::invalid_argument(
          "gait features: the feature sets with body shape (dynamic_static_shape, shape, "
          "static_shape, dynamic_shape) need 3D features with body shape in the gallery; use "
          "dynamic or dynamic_static with the 2D views");
    checkSizes("the shape feature", f.shape, mean_shape);
    phi.segment(at, kShapeSize) = (f.shape - mean_shape).cwiseQuotient(sigma_shape);
  }
  if (weights.size() > 0) {
    if (weights.size() != phi.size())
      throw std::invalid_argument("gait features: " + std::to_string(weights.size()) +
                                  " component weights for " + std::to_string(phi.size()) +
                                  " components; fit the weights for the feature set in use");
    phi = phi.cwiseProduct(weights);
  }
  return phi;
}

Eigen::VectorXf FeatureNormalization::apply(const GaitFeatures& f, FeatureSet set) const {
  return normalized(f, set).cast<float>();
}

Eigen::VectorXd noiseWeights(const FeatureNormalization& normalization, const FeatureNoise& noise,
                             FeatureSet set) {
  const auto ratio = [](const char* what, const Eigen::VectorXd& sigma, const Eigen::VectorXd& sd) {
    if (sd.size() != sigma.size())
      throw std::invalid_argument(std::string("noise weights: the ") + what + " noise has " +
                                  std::to_string(sd.size()) + " components, the statistics " +
                                  std::to_string(sigma.size()) +
                                  "; learn the noise on the same view and feature set");
    // A zero noise: the learning walks never moved the component (an axis the fitter held),
    // so it has no scale to be measured in; left out rather than weighed without bound.
    return Eigen::VectorXd(
        (sd.array() > 0).select(sigma.array() / sd.array().max(1e-9), 0.0).matrix());
  };
  Eigen::VectorXd w(normalization.size(set));
  Eigen::Index at = 0;
  if (hasDynamic(set)) {
    const Eigen::Index n = normalization.sigma_dynamic.size();
    w.segment(at, n) = ratio("dynamic", normalization.sigma_dynamic, noise.dynamic);
    at += n;
  }
  if (hasStatic(set)) {
    const Eigen::Index n = normalization.sigma_static.size();
    w.segment(at, n) = ratio("static", normalization.sigma_static, noise.statics);
    at += n;
  }
  if (hasShape(set))
    w.segment(at, kShapeSize) = ratio("shape", normalization.sigma_shape, noise.shape);
  return w;
}

}  // namespace body_gait_id
