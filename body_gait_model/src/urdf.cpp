// URDF text of a body model (for robot_state_publisher).
#include <body_gait_model/urdf.h>

#include <iomanip>
#include <sstream>

namespace body_gait_model {
namespace {

std::string xyz(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << std::setprecision(9) << v.x() << " " << v.y() << " " << v.z();
  return out.str();
}

}  // namespace

std::vector<std::string> urdfJointNames() {
  std::vector<std::string> names;
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    if (segmentInfo(segment).fixed) continue;
    names.push_back(std::string(segmentInfo(segment).name) + "_x");
    names.push_back(std::string(segmentInfo(segment).name) + "_z");
  }
  return names;
}

std::string modelUrdf(const BodyModel& model, const std::string& robot_name,
                      const std::string& link_prefix) {
  std::ostringstream urdf;
  urdf << std::setprecision(9);
  urdf << "<?xml version=\"1.0\"?>\n<robot name=\"" << robot_name << "\">\n";
  urdf << "  <link name=\"" << link_prefix << "body\"/>\n";
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    const SegmentInfo& info = segmentInfo(segment);
    const std::string name = info.name;
    const std::string parent =
        link_prefix + (info.parent == kWholeBody ? "body" : segmentInfo(info.parent).name);
    const double length = model.r[segment];
    const double radius =
        (model.shape.proximal_radius[segment] + model.shape.distal_radius[segment]) / 2;
    const double direction = info.points_up ? 1.0 : -1.0;
    // The URDF cylinder runs along its z: turn it onto the segment's y axis, centred mid-length.
    urdf << "  <link name=\"" << link_prefix << name << "\">\n"
         << "    <visual>\n"
         << "      <origin xyz=\"0 " << direction * length / 2
         << " 0\" rpy=\"1.5707963267949 0 0\"/>\n"
         << "      <geometry><cylinder radius=\"" << radius << "\" length=\"" << length
         << "\"/></geometry>\n"
         << "    </visual>\n"
         << "  </link>\n";
    const std::string origin = xyz(jointOffset(model, segment));
    if (info.fixed) {
      urdf << "  <joint name=\"" << name << "_fixed\" type=\"fixed\">\n"
           << "    <parent link=\"" << parent << "\"/>\n"
           << "    <child link=\"" << link_prefix << name << "\"/>\n"
           << "    <origin xyz=\"" << origin << "\" rpy=\"0 0 0\"/>\n"
           << "  </joint>\n";
      continue;
    }
    const JointLimits limits = jointLimits(segment);
    const std::string middle = link_prefix + name + "_x_link";
    urdf << "  <link name=\"" << middle << "\"/>\n"
         << "  <joint name=\"" << name << "_x\" type=\"revolute\">\n"
         << "    <parent link=\"" << parent << "\"/>\n"
         << "    <child link=\"" << middle << "\"/>\n"
         << "    <origin xyz=\"" << origin << "\" rpy=\"0 0 0\"/>\n"
         << "    <axis xyz=\"1 0 0\"/>\n"
         << "    <limit lower=\"" << limits.x_min << "\" upper=\"" << limits.x_max
         << "\" effort=\"0\" velocity=\"0\"/>\n"
         << "  </joint>\n"
         << "  <joint name=\"" << name << "_z\" type=\"revolute\">\n"
         << "    <parent link=\"" << middle << "\"/>\n"
         << "    <child link=\"" << link_prefix << name << "\"/>\n"
         << "    <origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n"
         << "    <axis xyz=\"0 0 1\"/>\n"
         << "    <limit lower=\"" << limits.z_min << "\" upper=\"" << limits.z_max
         << "\" effort=\"0\" velocity=\"0\"/>\n"
         << "  </joint>\n";
  }
  urdf << "</robot>\n";
  return urdf.str();
}

}  // namespace body_gait_model
