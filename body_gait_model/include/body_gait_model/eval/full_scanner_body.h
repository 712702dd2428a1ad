// Whole-body clouds from the full scanner simulation (tests and evaluation only): the rig's 12
// pairs render the subject in their timing groups, decode, triangulate and merge exactly as the
// scanner does (body_scan_merge's simulateScan), so the fitter is judged on the product's
// clouds. The true skeleton comes with the cloud; the fitter never sees it.
#pragma once

#include <body_gait_model/eval/body_cloud_sampler.h>

#include <string>
#include <vector>

namespace body_gait_model::eval {

struct FullScannerOptions {
  std::string rig_file;                    // empty: body_scan_driver's thesis rig (rospack)
  std::vector<std::string> missing_pairs;  // pairs that deliver nothing (e.g. "pole_c/pair_2")
  double floor_albedo = 0.3;               // the floor the subject stands on (cropped away)
  BodyKind body = BodyKind::kEllipsoid;    // the simulated body scanned
};

// Throws std::invalid_argument naming an unknown missing pair, std::runtime_error naming a rig
// file that cannot be read.
SampledBody scanBodyWithFullScanner(const body_scan_driver::sim::HumanBodySpec& spec,
                                    const FullScannerOptions& options = {});

// The subject's heading in evaluation case `index` (0, 1, ...): within +-46 deg of the rig's
// front (+x), where the subject of a whole-body scanner faces (two poles in front, one behind).
double fullScannerHeading(int index);

}  // namespace body_gait_model::eval
