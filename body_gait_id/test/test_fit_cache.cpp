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
  fit.model = body_gait_model::standingModel(1.71);
  fit.model.p << 0.1, -0.2, 0.95, 0.01, 1.234567890123, -0.02;
  for (int i = 0; i < fit.model.q.size(); ++i) fit.model.q(i) = 0.1 * i - 1.0 / 3;
  fit.model.shape.hip_rise = 0.0612345;
  fit.low_quality = true;
  fit.points = 412345;
  return fit;
}

fs::path scratch() {
  const fs::path folder =
      fs::temp_directory_path() / ("test_fit_cache_" + std::to_string(getpid()));
  fs::remove_all(folder);
  return folder;
}

TEST(FitCache, StoredFitsComeBackExactly) {
  const fs::path folder = scratch();
  const FitCache cache(folder.string());
  const CachedFit fit = someFit();
  EXPECT_FALSE(cache.load("0123456789abcdef").has_value());
  cache.store("0123456789abcdef", fit);
  const std::optional<CachedFit> back = cache.load("0123456789abcdef");
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
  fs::remove_all(folder);
}

TEST(FitCache, DamagedForeignOrOldEntriesAreMisses) {
  const fs::path folder = scratch();
  const FitCache cache(folder.string());
  const std::string key = "0123456789abcdef";
  const std::string text = serializeFit(someFit());
  auto entry = [&](const std::string& contents) {
    fs::create_directories(folder);
    std::ofstream(cache.pathOf(key)) << contents;
    return cache.load(key);
  };
  ASSERT_TRUE(entry(text).has_value());
  EXPECT_FALSE(entry(text.substr(0, text.size() / 2)).has_value());  // truncated
  EXPECT_FALSE(entry("garbage: [").has_value());
  std::string old = text;
  old.replace(old.find("cache_version: 1"), 16, "cache_version: 0");
  EXPECT_FALSE(entry(old).has_value());
  fs::remove_all(folder);

  // A cache that cannot be written is refused at once, naming the folder.
  const std::string blocked = (folder / "a_file").string();
  fs::create_directories(folder);
  std::ofstream(blocked) << "x";
  try {
    FitCache unusable(blocked + "/cache");
    FAIL() << "a folder under a file must be refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(blocked), std::string::npos) << e.what();
  }
  fs::remove_all(folder);

  const FitCache disabled;
  disabled.store(key, someFit());
  EXPECT_FALSE(disabled.load(key).has_value());
}

TEST(FitCache, KeyChangesWithSpecAndScanner) {
  body_scan_driver::sim::HumanBodySpec spec;
  const std::string key = scanKey(spec, "sampler");
  EXPECT_EQ(key.size(), 16u);
  EXPECT_EQ(scanKey(spec, "sampler"), key);  // deterministic
  EXPECT_NE(scanKey(spec, "full"), key);
  body_scan_driver::sim::HumanBodySpec moved = spec;
  moved.pose.left_knee_flexion += 1e-9;
  EXPECT_NE(scanKey(moved, "sampler"), key);
  moved = spec;
  moved.body.thigh_girth += 1e-9;
  EXPECT_NE(scanKey(moved, "sampler"), key);
  moved = spec;
  moved.materials.hair.albedo = 0.05;
  EXPECT_NE(scanKey(moved, "sampler"), key);
  // Bodies posed by explicit frames (motion capture) differ by their frames alone.
  moved = spec;
  moved.segment_frames = body_scan_driver::sim::bodySegmentFrames(spec);
  const std::string framed = scanKey(moved, "sampler");
  EXPECT_NE(framed, key);
  moved.segment_frames->foot[0].origin.x() += 1e-9;
  EXPECT_NE(scanKey(moved, "sampler"), framed);
}

}  // namespace
}  // namespace body_gait_id::eval
