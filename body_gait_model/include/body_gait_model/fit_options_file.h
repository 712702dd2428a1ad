// FitOptions from a YAML file (config/body_fitter.yaml): the keys mirror FitOptions' members,
// nested maps for its sub-structs (axes, torso, quality, refinement). Missing keys keep their
// defaults. No ROS.
#pragma once

#include <body_gait_model/body_fitter.h>

#include <string>

namespace body_gait_model {

// Throws std::runtime_error naming the file, the key and the fix on an unreadable file, an
// unknown key (a typo would otherwise be ignored silently) or a value of the wrong type.
FitOptions loadFitOptions(const std::string& path);

}  // namespace body_gait_model
