// ROS side of the body model (not part of the ROS-agnostic core): clouds in and out of
// PointCloud2, the BodyModel message, markers and the TF frames of a fitted model.
#pragma once

#include <body_gait_model/body_fitter.h>
#include <body_scan_msgs/BodyModel.h>
#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

namespace body_gait_model {

// The finite x, y, z points of a cloud (FLOAT32 or FLOAT64 fields, any point layout). Throws
// std::invalid_argument naming the problem when x, y or z is missing or the buffer is short.
Cloud cloudFromMsg(const sensor_msgs::PointCloud2& msg);
// An unorganized FLOAT32 xyz cloud (tests, tools).
sensor_msgs::PointCloud2 cloudToMsg(const Cloud& cloud, const std_msgs::Header& header);

// A model with no fit behind it (gait cycles, simulated truth): the fit-quality fields stay
// zero, points_per_segment empty.
body_scan_msgs::BodyModel toMsg(const BodyModel& model, const std_msgs::Header& header);
// A fitted model with its fit quality.
body_scan_msgs::BodyModel toMsg(const BodyFit& fit, const std_msgs::Header& header,
                                double fit_seconds);
// The model a message describes; throws std::invalid_argument when an array has the wrong size.
BodyModel fromMsg(const body_scan_msgs::BodyModel& msg);

// Tapered cylinders of the 12 segments (triangle meshes, namespace "segments") and the joint
// centres (spheres, "joints"), green, or red for a low-quality fit.
visualization_msgs::MarkerArray modelMarkers(const BodyModel& model, bool low_quality,
                                             const std_msgs::Header& header);

// The frames of modelUrdf(model, ..., link_prefix) posed by forward kinematics: header.frame_id
// -> <prefix>body, and every link (segments and their "_x_link"s) from its URDF parent. What
// robot_state_publisher would publish for jointStates(); used because it is not installed.
std::vector<geometry_msgs::TransformStamped> modelTransforms(const BodyModel& model,
                                                             const std_msgs::Header& header,
                                                             const std::string& link_prefix);
// q as positions of urdfJointNames().
sensor_msgs::JointState jointStates(const BodyModel& model, const std_msgs::Header& header);

}  // namespace body_gait_model
