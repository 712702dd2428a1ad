#include <body_scan_driver/sim/decoding_errors.h>
#include <body_scan_driver/stripe_decoder.h>

#include <cmath>

namespace body_scan_driver::sim {

double wrongStripeFraction(const RenderedPatternSet& set, const Scene& scene,
                           const PatternLayout& layout, const std::string& surface_prefix) {
  StripeImage decoded;
  StripeDecoder(layout).decode(set.frames, decoded);
  int lit = 0, wrong = 0;
  for (int v = 0; v < decoded.coordinate.rows; ++v)
    for (int u = 0; u < decoded.coordinate.cols; ++u) {
      const int surface = set.truth.surface(v, u);
      const float truth = set.truth.stripe(v, u);
      if (surface < 0 || std::isnan(truth) ||
          scene.surfaces()[surface]->name.rfind(surface_prefix, 0) != 0)
        continue;
      ++lit;
      const float got = decoded.coordinate(v, u);
      wrong += !std::isnan(got) && std::abs(got - truth) > 1.f;
    }
  return lit > 0 ? static_cast<double>(wrong) / lit : 0.0;
}

}  // namespace body_scan_driver::sim
