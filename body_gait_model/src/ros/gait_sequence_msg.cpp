#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/ros/gait_sequence_msg.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace body_gait_model {

body_scan_msgs::GaitSequence toMsg(const GaitCycle& cycle, const std_msgs::Header& header,
                                   const std::string& subject) {
  body_scan_msgs::GaitSequence msg;
  msg.header = header;
  msg.subject = subject;
  for (const BodyModel& frame : cycle.frames) msg.frames.push_back(toMsg(frame, header));
  msg.representative_frames.assign(kRepresentativeFrames.begin(), kRepresentativeFrames.end());
  msg.velocity.x = cycle.velocity.x();
  msg.velocity.y = cycle.velocity.y();
  msg.velocity.z = cycle.velocity.z();
  msg.stride_length = cycle.stride_length;
  return msg;
}

GaitCycle fromMsg(const body_scan_msgs::GaitSequence& msg) {
  if (msg.frames.size() != static_cast<size_t>(kGaitCycleFrames))
    throw std::invalid_argument("GaitSequence has " + std::to_string(msg.frames.size()) +
                                " frames, not " + std::to_string(kGaitCycleFrames) +
                                " (thesis 5.8.2); publish a whole cycle");
  if (!std::equal(msg.representative_frames.begin(), msg.representative_frames.end(),
                  kRepresentativeFrames.begin(), kRepresentativeFrames.end()))
    throw std::invalid_argument(
        "GaitSequence.representative_frames must be 1, 6, 11, 16 (thesis 5.8.2)");
  GaitCycle cycle;
  for (size_t f = 0; f < msg.frames.size(); ++f) {
    try {
      cycle.frames.push_back(fromMsg(msg.frames[f]));
    } catch (const std::invalid_argument& error) {
      throw std::invalid_argument("GaitSequence frame " + std::to_string(f + 1) + ": " +
                                  error.what());
    }
  }
  cycle.velocity = Eigen::Vector3d(msg.velocity.x, msg.velocity.y, msg.velocity.z);
  cycle.stride_length = msg.stride_length;
  if (!cycle.velocity.allFinite() || !std::isfinite(cycle.stride_length))
    throw std::invalid_argument("GaitSequence.velocity or stride_length is not finite");
  return cycle;
}

visualization_msgs::MarkerArray gaitSequenceMarkers(const GaitCycle& cycle,
                                                    const std_msgs::Header& header, double spacing,
                                                    const Eigen::Vector3d& offset) {
  visualization_msgs::MarkerArray markers;
  const double speed = cycle.velocity.norm();
  const Eigen::Vector3d direction =
      speed > 0 ? Eigen::Vector3d(cycle.velocity / speed) : Eigen::Vector3d::UnitX();
  for (int f = 0; f < static_cast<int>(cycle.frames.size()); ++f) {
    BodyModel model = cycle.frames[f];
    model.p.head<3>() += offset + f * (spacing * direction - cycle.velocity);
    const bool representative =
        std::count(kRepresentativeFrames.begin(), kRepresentativeFrames.end(), f + 1) > 0;
    char prefix[32];
    std::snprintf(prefix, sizeof(prefix), "frame_%02d/", f + 1);
    for (visualization_msgs::Marker& marker : modelMarkers(model, false, header).markers) {
      marker.ns = prefix + marker.ns;
      if (representative) {
        marker.color.g = 0.4f;
        marker.color.b = 0.9f;
      }
      markers.markers.push_back(marker);
    }
  }
  return markers;
}

}  // namespace body_gait_model
