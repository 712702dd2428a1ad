#include <body_scan_driver/simd.h>

#include <algorithm>

namespace body_scan_driver {

SimdLevel detectedSimdLevel() {
#if defined(__x86_64__) || defined(__i386__)
  static const SimdLevel level = [] {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq"))
      return SimdLevel::kAvx512;
    if (__builtin_cpu_supports("avx2")) return SimdLevel::kAvx2;
    return SimdLevel::kSse2;
  }();
  return level;
#else
  return SimdLevel::kSse2;
#endif
}

SimdLevel effectiveSimdLevel(SimdLevel requested) {
  return std::min(requested, detectedSimdLevel());
}

std::vector<SimdLevel> availableSimdLevels() {
  std::vector<SimdLevel> levels;
  for (SimdLevel level : {SimdLevel::kSse2, SimdLevel::kAvx2, SimdLevel::kAvx512})
    if (level <= detectedSimdLevel()) levels.push_back(level);
  return levels;
}

std::string simdLevelName(SimdLevel level) {
  switch (level) {
    case SimdLevel::kSse2:
      return "sse2";
    case SimdLevel::kAvx2:
      return "avx2";
    case SimdLevel::kAvx512:
      return "avx512";
  }
  return "unknown";
}

}  // namespace body_scan_driver
