// Body models in YAML (the CLI's enrolment input and the gallery export):
//
//   poses:            # for enrolment: s1, s2, s3, s4 (thesis 5.3 order)
//     - p: [6 values]   # eq 5.1: tau_x, tau_y, tau_z (m), theta_x, theta_y, theta_z (rad)
//       q: [22 values]  # eq 5.2 (rad), kinematic_model.h order
//       r: [12 values]  # eq 5.3 (m)
//       # optional shape (default: the shape of standingModel(1.70)):
//       proximal_radius: [12], distal_radius: [12]
//       shoulder_half_width: 0.18, shoulder_drop: 0.06, hip_half_width: 0.09, hip_rise: 0.05
//
// or BodyModel messages one per YAML document, as `rostopic echo -n 4 /body_gait/model > f.yaml`
// writes them (the message has the same keys; its other fields are ignored).
#pragma once

#include <body_gait_id/gallery_database.h>
#include <body_gait_model/kinematic_model.h>

#include <ostream>
#include <string>
#include <vector>

namespace body_gait_id {

// Throws std::runtime_error naming the file, the pose and the key that is missing or has the
// wrong length.
std::vector<body_gait::BodyModel> readBodyModels(const std::string& path);
void writeBodyModels(std::ostream& out, const std::vector<body_gait::BodyModel>& models);

// The whole gallery: subjects, scans, poses with models and 3D features, the 3D statistics.
void exportGalleryYaml(const GalleryDatabase& db, std::ostream& out);
// One row per pose: subject_id, name, sequence, frame, q0..q21, r0..r11 (3D features).
void exportGalleryCsv(const GalleryDatabase& db, std::ostream& out);

}  // namespace body_gait_id
