// Body models in YAML: the one reader and writer of the format, used by play_gait_cycle (the 4
// representative poses s1..s4 of thesis 5.3), body_gait_id's enrolment input, fit cache and
// gallery export, and evaluate_body_fit's fitted walks. No ROS.
//
//   poses:            # s1..s4 in thesis 5.3 order where 4 representative poses are meant
//     - p: [6 numbers]    # eq 5.1: tau_x, tau_y, tau_z (m, world), theta_x, theta_y, theta_z
//       q: [22 numbers]   # eq 5.2 (rad), kinematic_model.h order
//       r: [12 numbers]   # eq 5.3 (m)
//       # optional (BodyShape; default: standingModel of the stature the legs imply):
//       proximal_radius: [12], distal_radius: [12], shoulder_half_width, shoulder_drop,
//       hip_half_width, hip_rise, hip_back (0 when a file with hip_rise has none: the hips
//       on the lower torso's axis, as models were before it)
//       # optional annotations, read past: frame, sequence, low_quality
//
// or BodyModel messages one per YAML document, as `rostopic echo -n 4 /body_gait/model > f.yaml`
// writes them (the same keys; the message's other fields are read past).
#pragma once

#include <body_gait_model/gait_cycle.h>

#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace body_gait_model {

// One model as a map with every key above (the shape included), lists in flow style.
YAML::Node bodyModelToYaml(const BodyModel& model);
// The file's text: `poses:` with every model, doubles exact (17 digits), after `comment` lines.
std::string bodyModelsYaml(const std::vector<BodyModel>& models, const std::string& comment = "");

// Every model of a file (either form above). Throws std::runtime_error naming the file, the pose,
// the key and the fix on an unreadable file, no poses, a missing or unknown key, or an array of
// the wrong length.
std::vector<BodyModel> loadBodyModels(const std::string& path);

// Exactly 4 models, s1..s4. The same errors, and one for any other count.
RepresentativePoses loadRepresentativePoses(const std::string& path);
// Writes every key (the shape included); throws std::runtime_error if the file cannot be written.
void saveRepresentativePoses(const std::string& path, const RepresentativePoses& poses);

}  // namespace body_gait_model
