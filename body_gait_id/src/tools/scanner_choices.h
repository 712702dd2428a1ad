// The --scanner, --body and --fit choices of the evaluation tools (evaluate_gait_id,
// enroll_simulated_people).
#pragma once

#include <body_gait_id/eval/gait_id_evaluation.h>

#include <string>
#include <utility>
#include <vector>

namespace body_gait_id::tools {

inline const std::vector<std::pair<std::string, eval::ScannerKind>> kScannerChoices = {
    {"full", eval::ScannerKind::kFull},
    {"sampler", eval::ScannerKind::kSampler},
    {"truth", eval::ScannerKind::kTruth}};

inline const std::vector<std::pair<std::string, body_gait_model::eval::BodyKind>> kBodyChoices = {
    {"ellipsoid", body_gait_model::eval::BodyKind::kEllipsoid},
    {"mesh", body_gait_model::eval::BodyKind::kMesh}};

// --fit: a walk's 4 scans fitted together (as the body fitter fits a live walk) or each alone.
inline const std::vector<std::pair<std::string, eval::FitLevel>> kFitChoices = {
    {"walk", eval::FitLevel::kWalk}, {"scan", eval::FitLevel::kScan}};
inline constexpr const char* kFitHelp =
    "walk: a walk's 4 scans fitted together (fitWalk, one body), as the body fitter fits a live "
    "walk; scan: each scan alone (fitBody), as a single scan";

inline std::string scannerName(eval::ScannerKind scanner) {
  for (const auto& [name, kind] : kScannerChoices)
    if (kind == scanner) return name;
  return "?";
}

inline std::string bodyName(body_gait_model::eval::BodyKind body) {
  for (const auto& [name, kind] : kBodyChoices)
    if (kind == body) return name;
  return "?";
}

}  // namespace body_gait_id::tools
