// gait_id_node's inputs: an EnrollSubject request (bytes -> ROS deserialization -> onEnroll's
// path up to the database: fromMsg of each pose, representativePoses, trainingPoses), an
// Identify request (-> fromMsg -> gaitFeatures), and the files: a models file (what
// gait_gallery enroll imports) and a feature noise file.
#include <body_gait_id/enrollment.h>
#include <body_gait_id/feature_noise_file.h>
#include <body_gait_id/gait_features.h>
#include <body_gait_id/models_file.h>
#include <body_gait_model/ros/body_model_msg.h>
#include <body_scan_driver/fuzz_target.h>
#include <body_scan_msgs/EnrollSubject.h>
#include <body_scan_msgs/Identify.h>

#include <cstdlib>

using namespace body_gait_id;
namespace fuzz = body_scan_driver::fuzz;

namespace {

// What an enrolment makes of four poses before it writes them.
void enrolPoses(const std::vector<body_gait_model::BodyModel>& models) {
  const std::vector<PoseRecord> poses = trainingPoses(representativePoses(models));
  for (const PoseRecord& pose : poses) gaitFeatures(pose.model);
}

}  // namespace

BODY_SCAN_FUZZ_TARGET(enroll_request) {
  body_scan_msgs::EnrollSubject::Request request;
  if (!fuzz::deserialize(data, size, request)) return 0;
  try {
    std::vector<body_gait_model::BodyModel> models;
    for (const auto& pose : request.poses) models.push_back(body_gait_model::fromMsg(pose));
    enrolPoses(models);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

BODY_SCAN_FUZZ_TARGET(identify_request) {
  body_scan_msgs::Identify::Request request;
  if (!fuzz::deserialize(data, size, request)) return 0;
  try {
    for (View view : {View::k3D, View::kFrontal, View::kSide})
      gaitFeatures(body_gait_model::fromMsg(request.model), view);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

BODY_SCAN_FUZZ_TARGET(gallery_import) {
  try {
    enrolPoses(readBodyModels(fuzz::inputFile("gallery_import", data, size, ".yaml")));
  } catch (const std::exception&) {
  }
  return 0;
}

BODY_SCAN_FUZZ_TARGET(feature_noise) {
  try {
    readFeatureNoise(fuzz::inputFile("feature_noise", data, size, ".yaml"));
  } catch (const std::exception&) {
  }
  return 0;
}
