#include <body_gait_id/eval/recognition_metrics.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace body_gait_id::eval {
namespace {

constexpr double kZ95 = 1.959963984540054;  // two-sided 95 % normal quantile

void checkProbe(const ProbeResult& probe, std::size_t index) {
  const std::string name = "probe " + std::to_string(index) + " (subject " +
                           std::to_string(probe.true_subject) + ", frame " +
                           std::to_string(probe.true_frame) + ")";
  if (probe.enrolled && probe.candidates.empty())
    throw std::invalid_argument(name +
                                " is enrolled but has no candidates: rank every enrolled "
                                "subject for it (Matcher::rankSubjects)");
  for (std::size_t i = 0; i < probe.candidates.size(); ++i) {
    if (!std::isfinite(probe.candidates[i].score))
      throw std::invalid_argument(name + " has a non-finite score: check its features for NaN");
    if (i > 0 && probe.candidates[i].score < probe.candidates[i - 1].score)
      throw std::invalid_argument(name +
                                  " has candidates not sorted best first: sort by ascending "
                                  "score");
  }
}

double fractionAtMost(const std::vector<double>& sorted, double threshold) {
  if (sorted.empty()) return 0;
  const auto end = std::upper_bound(sorted.begin(), sorted.end(), threshold);
  return static_cast<double>(end - sorted.begin()) / static_cast<double>(sorted.size());
}

}  // namespace

Proportion proportion(int count, int n) {
  Proportion p;
  p.count = count;
  p.n = n;
  if (n <= 0) {
    p.rate = std::numeric_limits<double>::quiet_NaN();
    return p;  // nothing observed: [0, 1]
  }
  p.rate = static_cast<double>(count) / n;
  if (count == 0) {  // rule of 3: one-sided 95 % bound with no event observed
    p.ci_low = 0;
    p.ci_high = std::min(1.0, 3.0 / n);
  } else if (count == n) {
    p.ci_low = std::max(0.0, 1.0 - 3.0 / n);
    p.ci_high = 1;
  } else {  // Wilson score interval
    const double z2 = kZ95 * kZ95;
    const double centre = (p.rate + z2 / (2.0 * n)) / (1 + z2 / n);
    const double half =
        kZ95 / (1 + z2 / n) * std::sqrt(p.rate * (1 - p.rate) / n + z2 / (4.0 * n * n));
    p.ci_low = std::max(0.0, centre - half);
    p.ci_high = std::min(1.0, centre + half);
  }
  return p;
}

RecognitionMetrics evaluateRecognition(const std::vector<ProbeResult>& probes,
                                       const MetricsOptions& options) {
  RecognitionMetrics metrics;
  std::size_t enrolled_subjects = 0;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    checkProbe(probes[i], i);
    enrolled_subjects = std::max(enrolled_subjects, probes[i].candidates.size());
    (probes[i].enrolled ? metrics.enrolled_probes : metrics.non_enrolled_probes)++;
  }
  const int max_rank =
      static_cast<int>(std::min<std::size_t>(std::max(0, options.max_cmc_rank), enrolled_subjects));

  // Identification, pose error and CMC over the enrolled probes.
  std::vector<int> found_within(max_rank, 0);
  int rank1_correct = 0;
  double pose_error_sum = 0, cyclic_pose_error_sum = 0;
  std::vector<double> genuine, impostor;
  std::vector<double> correct_rank1_scores;  // open set: the scores that can be accepted
  std::vector<double> non_enrolled_rank1_scores;
  for (const ProbeResult& probe : probes) {
    if (!probe.enrolled) {
      for (const RankedCandidate& c : probe.candidates) impostor.push_back(c.score);
      if (!probe.candidates.empty()) non_enrolled_rank1_scores.push_back(probe.candidates[0].score);
      continue;
    }
    const RankedCandidate& best = probe.candidates[0];
    if (best.subject_id == probe.true_subject) {
      ++rank1_correct;
      correct_rank1_scores.push_back(best.score);
    }
    const int difference = std::abs(best.frame - probe.true_frame);
    pose_error_sum += difference;
    cyclic_pose_error_sum += std::min(difference % options.cycle_frames,
                                      options.cycle_frames - difference % options.cycle_frames);
    for (std::size_t rank = 0; rank < probe.candidates.size(); ++rank) {
      const RankedCandidate& c = probe.candidates[rank];
      if (c.subject_id == probe.true_subject) {
        genuine.push_back(c.score);
        for (int k = static_cast<int>(rank); k < max_rank; ++k) ++found_within[k];
      } else {
        impostor.push_back(c.score);
      }
    }
  }
  const int n = metrics.enrolled_probes;
  metrics.identification = proportion(rank1_correct, n);
  metrics.average_pose_error = n > 0 ? pose_error_sum / n : 0;
  metrics.average_cyclic_pose_error = n > 0 ? cyclic_pose_error_sum / n : 0;
  for (int k = 0; k < max_rank; ++k) metrics.cmc.push_back(proportion(found_within[k], n));

  // Verification ROC and EER: one point per distinct score.
  std::sort(genuine.begin(), genuine.end());
  std::sort(impostor.begin(), impostor.end());
  metrics.genuine_scores = static_cast<int>(genuine.size());
  metrics.impostor_scores = static_cast<int>(impostor.size());
  std::vector<double> thresholds(genuine);
  thresholds.insert(thresholds.end(), impostor.begin(), impostor.end());
  std::sort(thresholds.begin(), thresholds.end());
  thresholds.erase(std::unique(thresholds.begin(), thresholds.end()), thresholds.end());
  double closest = std::numeric_limits<double>::infinity();
  for (double t : thresholds) {
    RocPoint point{t, fractionAtMost(impostor, t),
                   genuine.empty() ? 0.0 : 1 - fractionAtMost(genuine, t)};
    metrics.roc.push_back(point);
    const double gap = std::abs(point.false_accept_rate - point.false_reject_rate);
    if (!genuine.empty() && !impostor.empty() && gap < closest) {
      closest = gap;
      metrics.equal_error_rate = (point.false_accept_rate + point.false_reject_rate) / 2;
      metrics.eer_threshold = t;
    }
  }

  // Open set: the smallest threshold that accepts enough correct rank-1 matches.
  if (n > 0 && metrics.non_enrolled_probes > 0) {
    OpenSetResult open;
    open.target_fnir = options.target_fnir;
    std::sort(correct_rank1_scores.begin(), correct_rank1_scores.end());
    const int needed = static_cast<int>(std::ceil((1 - options.target_fnir) * n - 1e-9));
    const int accepted_max = static_cast<int>(correct_rank1_scores.size());
    open.target_reached = needed <= accepted_max;
    const int accepted = open.target_reached ? std::max(needed, 0) : accepted_max;
    open.threshold = accepted > 0 ? correct_rank1_scores[accepted - 1]
                                  : -std::numeric_limits<double>::infinity();
    int accepted_correct = 0;
    for (double s : correct_rank1_scores) accepted_correct += s <= open.threshold;
    open.fnir = proportion(n - accepted_correct, n);
    int false_positives = 0;
    for (double s : non_enrolled_rank1_scores) false_positives += s <= open.threshold;
    open.fpir = proportion(false_positives, metrics.non_enrolled_probes);
    metrics.open_set = open;
  }
  return metrics;
}

std::vector<ProbeResult> perWalkProbes(const std::vector<ProbeResult>& frame_probes) {
  std::vector<ProbeResult> walks;
  std::size_t begin = 0;
  while (begin < frame_probes.size()) {
    const ProbeResult& first = frame_probes[begin];
    std::size_t end = begin + 1;
    while (end < frame_probes.size() && frame_probes[end].true_subject == first.true_subject &&
           frame_probes[end].enrolled == first.enrolled)
      ++end;
    std::map<std::int64_t, double> sum;
    for (std::size_t i = begin; i < end; ++i) {
      for (const RankedCandidate& c : frame_probes[i].candidates) sum[c.subject_id] += c.score;
      if (frame_probes[i].candidates.size() != sum.size())
        throw std::invalid_argument("probe " + std::to_string(i) + " (subject " +
                                    std::to_string(first.true_subject) +
                                    ") ranks other subjects than its walk's first frame: rank "
                                    "every enrolled subject for every frame");
    }
    ProbeResult walk{first.true_subject, 0, first.enrolled, {}};
    for (const auto& [subject, total] : sum)
      walk.candidates.push_back({subject, 0, total / static_cast<double>(end - begin)});
    std::stable_sort(walk.candidates.begin(), walk.candidates.end(),
                     [](const auto& a, const auto& b) { return a.score < b.score; });
    walks.push_back(std::move(walk));
    begin = end;
  }
  return walks;
}

LinearFeatureTransform LinearFeatureTransform::pca(const Eigen::MatrixXd& samples, int components) {
  if (samples.rows() < 2 || components < 1 || components > samples.cols())
    throw std::invalid_argument("PCA needs at least 2 samples and 1 <= components (" +
                                std::to_string(components) + ") <= feature dimension (" +
                                std::to_string(samples.cols()) + ")");
  LinearFeatureTransform t;
  t.mean = samples.colwise().mean().transpose();
  const Eigen::MatrixXd centred = samples.rowwise() - t.mean.transpose();
  const Eigen::MatrixXd covariance = centred.transpose() * centred / (samples.rows() - 1);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);  // ascending eigenvalues
  t.projection = solver.eigenvectors().rightCols(components).rowwise().reverse();
  return t;
}

LinearFeatureTransform LinearFeatureTransform::lda(const Eigen::MatrixXd& samples,
                                                   const std::vector<std::int64_t>& labels,
                                                   int components, double regularization) {
  if (static_cast<std::size_t>(samples.rows()) != labels.size())
    throw std::invalid_argument("LDA needs one subject label per sample (" +
                                std::to_string(labels.size()) + " labels for " +
                                std::to_string(samples.rows()) + " samples)");
  std::map<std::int64_t, std::vector<Eigen::Index>> rows_of;
  for (std::size_t i = 0; i < labels.size(); ++i) rows_of[labels[i]].push_back(i);
  const int classes = static_cast<int>(rows_of.size());
  if (classes < 2) throw std::invalid_argument("LDA needs samples of at least 2 subjects");
  if (components <= 0) components = classes - 1;
  if (components > std::min<int>(classes - 1, samples.cols()))
    throw std::invalid_argument("LDA gives at most subjects - 1 = " + std::to_string(classes - 1) +
                                " components (asked " + std::to_string(components) + ")");
  const Eigen::Index d = samples.cols();
  LinearFeatureTransform t;
  t.mean = samples.colwise().mean().transpose();
  Eigen::MatrixXd within = Eigen::MatrixXd::Zero(d, d), between = Eigen::MatrixXd::Zero(d, d);
  for (const auto& [label, rows] : rows_of) {
    Eigen::VectorXd class_mean = Eigen::VectorXd::Zero(d);
    for (Eigen::Index r : rows) class_mean += samples.row(r).transpose();
    class_mean /= static_cast<double>(rows.size());
    for (Eigen::Index r : rows) {
      const Eigen::VectorXd deviation = samples.row(r).transpose() - class_mean;
      within += deviation * deviation.transpose();
    }
    const Eigen::VectorXd offset = class_mean - t.mean;
    between += static_cast<double>(rows.size()) * offset * offset.transpose();
  }
  const double epsilon = regularization * std::max(within.trace() / d, 1e-12);
  within += epsilon * Eigen::MatrixXd::Identity(d, d);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(between, within);
  t.projection = solver.eigenvectors().rightCols(components).rowwise().reverse();
  return t;
}

Eigen::VectorXd LinearFeatureTransform::apply(const Eigen::VectorXd& x) const {
  if (x.size() != mean.size())
    throw std::invalid_argument("feature vector has " + std::to_string(x.size()) +
                                " components, the transform was fitted on " +
                                std::to_string(mean.size()));
  return projection.transpose() * (x - mean);
}

Eigen::MatrixXd LinearFeatureTransform::applyRows(const Eigen::MatrixXd& samples) const {
  if (samples.cols() != mean.size())
    throw std::invalid_argument("feature vectors have " + std::to_string(samples.cols()) +
                                " components, the transform was fitted on " +
                                std::to_string(mean.size()));
  return (samples.rowwise() - mean.transpose()) * projection;
}

}  // namespace body_gait_id::eval
