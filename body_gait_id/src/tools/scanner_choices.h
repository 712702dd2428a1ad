// The --scanner and --body choices of the evaluation tools (evaluate_gait_id,
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

inline std::string scannerName(eval::ScannerKind scanner) {
  for (const auto& [name, kind] : kScannerChoices)
    if (kind == scanner) return name;
  return "?";
}

}  // namespace body_gait_id::tools
