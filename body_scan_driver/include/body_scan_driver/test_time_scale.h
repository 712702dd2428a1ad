// Wall-clock bounds of the suite's ROS tests, stretched by BODY_SCAN_TEST_TIME_SCALE.
// make sanitize sets it (sanitized nodes run several times slower); the .test files' time
// limits and the nodes' timeouts they set read the same variable.
#pragma once

#include <cstdlib>

namespace body_scan_driver {

inline double testTimeScale() {
  const char* value = std::getenv("BODY_SCAN_TEST_TIME_SCALE");
  const double scale = value ? std::atof(value) : 1.0;
  return scale > 1.0 ? scale : 1.0;
}

// A wait bound or "must not take longer than" bound of `seconds` on an unloaded build.
inline double scaledSeconds(double seconds) { return seconds * testTimeScale(); }

}  // namespace body_scan_driver
