#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/ros/gait_sequence_msg.h>

#include <stdexcept>

namespace body_gait {

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
  return cycle;
}

}  // namespace body_gait
