// URDF of a fitted body model for robot_state_publisher (string output, no ROS dependency).
#pragma once

#include <body_gait_model/kinematic_model.h>

#include <string>
#include <vector>

namespace body_gait_model {

// Names of the URDF's revolute joints in the order of q (eq 5.2): "<segment>_x", "<segment>_z"
// for every segment but the fixed neck. A joint_states message with these names and q as
// positions poses the URDF like forwardKinematics.
std::vector<std::string> urdfJointNames();

// The model as a URDF: root link "body" (the whole-body frame of p, which a tf broadcaster
// publishes; URDF has no 6-DOF joint for robot_state_publisher), one link per segment with a
// cylinder visual (mean of its two radii; length l^r from r), each 2-DOF joint as two revolute
// joints (about x, then z, through a massless "<segment>_x_link") with the limits of Table 5.2,
// and a fixed joint for the neck. link_prefix (e.g. "body_gait/") prefixes every link name.
std::string modelUrdf(const BodyModel& model, const std::string& robot_name = "body",
                      const std::string& link_prefix = "");

}  // namespace body_gait_model
