// Exact nearest-neighbour matching (thesis eq 5.16) with a k-d tree over the principal axes;
// see matcher.h for the scheme.
#include <body_gait_id/matcher.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace body_gait_id {
namespace {

constexpr int kBlock = 8;      // floats summed between early-exit checks (one AVX register)
constexpr int kLeafRows = 64;  // rows per k-d tree leaf (at most; 16-64 measured alike)
// A cell is skipped only if its box distance exceeds the best by this factor: the box
// distance is accumulated in float32 too, and must not drop an exact tie by a rounding.
constexpr float kPruneSlack = 1.0f + 1e-5f;

// A NaN would poison the statistics and compare false in every distance.
void checkFinite(const std::vector<GalleryPose>& gallery) {
  if (gallery.empty())
    throw std::invalid_argument("matcher: the gallery is empty; enrol at least one subject first");
  for (std::size_t i = 0; i < gallery.size(); ++i)
    if (!gallery[i].features.dynamic.allFinite() || !gallery[i].features.statics.allFinite())
      throw std::invalid_argument("matcher: gallery pose " + std::to_string(i) + " (subject " +
                                  std::to_string(gallery[i].subject_id) + ", frame " +
                                  std::to_string(gallery[i].frame) +
                                  ") has non-finite features (NaN or inf): enrol the subject "
                                  "again from valid fits");
}

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
  checkFinite(gallery);
  normalization_ = FeatureNormalization::fit(featuresOf(gallery));
  build(std::move(gallery));
}

Matcher::Matcher(std::vector<GalleryPose> gallery, FeatureSet set, FeatureNormalization stored)
    : set_(set), normalization_(std::move(stored)) {
  checkFinite(gallery);
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
  // the early exit of the partial distance most selective.
  axes_ = solver.eigenvectors().rowwise().reverse().cast<float>();
  const Eigen::MatrixXf rotated = axes_.transpose() * phi;

  // k-d tree: split a range of rows at the median of its widest axis until leaves are small.
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  nodes_.clear();
  nodes_.reserve(2 * n / kLeafRows + 2);
  const std::function<int(std::uint32_t, std::uint32_t)> build = [&](std::uint32_t begin,
                                                                     std::uint32_t end) {
    const int index = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    if (end - begin <= std::uint32_t(kLeafRows)) {
      nodes_[index].begin = begin;
      nodes_[index].end = end;
      return index;
    }
    Eigen::VectorXf low = rotated.col(order[begin]), high = low;
    for (std::uint32_t i = begin + 1; i < end; ++i) {
      low = low.cwiseMin(rotated.col(order[i]));
      high = high.cwiseMax(rotated.col(order[i]));
    }
    int axis = 0;
    (high - low).maxCoeff(&axis);
    const std::uint32_t middle = begin + (end - begin) / 2;
    std::nth_element(
        order.begin() + begin, order.begin() + middle, order.begin() + end,
        [&](std::uint32_t a, std::uint32_t b) { return rotated(axis, a) < rotated(axis, b); });
    const float split = rotated(axis, order[middle]);
    const int left = build(begin, middle);
    const int right = build(middle, end);
    nodes_[index].axis = axis;
    nodes_[index].split = split;
    nodes_[index].left = left;
    nodes_[index].right = right;
    return index;
  };
  build(0, static_cast<std::uint32_t>(n));

  std::unordered_map<std::int64_t, std::uint32_t> slots;
  rows_.assign(n * stride_, 0.0f);
  ids_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t source = order[i];
    std::copy_n(rotated.col(source).data(), dimension_, rows_.data() + i * stride_);
    const GalleryPose& pose = gallery[source];
    const auto slot = slots.emplace(pose.subject_id, std::uint32_t(slots.size())).first->second;
    ids_[i] = {pose.subject_id, pose.sequence, pose.frame, source, slot};
  }
  subject_count_ = slots.size();
}

std::vector<float> Matcher::project(const GaitFeatures& probe) const {
  const Eigen::VectorXf phi = normalization_.apply(probe, set_);
  // A NaN would compare false everywhere and return an arbitrary pose.
  if (!phi.allFinite())
    throw std::invalid_argument(
        "matcher: the probe's features are not finite (NaN or inf): identify a valid fit");
  const Eigen::VectorXf rotated = axes_.transpose() * (phi - centre_);
  std::vector<float> out(stride_, 0.0f);
  std::copy_n(rotated.data(), dimension_, out.data());
  return out;
}

struct Matcher::Search {
  const float* query;
  std::vector<float> offset;  // per axis: distance from the query to the current cell's box
  float best = std::numeric_limits<float>::infinity();
  std::size_t best_index = 0;
};

void Matcher::search(int index, float cell_distance, Search& s) const {
  const Node& node = nodes_[index];
  if (node.axis < 0) {
    for (std::uint32_t i = node.begin; i < node.end; ++i) {
      const float d = partialDistance(row(i), s.query, stride_, s.best);
      if (d < s.best || (d == s.best && ids_[i].gallery_index < ids_[s.best_index].gallery_index)) {
        s.best = d;
        s.best_index = i;
      }
    }
    return;
  }
  const float gap = s.query[node.axis] - node.split;
  const int near = gap < 0 ? node.left : node.right;
  const int far = gap < 0 ? node.right : node.left;
  search(near, cell_distance, s);
  // The far cell lies beyond the split plane: its box is |gap| away along this axis.
  const float previous = s.offset[node.axis];
  const float far_distance = cell_distance - previous * previous + gap * gap;
  if (far_distance <= s.best * kPruneSlack) {
    s.offset[node.axis] = std::abs(gap);
    search(far, far_distance, s);
    s.offset[node.axis] = previous;
  }
}

Match Matcher::identify(const GaitFeatures& probe) const {
  const std::vector<float> query = project(probe);
  Search s{query.data(), std::vector<float>(stride_, 0.0f)};
  search(0, 0.0f, s);
  const PoseId& id = ids_[s.best_index];
  return {id.subject_id, id.sequence, id.frame, std::sqrt(double(s.best))};
}

std::vector<Match> Matcher::rankSubjects(const GaitFeatures& probe) const {
  const std::vector<float> query = project(probe);
  // Every subject needs its own best, so every row is measured: whole rows without the early
  // exit, then branch-free minima per subject, then the rows that reach them (few, so that
  // branch is predictable). The early-exit scan was 3x slower here: its branches, and the
  // subject's best, are unpredictable row to row.
  const std::size_t n = ids_.size();
  std::vector<float> distance(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float* r = row(i);
    float lanes[kBlock] = {};
    for (int start = 0; start < stride_; start += kBlock)
      for (int k = 0; k < kBlock; ++k) {
        const float d = r[start + k] - query[start + k];
        lanes[k] += d * d;
      }
    float sum = 0;
    for (int k = 0; k < kBlock; ++k) sum += lanes[k];
    distance[i] = sum;
  }
  std::vector<float> best(subject_count_, std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < n; ++i)
    best[ids_[i].subject_slot] = std::min(best[ids_[i].subject_slot], distance[i]);
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> best_index(subject_count_, kNone);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t slot = ids_[i].subject_slot;
    if (distance[i] == best[slot] &&
        (best_index[slot] == kNone || ids_[i].gallery_index < ids_[best_index[slot]].gallery_index))
      best_index[slot] = i;
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
