// The fit cache returns exactly what was stored, refuses foreign or truncated files, and its
// key changes with anything the scan depends on.
#include <body_gait_id/eval/fit_cache.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace body_gait_id::eval {
namespace {

namespace fs = std::filesystem;

CachedFit someFit() {
  CachedFit fit;
  fit.model = body_gait::standingModel(1.71);
  fit.model.p << 0.1, -0.2, 0.95, 0.01, 1.234567890123, -0.02;
  for (int i = 0; i < fit.model.q.size(); ++i) fit.model.q(i) = 0.1 * i - 1.0 / 3;
  fit.model.shape.hip_rise = 0.0612345;
  fit.low_quality = true;
  fit.points = 412345;
  return fit;
}

TEST(FitCache, SerializationRoundTripsExactly) {
  const CachedFit fit = someFit();
  const std::optional<CachedFit> back = parseFit(serializeFit(fit));
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->model.p, fit.model.p);
  EXPECT_EQ(back->model.q, fit.model.q);
  EXPECT_EQ(back->model.r, fit.model.r);
  EXPECT_EQ(back->model.shape.proximal_radius, fit.model.shape.proximal_radius);
  EXPECT_EQ(back->model.shape.distal_radius, fit.model.shape.distal_radius);
  EXPECT_EQ(back->model.shape.shoulder_half_width, fit.model.shape.shoulder_half_width);
  EXPECT_EQ(back->model.shape.hip_rise, fit.model.shape.hip_rise);
  EXPECT_TRUE(back->low_quality);
  EXPECT_EQ(back->points, 412345);
}

TEST(FitCache, ForeignOrTruncatedTextIsNoFit) {
  const std::string text = serializeFit(someFit());
  EXPECT_FALSE(parseFit(text.substr(0, text.size() - 5)).has_value());
  EXPECT_FALSE(parseFit("body_gait_id fitted model v0\n" + text.substr(text.find('\n') + 1)));
  EXPECT_FALSE(parseFit("").has_value());
}

TEST(FitCache, KeyChangesWithSpecAndScanner) {
  body_scan::sim::HumanBodySpec spec;
  const std::string key = scanKey(spec, "sampler");
  EXPECT_EQ(key.size(), 16u);
  EXPECT_EQ(scanKey(spec, "sampler"), key);  // deterministic
  EXPECT_NE(scanKey(spec, "full"), key);
  body_scan::sim::HumanBodySpec moved = spec;
  moved.pose.left_knee_flexion += 1e-9;
  EXPECT_NE(scanKey(moved, "sampler"), key);
  moved = spec;
  moved.body.thigh_girth += 1e-9;
  EXPECT_NE(scanKey(moved, "sampler"), key);
  moved = spec;
  moved.materials.hair.albedo = 0.05;
  EXPECT_NE(scanKey(moved, "sampler"), key);
}

TEST(FitCache, StoresAndLoadsInItsFolder) {
  const fs::path folder =
      fs::temp_directory_path() / ("test_fit_cache_" + std::to_string(getpid()));
  fs::remove_all(folder);
  const FitCache cache(folder.string());
  EXPECT_FALSE(cache.load("0123456789abcdef").has_value());
  cache.store("0123456789abcdef", someFit());
  const std::optional<CachedFit> back = cache.load("0123456789abcdef");
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->model.q, someFit().model.q);
  // A damaged entry is a miss (the evaluation fits again and overwrites it).
  std::ofstream(cache.pathOf("0123456789abcdef")) << "garbage";
  EXPECT_FALSE(cache.load("0123456789abcdef").has_value());
  fs::remove_all(folder);

  const FitCache disabled;
  disabled.store("0123456789abcdef", someFit());
  EXPECT_FALSE(disabled.load("0123456789abcdef").has_value());
}

}  // namespace
}  // namespace body_gait_id::eval
