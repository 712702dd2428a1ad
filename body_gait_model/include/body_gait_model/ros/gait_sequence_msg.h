// ROS side of gait reconstruction: a GaitCycle (gait_cycle.h) in and out of the GaitSequence
// message (not part of the ROS-agnostic core).
#pragma once

#include <body_gait_model/gait_cycle.h>
#include <body_scan_msgs/GaitSequence.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>

namespace body_gait_model {

// Every frame gets the sequence's header; representative_frames = kRepresentativeFrames.
body_scan_msgs::GaitSequence toMsg(const GaitCycle& cycle, const std_msgs::Header& header,
                                   const std::string& subject = "");
// The cycle a message describes. Throws std::invalid_argument naming the problem when it does
// not hold kGaitCycleFrames frames, its representative frames are not 1, 6, 11, 16 or a frame's
// arrays have the wrong sizes.
GaitCycle fromMsg(const body_scan_msgs::GaitSequence& msg);

// All frames at once, like the thesis's Fig 5.6: frame f's model (modelMarkers, namespaces
// "frame_FF/segments" and "frame_FF/joints") spread `spacing` m apart along the walking
// direction instead of the walked v per frame, the whole row moved by `offset` (world m);
// representative frames blue, interpolated ones green.
visualization_msgs::MarkerArray gaitSequenceMarkers(const GaitCycle& cycle,
                                                    const std_msgs::Header& header,
                                                    double spacing = 0.4,
                                                    const Eigen::Vector3d& offset = {0, 0, 0});

}  // namespace body_gait_model
