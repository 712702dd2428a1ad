#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/urdf.h>
#include <body_scan_driver/ros/conversions.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;

geometry_msgs::Point point(const Eigen::Vector3d& v) {
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

geometry_msgs::Transform transform(const Eigen::Isometry3d& pose) {
  geometry_msgs::Transform t;
  t.translation.x = pose.translation().x();
  t.translation.y = pose.translation().y();
  t.translation.z = pose.translation().z();
  const Eigen::Quaterniond q(pose.rotation());
  t.rotation.x = q.x();
  t.rotation.y = q.y();
  t.rotation.z = q.z();
  t.rotation.w = q.w();
  return t;
}

std::vector<double> vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

}  // namespace

Cloud cloudFromMsg(const sensor_msgs::PointCloud2& msg) {
  int64_t offset[3] = {-1, -1, -1};  // 64 bits: a field's offset is any uint32
  int type[3] = {0, 0, 0};
  const char* names[3] = {"x", "y", "z"};
  for (const auto& field : msg.fields)
    for (int i = 0; i < 3; ++i)
      if (field.name == names[i]) {
        offset[i] = field.offset;
        type[i] = field.datatype;
      }
  for (int i = 0; i < 3; ++i) {
    if (offset[i] < 0)
      throw std::invalid_argument(std::string("the cloud has no '") + names[i] +
                                  "' field; publish x, y, z (FLOAT32 or FLOAT64)");
    if (type[i] != sensor_msgs::PointField::FLOAT32 && type[i] != sensor_msgs::PointField::FLOAT64)
      throw std::invalid_argument(std::string("the cloud's '") + names[i] +
                                  "' field is not FLOAT32 or FLOAT64");
    const int size = type[i] == sensor_msgs::PointField::FLOAT32 ? 4 : 8;
    if (offset[i] + size > static_cast<int64_t>(msg.point_step))
      throw std::invalid_argument("the cloud's point_step " + std::to_string(msg.point_step) +
                                  " is shorter than its '" + names[i] + "' field's end");
  }
  if (msg.is_bigendian)
    throw std::invalid_argument("big-endian clouds are not supported; publish little-endian");
  const size_t count = static_cast<size_t>(msg.width) * msg.height;
  if (msg.row_step < static_cast<uint64_t>(msg.width) * msg.point_step)
    throw std::invalid_argument("the cloud's row_step is less than width * point_step");
  if (msg.data.size() < static_cast<uint64_t>(msg.row_step) * msg.height)
    throw std::invalid_argument("the cloud's data is shorter than row_step * height");
  Cloud cloud;
  cloud.reserve(count);
  for (uint32_t row = 0; row < msg.height; ++row)
    for (uint32_t column = 0; column < msg.width; ++column) {
      const uint8_t* p =
          msg.data.data() + static_cast<size_t>(row) * msg.row_step + column * msg.point_step;
      Eigen::Vector3d v;
      for (int i = 0; i < 3; ++i) {
        if (type[i] == sensor_msgs::PointField::FLOAT32) {
          float f;
          std::memcpy(&f, p + offset[i], 4);
          v[i] = f;
        } else {
          std::memcpy(&v[i], p + offset[i], 8);
        }
      }
      if (v.allFinite()) cloud.push_back(v);
    }
  return cloud;
}

sensor_msgs::PointCloud2 cloudToMsg(const Cloud& cloud, const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 msg;
  msg.header = header;
  body_scan_driver::layoutFloatCloud(msg, static_cast<uint32_t>(cloud.size()), 1, /*rgb=*/false);
  msg.is_dense = true;
  float* out = reinterpret_cast<float*>(msg.data.data());
  for (const auto& p : cloud)
    for (int i = 0; i < 3; ++i) *out++ = static_cast<float>(p[i]);
  return msg;
}

body_scan_msgs::BodyModel toMsg(const BodyModel& model, const std_msgs::Header& header) {
  body_scan_msgs::BodyModel msg;
  msg.header = header;
  msg.p = vector(model.p);
  msg.q = vector(model.q);
  msg.r = vector(model.r);
  for (int s = 0; s < kSegmentCount; ++s) {
    msg.segment_names.push_back(segmentInfo(s).name);
    msg.proximal_radius.push_back(model.shape.proximal_radius[s]);
    msg.distal_radius.push_back(model.shape.distal_radius[s]);
  }
  msg.shoulder_half_width = model.shape.shoulder_half_width;
  msg.shoulder_drop = model.shape.shoulder_drop;
  msg.hip_half_width = model.shape.hip_half_width;
  msg.hip_rise = model.shape.hip_rise;
  msg.hip_back = model.shape.hip_back;
  return msg;
}

body_scan_msgs::BodyModel toMsg(const BodyFit& fit, const std_msgs::Header& header,
                                double fit_seconds) {
  body_scan_msgs::BodyModel msg = toMsg(fit.model, header);
  msg.points_per_segment.assign(fit.quality.points_per_segment.begin(),
                                fit.quality.points_per_segment.end());
  msg.rms_distance = fit.quality.rms_distance;
  msg.explained_fraction = fit.quality.explained_fraction;
  msg.low_quality = fit.quality.low_quality;
  msg.reason = fit.quality.reason;
  msg.fit_seconds = fit_seconds;
  return msg;
}

BodyModel fromMsg(const body_scan_msgs::BodyModel& msg) {
  auto check = [](const std::vector<double>& v, size_t size, const char* name) {
    if (v.size() != size)
      throw std::invalid_argument(std::string("BodyModel.") + name + " has " +
                                  std::to_string(v.size()) + " elements, not " +
                                  std::to_string(size));
  };
  check(msg.p, 6, "p");
  check(msg.q, 22, "q");
  check(msg.r, 12, "r");
  check(msg.proximal_radius, 12, "proximal_radius");
  check(msg.distal_radius, 12, "distal_radius");
  auto finite = [](const std::vector<double>& v, const char* name) {
    for (size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i]))
        throw std::invalid_argument(std::string("BodyModel.") + name + "[" + std::to_string(i) +
                                    "] is not finite");
  };
  finite(msg.p, "p");
  finite(msg.q, "q");
  finite(msg.r, "r");
  finite(msg.proximal_radius, "proximal_radius");
  finite(msg.distal_radius, "distal_radius");
  finite({msg.shoulder_half_width}, "shoulder_half_width");
  finite({msg.shoulder_drop}, "shoulder_drop");
  finite({msg.hip_half_width}, "hip_half_width");
  finite({msg.hip_rise}, "hip_rise");
  finite({msg.hip_back}, "hip_back");
  BodyModel model;
  model.p = Eigen::Map<const PoseVector>(msg.p.data());
  model.q = Eigen::Map<const JointAngles>(msg.q.data());
  model.r = Eigen::Map<const SegmentLengths>(msg.r.data());
  for (int s = 0; s < kSegmentCount; ++s) {
    model.shape.proximal_radius[s] = msg.proximal_radius[s];
    model.shape.distal_radius[s] = msg.distal_radius[s];
  }
  model.shape.shoulder_half_width = msg.shoulder_half_width;
  model.shape.shoulder_drop = msg.shoulder_drop;
  model.shape.hip_half_width = msg.hip_half_width;
  model.shape.hip_rise = msg.hip_rise;
  model.shape.hip_back = msg.hip_back;
  return model;
}

visualization_msgs::MarkerArray modelMarkers(const BodyModel& model, bool low_quality,
                                             const std_msgs::Header& header) {
  const PosedModel posed = forwardKinematics(model);
  std_msgs::ColorRGBA colour;
  colour.r = low_quality ? 0.9f : 0.1f;
  colour.g = low_quality ? 0.1f : 0.8f;
  colour.b = 0.1f;
  colour.a = 0.6f;
  visualization_msgs::MarkerArray markers;
  constexpr int kSides = 16;
  for (int s = 0; s < kSegmentCount; ++s) {
    const PosedSegment& segment = posed.segments[s];
    visualization_msgs::Marker marker;
    marker.header = header;
    marker.ns = "segments";
    marker.id = s;
    marker.type = visualization_msgs::Marker::TRIANGLE_LIST;
    marker.action = visualization_msgs::Marker::ADD;
    marker.pose.orientation.w = 1;
    marker.scale.x = marker.scale.y = marker.scale.z = 1;
    marker.color = colour;
    // Two rings around the axis (radial directions from the segment frame's x and z axes).
    const Eigen::Vector3d ex = segment.frame.linear().col(0), ez = segment.frame.linear().col(2);
    auto ring = [&](const Eigen::Vector3d& centre, double radius, int k) {
      const double angle = 2 * kPi * k / kSides;
      return centre + radius * (std::cos(angle) * ex + std::sin(angle) * ez);
    };
    for (int k = 0; k < kSides; ++k) {
      const Eigen::Vector3d a0 = ring(segment.proximal, segment.proximal_radius, k),
                            a1 = ring(segment.proximal, segment.proximal_radius, k + 1),
                            b0 = ring(segment.distal, segment.distal_radius, k),
                            b1 = ring(segment.distal, segment.distal_radius, k + 1);
      for (const Eigen::Vector3d* v : {&a0, &b0, &a1, &a1, &b0, &b1})
        marker.points.push_back(point(*v));
      // End caps
      for (const Eigen::Vector3d* v : {&segment.proximal, &a1, &a0, &segment.distal, &b0, &b1})
        marker.points.push_back(point(*v));
    }
    markers.markers.push_back(marker);
  }
  visualization_msgs::Marker joints;
  joints.header = header;
  joints.ns = "joints";
  joints.id = 0;
  joints.type = visualization_msgs::Marker::SPHERE_LIST;
  joints.action = visualization_msgs::Marker::ADD;
  joints.pose.orientation.w = 1;
  joints.scale.x = joints.scale.y = joints.scale.z = 0.05;
  joints.color = colour;
  joints.color.a = 1.0f;
  joints.color.b = 0.9f;  // bluish tint: visible against the cylinders
  for (const char* name :
       {"neck_base", "head_base", "head_top", "waist", "right_shoulder", "right_elbow",
        "right_hand_tip", "left_shoulder", "left_elbow", "left_hand_tip", "right_hip", "right_knee",
        "right_sole", "left_hip", "left_knee", "left_sole"})
    joints.points.push_back(point(posed.joint(name)));
  markers.markers.push_back(joints);
  return markers;
}

std::vector<geometry_msgs::TransformStamped> modelTransforms(const BodyModel& model,
                                                             const std_msgs::Header& header,
                                                             const std::string& link_prefix) {
  const PosedModel posed = forwardKinematics(model);
  std::vector<geometry_msgs::TransformStamped> transforms;
  auto add = [&](const std::string& parent, const std::string& child,
                 const Eigen::Isometry3d& pose) {
    geometry_msgs::TransformStamped t;
    t.header.stamp = header.stamp;
    t.header.frame_id = parent;
    t.child_frame_id = child;
    t.transform = transform(pose);
    transforms.push_back(t);
  };
  add(header.frame_id, link_prefix + "body", posed.whole_body);
  for (int s = 0; s < kSegmentCount; ++s) {
    const SegmentInfo& info = segmentInfo(s);
    const Eigen::Isometry3d parent =
        info.parent == kWholeBody ? posed.whole_body : posed.segments[info.parent].frame;
    const std::string parent_name =
        link_prefix + (info.parent == kWholeBody ? "body" : segmentInfo(info.parent).name);
    const Eigen::Isometry3d local = parent.inverse() * posed.segments[s].frame;
    if (info.fixed) {
      add(parent_name, link_prefix + info.name, local);
      continue;
    }
    // The URDF's two revolute joints: Rx(theta_x) into "<segment>_x_link", then Rz(theta_z).
    const Eigen::Isometry3d rz(Eigen::AngleAxisd(model.thetaZ(s), Eigen::Vector3d::UnitZ()));
    const std::string middle = link_prefix + info.name + "_x_link";
    add(parent_name, middle, local * rz.inverse());
    add(middle, link_prefix + info.name, rz);
  }
  return transforms;
}

sensor_msgs::JointState jointStates(const BodyModel& model, const std_msgs::Header& header) {
  sensor_msgs::JointState state;
  state.header = header;
  state.name = urdfJointNames();
  state.position = vector(model.q);
  return state;
}

}  // namespace body_gait_model
