// The body fitter's and the gait tools' inputs: a PointCloud2 (bytes -> ROS deserialization ->
// cloudFromMsg, the fitter's reader), a BodyModel and a GaitSequence (-> fromMsg -> the
// kinematics and markers made of them), and the files: gait poses (body-model YAML) and fit
// options.
#include <body_gait_model/fit_options_file.h>
#include <body_gait_model/gait_poses_file.h>
#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/ros/gait_sequence_msg.h>
#include <body_scan_driver/fuzz_target.h>

#include <cstdlib>

using namespace body_gait_model;
namespace fuzz = body_scan_driver::fuzz;

BODY_SCAN_FUZZ_TARGET(point_cloud2) {
  sensor_msgs::PointCloud2 msg;
  if (!fuzz::deserialize(data, size, msg)) return 0;
  try {
    const Cloud cloud = cloudFromMsg(msg);
    for (const auto& point : cloud)
      if (!point.allFinite()) std::abort();  // the reader keeps finite points only
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

BODY_SCAN_FUZZ_TARGET(body_model) {
  body_scan_msgs::BodyModel msg;
  if (!fuzz::deserialize(data, size, msg)) return 0;
  try {
    const BodyModel model = fromMsg(msg);
    forwardKinematics(model);
    modelMarkers(model, msg.low_quality, msg.header);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

BODY_SCAN_FUZZ_TARGET(gait_sequence) {
  body_scan_msgs::GaitSequence msg;
  if (!fuzz::deserialize(data, size, msg)) return 0;
  try {
    const GaitCycle cycle = fromMsg(msg);
    gaitSequenceMarkers(cycle, msg.header);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

BODY_SCAN_FUZZ_TARGET(body_model_yaml) {
  const std::string path = fuzz::inputFile("body_model_yaml", data, size, ".yaml");
  try {
    loadBodyModels(path);
  } catch (const std::exception&) {
  }
  try {
    loadRepresentativePoses(path);
  } catch (const std::exception&) {
  }
  return 0;
}

BODY_SCAN_FUZZ_TARGET(fit_options) {
  try {
    loadFitOptions(fuzz::inputFile("fit_options", data, size, ".yaml"));
  } catch (const std::exception&) {
  }
  return 0;
}
