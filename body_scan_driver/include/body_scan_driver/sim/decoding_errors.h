// How well a rendered pattern set decodes, against its ground truth (tests and evaluation of
// interference: thesis 4.3, Fig 4.7).
#pragma once

#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/sim/virtual_pair.h>

#include <string>

namespace body_scan_driver::sim {

// Fraction of the lit pixels on surfaces whose name starts with surface_prefix (e.g. the
// person's "person/") that decode (StripeDecoder, default parameters) more than one stripe
// away from the true stripe. 0 when there are none.
double wrongStripeFraction(const RenderedPatternSet& set, const Scene& scene,
                           const PatternLayout& layout,
                           const std::string& surface_prefix = "person/");

}  // namespace body_scan_driver::sim
