#include <body_gait_id/eval/fit_cache.h>
#include <body_gait_id/models_file.h>
#include <body_scan_driver/atomic_file.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <filesystem>
#include <sstream>

namespace body_gait_id::eval {
namespace {

constexpr int kCacheVersion = 1;

// The spec's parts are plain doubles (no padding), so their bytes are their values.
static_assert(sizeof(body_scan_driver::sim::Anthropometry) % sizeof(double) == 0);
static_assert(sizeof(body_scan_driver::sim::BodyPose) % sizeof(double) == 0);
static_assert(sizeof(body_scan_driver::sim::BodyMaterials) % sizeof(double) == 0);
static_assert(sizeof(body_scan_driver::sim::BodySegmentFrames) % sizeof(double) == 0);

void fnv1a(std::uint64_t& hash, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 1099511628211ull;
  }
}

}  // namespace

std::string serializeFit(const CachedFit& fit) {
  std::ostringstream out;
  writeBodyModels(out, {fit.model});
  out << "cache_version: " << kCacheVersion
      << "\nlow_quality: " << (fit.low_quality ? "true" : "false") << "\npoints: " << fit.points
      << "\n";
  return out.str();
}

std::string scanKey(const body_scan_driver::sim::HumanBodySpec& spec, const std::string& scanner) {
  std::uint64_t hash = 14695981039346656037ull;
  fnv1a(hash, &spec.body, sizeof(spec.body));
  fnv1a(hash, &spec.pose, sizeof(spec.pose));
  fnv1a(hash, &spec.materials, sizeof(spec.materials));
  fnv1a(hash, spec.position.data(), sizeof(double) * 3);
  // A body posed by explicit frames (motion capture) differs by its frames; bodies posed by
  // angles keep their keys.
  if (spec.segment_frames) fnv1a(hash, &*spec.segment_frames, sizeof(*spec.segment_frames));
  fnv1a(hash, scanner.data(), scanner.size());
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

FitCache::FitCache(std::string folder) : folder_(std::move(folder)) {
  if (folder_.empty()) return;
  const std::string probe = folder_ + "/.write_test";
  body_scan_driver::writeFileAtomically(probe, "");  // creates the folder, or says why it cannot
  std::error_code ignored;
  std::filesystem::remove(probe, ignored);
}

std::string FitCache::pathOf(const std::string& key) const {
  return folder_ + "/fit_" + key + ".yaml";
}

std::optional<CachedFit> FitCache::load(const std::string& key) const {
  if (folder_.empty()) return std::nullopt;
  const std::string path = pathOf(key);
  if (!std::filesystem::exists(path)) return std::nullopt;
  try {
    const YAML::Node root = YAML::LoadFile(path);
    if (!root["cache_version"] || root["cache_version"].as<int>() != kCacheVersion ||
        !root["low_quality"] || !root["points"])
      return std::nullopt;
    const std::vector<body_gait_model::BodyModel> models = readBodyModels(path);
    if (models.size() != 1) return std::nullopt;
    return CachedFit{models[0], root["low_quality"].as<bool>(), root["points"].as<int>()};
  } catch (const std::exception&) {
    return std::nullopt;  // damaged or foreign: a miss
  }
}

void FitCache::store(const std::string& key, const CachedFit& fit) const {
  if (folder_.empty()) return;
  body_scan_driver::writeFileAtomically(pathOf(key), serializeFit(fit));
}

}  // namespace body_gait_id::eval
