#include <body_gait_id/eval/fit_cache.h>
#include <body_scan_driver/atomic_file.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <type_traits>

namespace body_gait_id::eval {
namespace {

constexpr const char* kVersionLine = "body_gait_id fitted model v1";

// The spec's parts are plain doubles (no padding), so their bytes are their values.
static_assert(sizeof(body_scan::sim::Anthropometry) % sizeof(double) == 0);
static_assert(sizeof(body_scan::sim::BodyPose) % sizeof(double) == 0);
static_assert(sizeof(body_scan::sim::BodyMaterials) % sizeof(double) == 0);

void fnv1a(std::uint64_t& hash, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 1099511628211ull;
  }
}

template <typename Vector>
void writeNumbers(std::ostream& out, const char* name, const Vector& values) {
  out << name;
  for (const double v : values) {
    char text[32];
    std::snprintf(text, sizeof(text), " %.17g", v);
    out << text;
  }
  out << "\n";
}

template <typename Vector>
bool readNumbers(std::istream& in, const std::string& name, Vector& values) {
  std::string label;
  if (!(in >> label) || label != name) return false;
  for (auto& v : values)
    if (!(in >> v)) return false;
  return true;
}

}  // namespace

std::string serializeFit(const CachedFit& fit) {
  std::ostringstream out;
  const body_gait::BodyModel& m = fit.model;
  out << kVersionLine << "\n";
  writeNumbers(out, "p", m.p);
  writeNumbers(out, "q", m.q);
  writeNumbers(out, "r", m.r);
  writeNumbers(out, "proximal_radius", m.shape.proximal_radius);
  writeNumbers(out, "distal_radius", m.shape.distal_radius);
  writeNumbers(out, "joints",
               std::array<double, 4>{m.shape.shoulder_half_width, m.shape.shoulder_drop,
                                     m.shape.hip_half_width, m.shape.hip_rise});
  out << "low_quality " << (fit.low_quality ? 1 : 0) << "\npoints " << fit.points << "\nend\n";
  return out.str();
}

std::optional<CachedFit> parseFit(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != kVersionLine) return std::nullopt;
  CachedFit fit;
  body_gait::BodyModel& m = fit.model;
  std::array<double, 4> joints{};
  std::string label, end;
  int low_quality = 0;
  if (!readNumbers(in, "p", m.p) || !readNumbers(in, "q", m.q) || !readNumbers(in, "r", m.r) ||
      !readNumbers(in, "proximal_radius", m.shape.proximal_radius) ||
      !readNumbers(in, "distal_radius", m.shape.distal_radius) ||
      !readNumbers(in, "joints", joints) || !(in >> label >> low_quality) ||
      label != "low_quality" || !(in >> label >> fit.points) || label != "points" || !(in >> end) ||
      end != "end")
    return std::nullopt;
  m.shape.shoulder_half_width = joints[0];
  m.shape.shoulder_drop = joints[1];
  m.shape.hip_half_width = joints[2];
  m.shape.hip_rise = joints[3];
  fit.low_quality = low_quality != 0;
  return fit;
}

std::string scanKey(const body_scan::sim::HumanBodySpec& spec, const std::string& scanner) {
  std::uint64_t hash = 14695981039346656037ull;
  fnv1a(hash, &spec.body, sizeof(spec.body));
  fnv1a(hash, &spec.pose, sizeof(spec.pose));
  fnv1a(hash, &spec.materials, sizeof(spec.materials));
  fnv1a(hash, spec.position.data(), sizeof(double) * 3);
  fnv1a(hash, scanner.data(), scanner.size());
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

FitCache::FitCache(std::string folder) : folder_(std::move(folder)) {}

std::string FitCache::pathOf(const std::string& key) const {
  return folder_ + "/fit_" + key + ".txt";
}

std::optional<CachedFit> FitCache::load(const std::string& key) const {
  if (folder_.empty()) return std::nullopt;
  std::ifstream file(pathOf(key));
  if (!file) return std::nullopt;
  std::stringstream text;
  text << file.rdbuf();
  return parseFit(text.str());
}

void FitCache::store(const std::string& key, const CachedFit& fit) const {
  if (folder_.empty()) return;
  body_scan::writeFileAtomically(pathOf(key), serializeFit(fit));
}

}  // namespace body_gait_id::eval
