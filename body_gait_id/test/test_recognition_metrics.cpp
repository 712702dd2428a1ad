// Recognition metrics against hand-computed small cases (exact numbers).
#include <body_gait_id/eval/recognition_metrics.h>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace body_gait_id::eval {
namespace {

// Three enrolled subjects (1, 2, 3), four enrolled probes and two probes of people who are not
// enrolled (4, 5). Scores are distances.
std::vector<ProbeResult> threeSubjectToy() {
  return {
      {1, 1, true, {{1, 1, 0.10}, {2, 5, 0.50}, {3, 9, 0.90}}},    // right, frame exact
      {1, 20, true, {{1, 1, 0.20}, {3, 2, 0.60}, {2, 3, 0.80}}},   // right, frame 1 for 20
      {2, 5, true, {{2, 7, 0.30}, {1, 4, 0.40}, {3, 6, 0.70}}},    // right, 2 frames off
      {3, 10, true, {{1, 10, 0.35}, {3, 9, 0.45}, {2, 1, 1.00}}},  // wrong at rank 1, right at 2
      {4, 3, false, {{2, 3, 0.25}, {1, 3, 0.65}, {3, 3, 0.95}}},
      {5, 3, false, {{3, 3, 0.55}, {1, 3, 0.75}, {2, 3, 0.85}}},
  };
}

TEST(Proportion, WilsonIntervalMatchesPublishedValues) {
  // 95/100: Wilson 95 % interval [0.8882, 0.9785] (e.g. Newcombe 1998's method 3).
  const Proportion p = proportion(95, 100);
  EXPECT_DOUBLE_EQ(p.rate, 0.95);
  EXPECT_NEAR(p.ci_low, 0.888250, 1e-6);
  EXPECT_NEAR(p.ci_high, 0.978456, 1e-6);
  const Proportion half = proportion(1, 2);
  EXPECT_NEAR(half.ci_low, 0.094531, 1e-6);
  EXPECT_NEAR(half.ci_high, 0.905469, 1e-6);
}

TEST(Proportion, RuleOfThreeWhenNoErrorsOrNoEvents) {
  const Proportion all = proportion(96, 96);
  EXPECT_DOUBLE_EQ(all.rate, 1.0);
  EXPECT_DOUBLE_EQ(all.ci_low, 1 - 3.0 / 96);
  EXPECT_DOUBLE_EQ(all.ci_high, 1.0);
  const Proportion none = proportion(0, 30);
  EXPECT_DOUBLE_EQ(none.ci_low, 0.0);
  EXPECT_DOUBLE_EQ(none.ci_high, 0.1);
  const Proportion empty = proportion(0, 0);
  EXPECT_TRUE(std::isnan(empty.rate));
  EXPECT_EQ(empty.ci_low, 0.0);
  EXPECT_EQ(empty.ci_high, 1.0);
}

TEST(EvaluateRecognition, IdentificationPoseErrorAndCmcOfTheToy) {
  const RecognitionMetrics m = evaluateRecognition(threeSubjectToy());
  EXPECT_EQ(m.enrolled_probes, 4);
  EXPECT_EQ(m.non_enrolled_probes, 2);
  EXPECT_EQ(m.identification.count, 3);
  EXPECT_EQ(m.identification.n, 4);
  EXPECT_DOUBLE_EQ(m.identification.rate, 0.75);
  // |1-1| + |1-20| + |7-5| + |10-10| over all 4 enrolled probes (the wrong one included).
  EXPECT_DOUBLE_EQ(m.average_pose_error, 21.0 / 4);
  EXPECT_DOUBLE_EQ(m.average_cyclic_pose_error, 3.0 / 4);  // frame 1 is 1 away from frame 20
  ASSERT_EQ(m.cmc.size(), 3u);                             // K = min(5, 3 subjects)
  EXPECT_DOUBLE_EQ(m.cmc[0].rate, 0.75);
  EXPECT_DOUBLE_EQ(m.cmc[1].rate, 1.0);
  EXPECT_DOUBLE_EQ(m.cmc[2].rate, 1.0);
}

TEST(EvaluateRecognition, RocAndEqualErrorRateOfTheToy) {
  const RecognitionMetrics m = evaluateRecognition(threeSubjectToy());
  EXPECT_EQ(m.genuine_scores, 4);    // 0.10 0.20 0.30 0.45
  EXPECT_EQ(m.impostor_scores, 14);  // 8 of enrolled probes + 6 of the non-enrolled
  ASSERT_EQ(m.roc.size(), 18u);      // all scores are distinct
  EXPECT_DOUBLE_EQ(m.roc.front().threshold, 0.10);
  EXPECT_DOUBLE_EQ(m.roc.front().false_accept_rate, 0.0);
  EXPECT_DOUBLE_EQ(m.roc.front().false_reject_rate, 0.75);
  EXPECT_DOUBLE_EQ(m.roc.back().false_accept_rate, 1.0);
  EXPECT_DOUBLE_EQ(m.roc.back().false_reject_rate, 0.0);
  // At 0.40: impostors 0.25 0.35 0.40 accepted (3/14), genuine 0.45 rejected (1/4): the
  // closest FAR/FRR pair of the curve.
  EXPECT_DOUBLE_EQ(m.eer_threshold, 0.40);
  EXPECT_DOUBLE_EQ(m.equal_error_rate, (3.0 / 14 + 1.0 / 4) / 2);
}

TEST(EvaluateRecognition, EqualErrorRateIsZeroWhenScoresSeparate) {
  std::vector<ProbeResult> probes = {
      {1, 1, true, {{1, 1, 0.1}, {2, 1, 0.5}}},
      {2, 1, true, {{2, 1, 0.2}, {1, 1, 0.6}}},
  };
  const RecognitionMetrics m = evaluateRecognition(probes);
  EXPECT_DOUBLE_EQ(m.equal_error_rate, 0.0);
  EXPECT_DOUBLE_EQ(m.eer_threshold, 0.2);
  EXPECT_FALSE(m.open_set.has_value());  // no non-enrolled probes
  ASSERT_EQ(m.cmc.size(), 2u);
}

TEST(EvaluateRecognition, OpenSetThresholdAtTheTargetFnir) {
  MetricsOptions options;
  options.target_fnir = 0.5;  // 2 of the 4 enrolled probes must be accepted
  RecognitionMetrics m = evaluateRecognition(threeSubjectToy(), options);
  ASSERT_TRUE(m.open_set.has_value());
  EXPECT_TRUE(m.open_set->target_reached);
  EXPECT_DOUBLE_EQ(m.open_set->threshold, 0.20);
  EXPECT_DOUBLE_EQ(m.open_set->fnir.rate, 0.5);
  EXPECT_DOUBLE_EQ(m.open_set->fpir.rate, 0.0);  // rank-1 scores 0.25 and 0.55 rejected

  options.target_fnir = 0.25;  // 3 of 4: threshold 0.30 lets 0.25 of person 4 in
  m = evaluateRecognition(threeSubjectToy(), options);
  EXPECT_TRUE(m.open_set->target_reached);
  EXPECT_DOUBLE_EQ(m.open_set->threshold, 0.30);
  EXPECT_DOUBLE_EQ(m.open_set->fnir.rate, 0.25);
  EXPECT_DOUBLE_EQ(m.open_set->fpir.rate, 0.5);

  // 5 %: 4 of 4 needed, but one probe is wrong at rank 1: the target cannot be reached; the
  // threshold accepts every right rank-1 match.
  m = evaluateRecognition(threeSubjectToy());
  EXPECT_FALSE(m.open_set->target_reached);
  EXPECT_DOUBLE_EQ(m.open_set->threshold, 0.30);
  EXPECT_EQ(m.open_set->fnir.count, 1);
  EXPECT_EQ(m.open_set->fpir.count, 1);
  EXPECT_EQ(m.open_set->fpir.n, 2);
}

TEST(EvaluateRecognition, BadInputNamesTheProbeAndTheFix) {
  std::vector<ProbeResult> probes = threeSubjectToy();
  probes[2].candidates.clear();
  try {
    evaluateRecognition(probes);
    FAIL() << "an enrolled probe without candidates must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("probe 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("rankSubjects"), std::string::npos) << e.what();
  }
  probes = threeSubjectToy();
  std::swap(probes[0].candidates[0], probes[0].candidates[1]);
  EXPECT_THROW(evaluateRecognition(probes), std::invalid_argument);
  probes = threeSubjectToy();
  probes[1].candidates[2].score = NAN;
  EXPECT_THROW(evaluateRecognition(probes), std::invalid_argument);
}

TEST(PerWalkProbes, MeanScoresOverEachWalkDecideOnce) {
  // Subject 1's walk: frame 2 alone would go to subject 2, the walk's mean does not.
  const std::vector<ProbeResult> frames = {
      {1, 1, true, {{1, 1, 0.1}, {2, 1, 0.5}}},  {1, 2, true, {{2, 2, 0.2}, {1, 2, 0.3}}},
      {2, 1, true, {{2, 1, 0.4}, {1, 1, 0.6}}},  {3, 1, false, {{1, 1, 0.7}, {2, 1, 0.9}}},
      {3, 2, false, {{2, 2, 0.8}, {1, 2, 0.9}}},
  };
  const std::vector<ProbeResult> walks = perWalkProbes(frames);
  ASSERT_EQ(walks.size(), 3u);
  EXPECT_EQ(walks[0].true_subject, 1);
  ASSERT_EQ(walks[0].candidates.size(), 2u);
  EXPECT_EQ(walks[0].candidates[0].subject_id, 1);
  EXPECT_DOUBLE_EQ(walks[0].candidates[0].score, 0.2);   // (0.1 + 0.3) / 2
  EXPECT_DOUBLE_EQ(walks[0].candidates[1].score, 0.35);  // (0.5 + 0.2) / 2
  EXPECT_DOUBLE_EQ(walks[1].candidates[0].score, 0.4);
  EXPECT_FALSE(walks[2].enrolled);
  EXPECT_DOUBLE_EQ(walks[2].candidates[0].score, 0.8);  // subject 1: (0.7 + 0.9) / 2
  EXPECT_DOUBLE_EQ(walks[2].candidates[1].score, 0.85);
  const RecognitionMetrics per_frame = evaluateRecognition(frames);
  const RecognitionMetrics per_walk = evaluateRecognition(walks);
  EXPECT_EQ(per_frame.identification.count, 2);  // of 3 frames
  EXPECT_EQ(per_walk.identification.count, 2);   // of 2 walks
  EXPECT_EQ(per_walk.identification.n, 2);
  std::vector<ProbeResult> ragged = frames;
  ragged[1].candidates.pop_back();
  EXPECT_THROW(perWalkProbes(ragged), std::invalid_argument);
}

TEST(LinearFeatureTransform, PcaFindsTheDirectionOfLargestVariance) {
  // Points spread along (0.6, 0.8) by +-20, and +-0.1 across it, uncorrelated.
  const Eigen::Vector2d along(0.6, 0.8), across(-0.8, 0.6), centre(3, -1);
  Eigen::MatrixXd samples(10, 2);
  for (int i = 0; i < 10; ++i)
    samples.row(i) =
        (centre + (i / 2 - 2) * 10.0 * along + (i % 2 ? 0.1 : -0.1) * across).transpose();
  const LinearFeatureTransform pca = LinearFeatureTransform::pca(samples, 1);
  EXPECT_NEAR((pca.mean - centre).norm(), 0.0, 1e-12);
  ASSERT_EQ(pca.projection.cols(), 1);
  EXPECT_NEAR(std::abs(pca.projection.col(0).dot(along)), 1.0, 1e-12);
  // The projection of a sample is its coordinate along the direction.
  EXPECT_NEAR(std::abs(pca.apply(samples.row(8).transpose())(0)), 20.0, 1e-9);
  EXPECT_THROW(LinearFeatureTransform::pca(samples, 3), std::invalid_argument);
}

TEST(LinearFeatureTransform, LdaFindsTheDiscriminantDirectionNotTheLargestVariance) {
  // Two subjects spread widely along x (+-10) and told apart only by y (+1 / -1): PCA keeps
  // x, LDA keeps y. Within-subject scatter is singular in y: the regularization handles it.
  Eigen::MatrixXd samples(8, 2);
  std::vector<std::int64_t> labels;
  for (int i = 0; i < 8; ++i) {
    const int subject = i % 2;
    samples.row(i) << (i / 2 - 1.5) * 20.0 / 3, subject ? -1.0 : 1.0;
    labels.push_back(subject + 7);
  }
  const LinearFeatureTransform pca = LinearFeatureTransform::pca(samples, 1);
  EXPECT_NEAR(std::abs(pca.projection(0, 0)), 1.0, 1e-9);
  const LinearFeatureTransform lda = LinearFeatureTransform::lda(samples, labels);
  ASSERT_EQ(lda.projection.cols(), 1);  // subjects - 1
  const Eigen::Vector2d direction = lda.projection.col(0).normalized();
  EXPECT_NEAR(std::abs(direction.y()), 1.0, 1e-9);
  const Eigen::MatrixXd projected = lda.applyRows(samples);
  for (int i = 2; i < 8; ++i)  // every sample of a subject projects to the same value
    EXPECT_NEAR(projected(i, 0), projected(i % 2, 0), 1e-9);
  EXPECT_GT(std::abs(projected(0, 0) - projected(1, 0)), 1.0);
}

TEST(LinearFeatureTransform, LdaComponentsAndBadInput) {
  Eigen::MatrixXd samples = Eigen::MatrixXd::Random(9, 4);
  const std::vector<std::int64_t> labels = {1, 1, 1, 2, 2, 2, 3, 3, 3};
  EXPECT_EQ(LinearFeatureTransform::lda(samples, labels).projection.cols(), 2);
  EXPECT_EQ(LinearFeatureTransform::lda(samples, labels, 1).projection.cols(), 1);
  EXPECT_THROW(LinearFeatureTransform::lda(samples, labels, 3), std::invalid_argument);
  EXPECT_THROW(LinearFeatureTransform::lda(samples, {1, 1, 1}), std::invalid_argument);
  EXPECT_THROW(LinearFeatureTransform::lda(samples, std::vector<std::int64_t>(9, 1)),
               std::invalid_argument);
  const LinearFeatureTransform lda = LinearFeatureTransform::lda(samples, labels);
  EXPECT_THROW(lda.apply(Eigen::VectorXd::Zero(3)), std::invalid_argument);
}

}  // namespace
}  // namespace body_gait_id::eval
