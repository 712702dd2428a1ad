// Fitted body models cached on disk, so that re-running an evaluation (another feature set,
// protocol or plot) skips the scans and fits that did not change. Evaluation only.
#pragma once

#include <body_gait_model/kinematic_model.h>
#include <body_scan_driver/sim/human_body.h>

#include <optional>
#include <string>

namespace body_gait_id::eval {

// One scan's fit: the model and what the evaluation reports about it.
struct CachedFit {
  body_gait_model::BodyModel model;
  bool low_quality = false;  // the fitter flagged it (body_gait_model::FitQuality)
  int points = 0;            // points of the scanned cloud
};

// A cache entry is a body models file (models_file.h, exact round trip) with one pose and the
// keys cache_version, low_quality and points beside 'poses:'.
std::string serializeFit(const CachedFit& fit);

// Key of everything a scan depends on: the spec's numbers (body, pose, materials, position; as
// raw bytes, so a field added to them changes the key) and the scanner's settings (a string the
// caller makes, e.g. "sampler columns=320 noise=0.002"). 16 hex digits. Not the code: a cache
// folder also serves as a frozen set of fits (the walk-session rostests' gallery), so clear an
// evaluation's cache after changing the fitter or the simulator.
std::string scanKey(const body_scan_driver::sim::HumanBodySpec& spec, const std::string& scanner);

class FitCache {
 public:
  // An empty folder disables the cache (load finds nothing, store does nothing). Creates the
  // folder; throws body_scan_driver::FileWriteError naming it when it cannot be created or written,
  // so a run fails before its scans, not after.
  explicit FitCache(std::string folder = {});
  // nullopt when absent, of another version, truncated or damaged (the caller fits again).
  std::optional<CachedFit> load(const std::string& key) const;
  // Written atomically; throws body_scan_driver::FileWriteError naming the file and the fix.
  void store(const std::string& key, const CachedFit& fit) const;
  std::string pathOf(const std::string& key) const;

 private:
  std::string folder_;
};

}  // namespace body_gait_id::eval
