// The indexed matcher (eq 5.16) against its named peer, the brute-force double scan, on random
// galleries: same nearest pose, same score (float32 rounding aside), same per-subject ranking.
#include <body_gait_id/matcher.h>
#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <random>

namespace body_gait_id {
namespace {

// Subjects with their own static vector and a smooth cycle of poses, plus noise; components
// on different scales (radians vs metres) so the normalization matters.
std::vector<GalleryPose> randomGallery(int subjects, int poses, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  std::vector<GalleryPose> gallery;
  for (int s = 0; s < subjects; ++s) {
    const Eigen::VectorXd statics = (Eigen::VectorXd::Random(12).array() * 0.1 + 0.4).matrix();
    const Eigen::VectorXd amplitude = Eigen::VectorXd::Random(22) * 0.6;
    const Eigen::VectorXd phase = Eigen::VectorXd::Random(22) * 3.0;
    for (int n = 0; n < poses; ++n) {
      GaitFeatures f;
      f.dynamic.resize(22);
      for (int k = 0; k < 22; ++k)
        f.dynamic[k] =
            amplitude[k] * std::sin(2 * M_PI * n / poses + phase[k]) + 0.05 * normal(rng);
      f.statics = statics;
      for (int k = 0; k < 12; ++k) f.statics[k] += 0.005 * normal(rng);
      gallery.push_back({1000 + s, n / 20, n % 20 + 1, f});
    }
  }
  return gallery;
}

GaitFeatures perturbed(const GaitFeatures& f, double sigma, std::mt19937& rng) {
  std::normal_distribution<double> normal(0, sigma);
  GaitFeatures out = f;
  for (Eigen::Index k = 0; k < out.dynamic.size(); ++k) out.dynamic[k] += normal(rng);
  for (Eigen::Index k = 0; k < out.statics.size(); ++k) out.statics[k] += 0.1 * normal(rng);
  return out;
}

class MatcherTest : public ::testing::TestWithParam<FeatureSet> {};

TEST_P(MatcherTest, IndexFindsTheBruteForceNearestPose) {
  std::mt19937 rng(7);
  const std::vector<GalleryPose> gallery = randomGallery(60, 40, rng);
  const Matcher matcher(gallery, GetParam());
  const BruteForceMatcher peer(gallery, GetParam(), matcher.normalization());
  ASSERT_EQ(matcher.size(), gallery.size());
  std::uniform_int_distribution<std::size_t> pick(0, gallery.size() - 1);
  int checked = 0;
  // Probes near a gallery pose (genuine), far from all (impostors of another gait) and between.
  for (double sigma : {0.02, 0.1, 0.5, 2.0}) {
    for (int i = 0; i < 150; ++i) {
      const GaitFeatures probe = perturbed(gallery[pick(rng)].features, sigma, rng);
      const Match indexed = matcher.identify(probe), brute = peer.identify(probe);
      ASSERT_EQ(indexed.subject_id, brute.subject_id) << "sigma " << sigma << " probe " << i;
      ASSERT_EQ(indexed.sequence, brute.sequence);
      ASSERT_EQ(indexed.frame, brute.frame);
      ASSERT_NEAR(indexed.score, brute.score, 1e-5 * (1 + brute.score));
      ++checked;
    }
  }
  EXPECT_EQ(checked, 600);
}

TEST_P(MatcherTest, GalleryPoseFindsItselfWithZeroScore) {
  std::mt19937 rng(3);
  const std::vector<GalleryPose> gallery = randomGallery(10, 40, rng);
  const Matcher matcher(gallery, GetParam());
  for (std::size_t i = 0; i < gallery.size(); i += 37) {
    const Match m = matcher.identify(gallery[i].features);
    EXPECT_EQ(m.subject_id, gallery[i].subject_id);
    EXPECT_EQ(m.sequence, gallery[i].sequence);
    EXPECT_EQ(m.frame, gallery[i].frame);
    EXPECT_LT(m.score, 1e-4);
  }
}

TEST_P(MatcherTest, RankSubjectsIsEachSubjectsBruteForceBest) {
  std::mt19937 rng(11);
  const std::vector<GalleryPose> gallery = randomGallery(25, 40, rng);
  const Matcher matcher(gallery, GetParam());
  for (int i = 0; i < 20; ++i) {
    const GaitFeatures probe = perturbed(gallery[i * 41].features, 0.2, rng);
    const std::vector<Match> ranked = matcher.rankSubjects(probe);
    ASSERT_EQ(ranked.size(), 25u);
    std::map<std::int64_t, double> best;  // brute force per subject, double precision
    for (const GalleryPose& pose : gallery) {
      const double d = (matcher.normalization().normalized(pose.features, GetParam()) -
                        matcher.normalization().normalized(probe, GetParam()))
                           .norm();
      auto [it, inserted] = best.emplace(pose.subject_id, d);
      if (!inserted) it->second = std::min(it->second, d);
    }
    for (std::size_t k = 0; k < ranked.size(); ++k) {
      EXPECT_NEAR(ranked[k].score, best.at(ranked[k].subject_id), 1e-5 * (1 + ranked[k].score));
      if (k > 0) {
        EXPECT_LE(ranked[k - 1].score, ranked[k].score);
      }
    }
    const Match first = matcher.identify(probe);
    EXPECT_EQ(ranked[0].subject_id, first.subject_id);
    EXPECT_EQ(ranked[0].frame, first.frame);
  }
}

INSTANTIATE_TEST_SUITE_P(FeatureSets, MatcherTest,
                         ::testing::Values(FeatureSet::kDynamic, FeatureSet::kDynamicStatic));

// The 2D views' sizes (11 + 12, 11): rows padded from 23 and 11 floats to blocks of 8.
TEST(Matcher, TwoDimensionalViewSizesMatchThePeer) {
  std::mt19937 rng(13);
  std::vector<GalleryPose> gallery = randomGallery(30, 40, rng);
  for (GalleryPose& pose : gallery) pose.features.dynamic.conservativeResize(11);
  for (FeatureSet set : {FeatureSet::kDynamic, FeatureSet::kDynamicStatic}) {
    const Matcher matcher(gallery, set);
    const BruteForceMatcher peer(gallery, set, matcher.normalization());
    std::uniform_int_distribution<std::size_t> pick(0, gallery.size() - 1);
    for (int i = 0; i < 200; ++i) {
      const GaitFeatures probe = perturbed(gallery[pick(rng)].features, 0.1 + 0.01 * i, rng);
      const Match indexed = matcher.identify(probe), brute = peer.identify(probe);
      ASSERT_EQ(indexed.subject_id, brute.subject_id) << "probe " << i;
      ASSERT_EQ(indexed.frame, brute.frame) << "probe " << i;
      ASSERT_NEAR(indexed.score, brute.score, 1e-5 * (1 + brute.score));
    }
  }
}

TEST(Matcher, StoredNormalizationIsUsedAsGiven) {
  std::mt19937 rng(5);
  const std::vector<GalleryPose> gallery = randomGallery(5, 40, rng);
  FeatureNormalization stored = Matcher(gallery, FeatureSet::kDynamicStatic).normalization();
  stored.sigma_static *= 2.0;  // a different scale changes the scores of static differences
  const Matcher matcher(gallery, FeatureSet::kDynamicStatic, stored);
  EXPECT_EQ(matcher.normalization().sigma_static, stored.sigma_static);
  const GaitFeatures probe = perturbed(gallery[3].features, 0.1, rng);
  EXPECT_NEAR(matcher.identify(probe).score,
              BruteForceMatcher(gallery, FeatureSet::kDynamicStatic, stored).identify(probe).score,
              1e-5);
}

TEST(Matcher, BadInputGivesClearErrors) {
  EXPECT_THROW(Matcher({}, FeatureSet::kDynamic), std::invalid_argument);
  std::mt19937 rng(1);
  const Matcher matcher(randomGallery(2, 40, rng), FeatureSet::kDynamic);
  GaitFeatures frontal{Eigen::VectorXd::Zero(11), Eigen::VectorXd::Zero(12), {}};
  EXPECT_THROW(matcher.identify(frontal), std::invalid_argument);
  GaitFeatures nan{Eigen::VectorXd::Zero(22), Eigen::VectorXd::Zero(12), {}};
  nan.dynamic[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(matcher.identify(nan), std::invalid_argument);
  EXPECT_THROW(matcher.rankSubjects(nan), std::invalid_argument);
  std::vector<GalleryPose> bad = randomGallery(2, 40, rng);
  bad[7].features.statics[3] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(Matcher(bad, FeatureSet::kDynamicStatic), std::invalid_argument);
}

}  // namespace
}  // namespace body_gait_id
