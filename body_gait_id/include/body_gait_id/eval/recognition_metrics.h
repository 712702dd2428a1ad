// Recognition evaluation (thesis 5.8.3 and beyond): identification rate and average pose error
// (Table 5.3), CMC, verification ROC / EER, the open-set test (FPIR at a target FNIR), 95 %
// confidence intervals, and PCA / LDA feature transforms (the thesis's future work).
// ROS-agnostic and independent of the matcher: the input is what any matcher ranks.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace body_gait_id::eval {

// One enrolled subject's best gallery pose for a probe. Scores are distances (eq 5.16's E_r):
// lower is better, and a probe is accepted when its score is <= the threshold.
struct RankedCandidate {
  std::int64_t subject_id = 0;
  int frame = 0;  // gait-cycle frame (1..20) of the subject's best pose
  double score = 0;
};

// A probe as the evaluation sees it: the truth and the matcher's ranking.
struct ProbeResult {
  std::int64_t true_subject = 0;
  int true_frame = 0;
  bool enrolled = true;                     // false: a person not in the gallery (open-set test)
  std::vector<RankedCandidate> candidates;  // best first, one per enrolled subject
};

// A proportion with its 95 % confidence interval: Wilson score interval, and the rule of 3
// ([0, 3/n] or [1 - 3/n, 1]) when no event or only events were observed.
struct Proportion {
  int count = 0;
  int n = 0;
  double rate = 0;  // count / n (NaN when n == 0)
  double ci_low = 0, ci_high = 1;
};
Proportion proportion(int count, int n);

struct RocPoint {
  double threshold = 0;
  double false_accept_rate = 0;  // impostor scores <= threshold
  double false_reject_rate = 0;  // genuine scores > threshold
};

struct OpenSetResult {
  double target_fnir = 0.05;
  bool target_reached = false;  // false: rank-1 errors alone exceed the target
  double threshold = 0;         // the smallest threshold whose FNIR <= target
  Proportion fnir;              // enrolled probes not (rank-1 correct and score <= threshold)
  Proportion fpir;              // non-enrolled probes whose rank-1 score <= threshold
};

struct RecognitionMetrics {
  int enrolled_probes = 0, non_enrolled_probes = 0;
  Proportion identification;  // rank-1 over enrolled probes (5.8.3)
  // Pose error (5.8.3): |frame of the rank-1 candidate - true frame| over ALL enrolled probes,
  // identified or not. Plain difference as in the thesis (its 0.41 and 1.31 frames are 39/96
  // and 126/96: all 96 testing poses); the cyclic one, min(d, cycle - d), is given beside it
  // since frames 20 and 1 are neighbours on the gait cycle.
  double average_pose_error = 0;
  double average_cyclic_pose_error = 0;
  std::vector<Proportion> cmc;  // cmc[k - 1]: true subject within the first k candidates
  // Verification: genuine = a probe's score against its true subject; impostors = its scores
  // against every other enrolled subject (all candidates of non-enrolled probes).
  int genuine_scores = 0, impostor_scores = 0;
  std::vector<RocPoint> roc;    // one point per distinct score, thresholds ascending
  double equal_error_rate = 0;  // (FAR + FRR) / 2 at the ROC point where they are closest
  double eer_threshold = 0;
  std::optional<OpenSetResult> open_set;  // when there are enrolled and non-enrolled probes
  // The same at a stricter operating point (FNIR 1 %), where a protocol computes it.
  std::optional<OpenSetResult> open_set_strict;
};

struct MetricsOptions {
  int max_cmc_rank = 5;       // K = min(this, enrolled subjects)
  int cycle_frames = 20;      // 5.8.2
  double target_fnir = 0.05;  // open-set operating point
};

// Throws std::invalid_argument naming the problem (no candidates for an enrolled probe,
// candidates not sorted best first, non-finite scores).
RecognitionMetrics evaluateRecognition(const std::vector<ProbeResult>& probes,
                                       const MetricsOptions& options = {});

// One decision per walk (beyond the thesis): consecutive probes of the same true subject and
// enrolment (one walk's frames) become one probe whose candidates score the MEAN of that
// subject's frame scores, best first. Frames are 0 (no pose error per walk). Throws
// std::invalid_argument when a walk's frames do not rank the same subjects.
std::vector<ProbeResult> perWalkProbes(const std::vector<ProbeResult>& frame_probes);

// Linear feature transform y = W^T (x - mean), fitted on gallery feature vectors (one per row).
struct LinearFeatureTransform {
  Eigen::VectorXd mean;
  Eigen::MatrixXd projection;  // d x k, columns in decreasing order of importance

  // PCA: the k directions of largest variance (orthonormal columns).
  static LinearFeatureTransform pca(const Eigen::MatrixXd& samples, int components);
  // LDA (Fisher): directions maximizing between-subject over within-subject scatter,
  // S_b w = lambda (S_w + epsilon I) w with epsilon = regularization * trace(S_w) / d so that
  // few samples per subject (S_w singular) still work. components <= subjects - 1 (0: all).
  static LinearFeatureTransform lda(const Eigen::MatrixXd& samples,
                                    const std::vector<std::int64_t>& labels, int components = 0,
                                    double regularization = 1e-3);

  Eigen::VectorXd apply(const Eigen::VectorXd& x) const;
  Eigen::MatrixXd applyRows(const Eigen::MatrixXd& samples) const;
};

}  // namespace body_gait_id::eval
