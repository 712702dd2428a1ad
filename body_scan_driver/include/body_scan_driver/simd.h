// Runtime choice of the x86 vector instruction set for the hot loops (decoder, triangulation).
// The library is compiled for the x86-64 baseline (SSE2); the AVX2 and AVX-512 variants are
// separate functions compiled with __attribute__((target(...))) and chosen at run time from
// what the CPU reports (__builtin_cpu_supports), so one binary runs everywhere.
#pragma once

#include <string>
#include <vector>

namespace body_scan_driver {

// Ordered: a higher level includes the lower ones.
enum class SimdLevel { kSse2 = 0, kAvx2 = 1, kAvx512 = 2 };

// The best level this CPU supports (AVX-512 needs F, BW, VL and DQ).
SimdLevel detectedSimdLevel();
// min(requested, detectedSimdLevel()): a request above what the CPU has falls back.
SimdLevel effectiveSimdLevel(SimdLevel requested);
// Every level this CPU can run, lowest first (tests iterate them).
std::vector<SimdLevel> availableSimdLevels();
std::string simdLevelName(SimdLevel level);

}  // namespace body_scan_driver
