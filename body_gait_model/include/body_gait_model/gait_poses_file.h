// The 4 representative poses s1..s4 of thesis 5.3 as a YAML file: the input of play_gait_cycle
// (poses fitted elsewhere, or written from simulated people). No ROS.
//
//   poses:            # exactly 4, in thesis 5.3 order (s1 right heel strike .. s4)
//     - p: [6 numbers]    # eq 5.1: tau_x, tau_y, tau_z (m, world), theta_x, theta_y, theta_z
//       q: [22 numbers]   # eq 5.2 (rad), kinematic_model.h order
//       r: [12 numbers]   # eq 5.3 (m)
//       # optional (BodyShape; default: standingModel of the stature the legs imply):
//       proximal_radius: [12], distal_radius: [12], shoulder_half_width, shoulder_drop,
//       hip_half_width, hip_rise
#pragma once

#include <body_gait_model/gait_cycle.h>

#include <string>

namespace body_gait {

// Throws std::runtime_error naming the file, the pose, the key and the fix on an unreadable
// file, a missing or unknown key, or an array of the wrong length.
RepresentativePoses loadRepresentativePoses(const std::string& path);
// Writes every key (the shape included); throws std::runtime_error if the file cannot be written.
void saveRepresentativePoses(const std::string& path, const RepresentativePoses& poses);

}  // namespace body_gait
