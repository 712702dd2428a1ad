// The within-subject feature noise (gait_features.h, FeatureNoise) on disk, so a matcher can
// weigh the features by it (noiseWeights) without the development people it was learned on:
//
//   # written by evaluate_gait_id --write-noise (cross-walk SDs, raw units: rad and m)
//   source: "sampler, 50 people, seed 3, median body"
//   dynamic: [22 values]   # q (eq 5.2)
//   statics: [12 values]   # r (eq 5.3)
//   shape: [24 values]     # bodyShapeFeatures
//
// It belongs to the scanner and fitter that produced the fits it was learned from.
#pragma once

#include <body_gait_id/gait_features.h>

#include <string>

namespace body_gait_id {

// Throws std::runtime_error naming the file and the key that is missing, has the wrong length
// or a value that is not a positive number.
FeatureNoise readFeatureNoise(const std::string& path);
// The file's text (evaluate_gait_id writes it atomically).
std::string featureNoiseYaml(const FeatureNoise& noise, const std::string& source);

}  // namespace body_gait_id
