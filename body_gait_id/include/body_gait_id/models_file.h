// Body models in YAML (the CLI's enrolment input and the fit cache: body_gait_model's
// gait_poses_file.h owns the format) and the gallery export.
#pragma once

#include <body_gait_id/gallery_database.h>
#include <body_gait_model/kinematic_model.h>

#include <ostream>
#include <string>
#include <vector>

namespace body_gait_id {

// body_gait_model::loadBodyModels (a `poses:` list or BodyModel messages, one per document); throws
// std::runtime_error naming the file, the pose and the key that is missing or has the wrong
// length.
std::vector<body_gait_model::BodyModel> readBodyModels(const std::string& path);
void writeBodyModels(std::ostream& out, const std::vector<body_gait_model::BodyModel>& models);

// The whole gallery: subjects, scans, poses with models and 3D features, the 3D statistics.
void exportGalleryYaml(const GalleryDatabase& db, std::ostream& out);
// One row per pose: subject_id, name, sequence, frame, q0..q21, r0..r11 (3D features).
void exportGalleryCsv(const GalleryDatabase& db, std::ostream& out);

}  // namespace body_gait_id
