// Plays a reconstructed gait cycle (thesis 5.6, 5.8.2) so rviz animates it. Fits nothing: the 4
// representative poses come from a YAML file (gait_poses_file.h) or from a simulated walking
// person read off the simulator's skeleton (modelFromSkeleton; evaluation library).
// Topics and parameters: body_gait_model/README.md.
#include <body_gait_model/eval/gait_subjects.h>
#include <body_gait_model/eval/skeleton_model.h>
#include <body_gait_model/gait_cycle.h>
#include <body_gait_model/gait_poses_file.h>
#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/ros/gait_sequence_msg.h>
#include <body_gait_model/urdf.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <map>
#include <stdexcept>
#include <string>

namespace {

using body_gait_model::RepresentativePoses;

body_gait_model::GaitSet gaitSetNamed(const std::string& name) {
  const std::map<std::string, body_gait_model::GaitSet> sets = {
      {"eta1", body_gait_model::GaitSet::kEta1},
      {"eta2", body_gait_model::GaitSet::kEta2},
      {"eta3", body_gait_model::GaitSet::kEta3}};
  const auto found = sets.find(name);
  if (found == sets.end())
    throw std::invalid_argument("~gait_set '" + name +
                                "' is unknown; use eta1 {s1,sb2,s3,sb4}, eta2 {sb1,s2,sb3,s4} "
                                "or eta3 {s1,s2,s3,s4} (thesis 5.8.3)");
  return found->second;
}

// The 4 poses of walk `trial` of simulated person `person`, straight from the true skeleton.
RepresentativePoses simulatedWalk(int person, std::uint32_t seed, int trial, double heading,
                                  std::string& name) {
  if (person < 0 || person > 9999)
    throw std::invalid_argument("~person must be 0..9999, got " + std::to_string(person));
  const auto people = body_gait_model::eval::simulatedPeople(person + 1, seed);
  name = people[person].name;
  RepresentativePoses poses;
  for (int index = 1; index <= 4; ++index)
    poses[index - 1] = body_gait_model::eval::modelFromSkeleton(
        body_gait_model::eval::walkingSubject(people[person], index, trial, heading));
  return poses;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "play_gait_cycle");
  ros::NodeHandle nh, pnh("~");
  const std::string poses_file = pnh.param<std::string>("poses_file", "");
  const std::string save_file = pnh.param<std::string>("save_poses_file", "");
  const std::string world_frame = pnh.param<std::string>("world_frame", "world");
  const std::string link_prefix = pnh.param<std::string>("link_prefix", "body_gait/");
  const double frame_rate = pnh.param("frame_rate", 10.0);
  const int cycles = pnh.param("cycles", 3);
  const double filmstrip_spacing = pnh.param("filmstrip_spacing", 0.45);
  const double filmstrip_left = pnh.param("filmstrip_left", 1.2);
  if (!(frame_rate > 0) || cycles < 1) {
    ROS_ERROR("~frame_rate must be > 0 Hz and ~cycles >= 1 (got %g, %d)", frame_rate, cycles);
    return 1;
  }

  body_gait_model::GaitCycle cycle;
  std::string subject;
  try {
    RepresentativePoses poses;
    if (!poses_file.empty()) {
      poses = body_gait_model::loadRepresentativePoses(poses_file);
      subject = pnh.param<std::string>("subject", "");
    } else {
      poses = simulatedWalk(pnh.param("person", 0), pnh.param("seed", 1), pnh.param("trial", 0),
                            pnh.param("heading", 0.0), subject);
    }
    if (!save_file.empty()) {
      body_gait_model::saveRepresentativePoses(save_file, poses);
      ROS_INFO("wrote the 4 poses to %s", save_file.c_str());
    }
    poses =
        body_gait_model::gaitSet(poses, gaitSetNamed(pnh.param<std::string>("gait_set", "eta3")));
    cycle = body_gait_model::reconstructGaitCycle(poses);
  } catch (const std::exception& e) {
    ROS_ERROR("no gait cycle to play: %s", e.what());
    return 1;
  }

  ros::Publisher sequence_pub =
      nh.advertise<body_scan_msgs::GaitSequence>("body_gait/gait_sequence", 1, true);
  ros::Publisher filmstrip_pub =
      nh.advertise<visualization_msgs::MarkerArray>("body_gait/gait_sequence_markers", 1, true);
  ros::Publisher model_pub = nh.advertise<body_scan_msgs::BodyModel>("body_gait/model", 2, true);
  ros::Publisher marker_pub =
      nh.advertise<visualization_msgs::MarkerArray>("body_gait/markers", 2, true);
  ros::Publisher joint_pub = nh.advertise<sensor_msgs::JointState>("body_gait/joint_states", 2);
  tf2_ros::TransformBroadcaster tf;
  std_msgs::Header header;
  header.frame_id = world_frame;
  header.stamp = ros::Time::now();
  sequence_pub.publish(body_gait_model::toMsg(cycle, header, subject));
  if (filmstrip_spacing > 0) {
    // To the walker's left: up x direction.
    const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(cycle.velocity.normalized());
    filmstrip_pub.publish(body_gait_model::gaitSequenceMarkers(cycle, header, filmstrip_spacing,
                                                               filmstrip_left * left));
  }
  // r and the shape are the same in every frame (eq 5.13): one URDF for the whole cycle.
  nh.setParam("robot_description",
              body_gait_model::modelUrdf(cycle.frames[0], "body_gait", link_prefix));
  ROS_INFO("gait cycle of %s: stride %.2f m, %.3f m per frame, %d frames at %.1f Hz",
           subject.empty() ? "the given poses" : subject.c_str(), cycle.stride_length,
           cycle.velocity.norm(), body_gait_model::kGaitCycleFrames, frame_rate);

  ros::Rate rate(frame_rate);
  for (long step = 0; ros::ok(); ++step) {
    const int frame = static_cast<int>(step % body_gait_model::kGaitCycleFrames);  // 0-based
    const long walked =
        (step / body_gait_model::kGaitCycleFrames) % cycles;  // cycles walked so far
    body_gait_model::BodyModel model = cycle.frames[frame];
    model.p.head<3>() += walked * body_gait_model::kGaitCycleFrames * cycle.velocity;
    header.stamp = ros::Time::now();
    model_pub.publish(body_gait_model::toMsg(model, header));
    marker_pub.publish(body_gait_model::modelMarkers(model, false, header));
    joint_pub.publish(body_gait_model::jointStates(model, header));
    tf.sendTransform(body_gait_model::modelTransforms(model, header, link_prefix));
    ros::spinOnce();
    rate.sleep();
  }
  return 0;
}
