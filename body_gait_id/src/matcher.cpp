// Exact nearest-neighbour matching (thesis eq 5.16) with a principal-axes ordered index; see
// matcher.h for the scheme.
#include <body_gait_id/matcher.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace body_gait_id {
namespace {

constexpr int kBlock = 8;  // floats summed between early-exit checks (one AVX register)

std::vector<GaitFeatures> featuresOf(const std::vector<GalleryPose>& gallery) {
  std::vector<GaitFeatures> features;
  features.reserve(gallery.size());
  for (const GalleryPose& pose : gallery) features.push_back(pose.features);
  return features;
}

// Squared distance of two padded rows, abandoned (returning a value > bound) once a block's
// partial sum exceeds bound. Strictly greater, so exact ties are finished and tie-broken.
inline float partialDistance(const float* a, const float* b, int stride, float bound) {
  float sum = 0;
  for (int start = 0; start < stride; start += kBlock) {
    float block = 0;
    for (int k = 0; k < kBlock; ++k) {
      const float d = a[start + k] - b[start + k];
      block += d * d;
    }
    sum += block;
    if (sum > bound) return sum;
  }
  return sum;
}

}  // namespace

Matcher::Matcher(std::vector<GalleryPose> gallery, FeatureSet set) : set_(set) {
  if (gallery.empty())
    throw std::invalid_argument("matcher: the gallery is empty; enrol at least one subject first");
  normalization_ = FeatureNormalization::fit(featuresOf(gallery));
  build(std::move(gallery));
}

Matcher::Matcher(std::vector<GalleryPose> gallery, FeatureSet set, FeatureNormalization stored)
    : set_(set), normalization_(std::move(stored)) {
  if (gallery.empty())
    throw std::invalid_argument("matcher: the gallery is empty; enrol at least one subject first");
  build(std::move(gallery));
}

void Matcher::build(std::vector<GalleryPose> gallery) {
  const std::size_t n = gallery.size();
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("matcher: more than 2^32 gallery poses");
  dimension_ = normalization_.size(set_);
  stride_ = (dimension_ + kBlock - 1) / kBlock * kBlock;

  // Normalized vectors (eqs 5.14-5.15), then their principal axes.
  Eigen::MatrixXf phi(dimension_, n);
  for (std::size_t i = 0; i < n; ++i) phi.col(i) = normalization_.apply(gallery[i].features, set_);
  centre_ = phi.rowwise().mean();
  phi.colwise() -= centre_;
  const Eigen::MatrixXd covariance = (phi * phi.transpose()).cast<double>() / double(n);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);
  // Eigen sorts eigenvalues ascending: reverse so the highest variance comes first, which makes
  // both the first-component ordering and the early exit of the partial distance most selective.
  axes_ = solver.eigenvectors().rowwise().reverse().cast<float>();
  const Eigen::MatrixXf rotated = axes_.transpose() * phi;

  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return rotated(0, a) < rotated(0, b) || (rotated(0, a) == rotated(0, b) && a < b);
  });

  std::unordered_map<std::int64_t, std::uint32_t> slots;
  rows_.assign(n * stride_, 0.0f);
  keys_.resize(n);
  ids_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t source = order[i];
    std::copy_n(rotated.col(source).data(), dimension_, rows_.data() + i * stride_);
    keys_[i] = rotated(0, source);
    const GalleryPose& pose = gallery[source];
    const auto slot = slots.emplace(pose.subject_id, std::uint32_t(slots.size())).first->second;
    ids_[i] = {pose.subject_id, pose.sequence, pose.frame, source, slot};
  }
  subject_count_ = slots.size();
}

std::vector<float> Matcher::project(const GaitFeatures& probe) const {
  const Eigen::VectorXf rotated = axes_.transpose() * (normalization_.apply(probe, set_) - centre_);
  std::vector<float> out(stride_, 0.0f);
  std::copy_n(rotated.data(), dimension_, out.data());
  return out;
}

Match Matcher::identify(const GaitFeatures& probe) const {
  const std::vector<float> query = project(probe);
  const float key = query[0];
  const std::size_t n = keys_.size();
  float best = std::numeric_limits<float>::infinity();
  std::size_t best_index = 0;
  const auto consider = [&](std::size_t i) {
    const float d = partialDistance(row(i), query.data(), stride_, best);
    if (d < best || (d == best && ids_[i].gallery_index < ids_[best_index].gallery_index)) {
      best = d;
      best_index = i;
    }
  };
  // Walk outward from the probe's place in the first-component order, always to the nearer
  // side; a side is done once its key gap squared alone exceeds the best squared distance.
  std::size_t up = std::lower_bound(keys_.begin(), keys_.end(), key) - keys_.begin();
  std::size_t down = up;  // candidates below: indices down-1, down-2, ...
  while (true) {
    const float gap_up = up < n ? keys_[up] - key : std::numeric_limits<float>::infinity();
    const float gap_down =
        down > 0 ? key - keys_[down - 1] : std::numeric_limits<float>::infinity();
    const bool go_up = gap_up <= gap_down;
    const float gap = go_up ? gap_up : gap_down;
    if (!(gap * gap <= best)) break;  // also ends when both sides are exhausted (inf)
    consider(go_up ? up++ : --down);
  }
  const PoseId& id = ids_[best_index];
  return {id.subject_id, id.sequence, id.frame, std::sqrt(double(best))};
}

std::vector<Match> Matcher::rankSubjects(const GaitFeatures& probe) const {
  const std::vector<float> query = project(probe);
  std::vector<float> best(subject_count_, std::numeric_limits<float>::infinity());
  std::vector<std::size_t> best_index(subject_count_, 0);
  for (std::size_t i = 0; i < keys_.size(); ++i) {
    const std::uint32_t slot = ids_[i].subject_slot;
    const float d = partialDistance(row(i), query.data(), stride_, best[slot]);
    if (d < best[slot] ||
        (d == best[slot] && ids_[i].gallery_index < ids_[best_index[slot]].gallery_index)) {
      best[slot] = d;
      best_index[slot] = i;
    }
  }
  std::vector<Match> matches;
  matches.reserve(subject_count_);
  for (std::size_t slot = 0; slot < subject_count_; ++slot) {
    const PoseId& id = ids_[best_index[slot]];
    matches.push_back({id.subject_id, id.sequence, id.frame, std::sqrt(double(best[slot]))});
  }
  std::stable_sort(matches.begin(), matches.end(),
                   [](const Match& a, const Match& b) { return a.score < b.score; });
  return matches;
}

BruteForceMatcher::BruteForceMatcher(const std::vector<GalleryPose>& gallery, FeatureSet set,
                                     FeatureNormalization normalization)
    : set_(set), normalization_(std::move(normalization)) {
  if (gallery.empty())
    throw std::invalid_argument("matcher: the gallery is empty; enrol at least one subject first");
  phi_.resize(normalization_.size(set_), gallery.size());
  ids_.reserve(gallery.size());
  for (std::size_t i = 0; i < gallery.size(); ++i) {
    phi_.col(i) = normalization_.normalized(gallery[i].features, set_);
    ids_.push_back({gallery[i].subject_id, gallery[i].sequence, gallery[i].frame, {}});
  }
}

Match BruteForceMatcher::identify(const GaitFeatures& probe) const {
  const Eigen::VectorXd query = normalization_.normalized(probe, set_);
  Eigen::Index best_index = 0;
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < phi_.cols(); ++i) {
    const double d = (phi_.col(i) - query).squaredNorm();
    if (d < best) {
      best = d;
      best_index = i;
    }
  }
  const GalleryPose& id = ids_[best_index];
  return {id.subject_id, id.sequence, id.frame, std::sqrt(best)};
}

}  // namespace body_gait_id
