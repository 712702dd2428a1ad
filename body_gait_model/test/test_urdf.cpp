// The generated URDF: a well-formed tree with Table 5.2 limits, whose joint chain posed with q
// (joint_states order of urdfJointNames) puts every segment where forwardKinematics does.
#include <body_gait_model/urdf.h>
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <map>
#include <sstream>

namespace body_gait_model {
namespace {

Eigen::Vector3d parseVector(const char* text) {
  std::istringstream in(text ? text : "");
  Eigen::Vector3d v;
  in >> v.x() >> v.y() >> v.z();
  return v;
}

struct UrdfJoint {
  std::string name, parent, child, type;
  Eigen::Vector3d origin, axis;
  double lower = 0, upper = 0;
};

TEST(Urdf, IsATreeThatPosesLikeForwardKinematics) {
  BodyModel model = standingModel(1.8);
  model.setJointAngles(kRightUpperArm, 0.3, -0.1);
  model.setJointAngles(kRightLowerArm, 0.6, 0.05);
  model.setJointAngles(kLeftUpperLeg, -0.5, 0.1);
  model.setJointAngles(kLeftLowerLeg, 0.4, 0);
  model.setJointAngles(kHead, 0.2, -0.3);
  model.setJointAngles(kUpperTorso, 0.1, 0.05);
  const std::string text = modelUrdf(model, "subject");

  tinyxml2::XMLDocument document;
  ASSERT_EQ(document.Parse(text.c_str()), tinyxml2::XML_SUCCESS) << text;
  const tinyxml2::XMLElement* robot = document.FirstChildElement("robot");
  ASSERT_NE(robot, nullptr);
  EXPECT_STREQ(robot->Attribute("name"), "subject");
  std::map<std::string, int> links;
  for (auto* link = robot->FirstChildElement("link"); link; link = link->NextSiblingElement("link"))
    ++links[link->Attribute("name")];
  EXPECT_EQ(links.size(), 1u + 12u + 11u);  // body, segments, one middle link per 2-DOF joint
  std::map<std::string, UrdfJoint> by_child;
  std::map<std::string, int> child_count;
  for (auto* joint = robot->FirstChildElement("joint"); joint;
       joint = joint->NextSiblingElement("joint")) {
    UrdfJoint j;
    j.name = joint->Attribute("name");
    j.type = joint->Attribute("type");
    j.parent = joint->FirstChildElement("parent")->Attribute("link");
    j.child = joint->FirstChildElement("child")->Attribute("link");
    j.origin = parseVector(joint->FirstChildElement("origin")->Attribute("xyz"));
    if (auto* axis = joint->FirstChildElement("axis")) j.axis = parseVector(axis->Attribute("xyz"));
    if (auto* limit = joint->FirstChildElement("limit")) {
      j.lower = limit->DoubleAttribute("lower");
      j.upper = limit->DoubleAttribute("upper");
    }
    EXPECT_EQ(links.count(j.parent), 1u) << j.name << " has an unknown parent " << j.parent;
    EXPECT_EQ(links.count(j.child), 1u) << j.name << " has an unknown child " << j.child;
    ++child_count[j.child];
    by_child[j.child] = j;
  }
  EXPECT_EQ(by_child.size(), links.size() - 1);  // every link but the root has one parent
  for (const auto& [child, count] : child_count) EXPECT_EQ(count, 1) << child;
  EXPECT_EQ(links.count("body"), 1u);
  EXPECT_EQ(by_child.count("body"), 0u);

  // Table 5.2 limits on the revolute joints.
  EXPECT_NEAR(by_child["right_upper_arm_x_link"].upper, jointLimits(kRightUpperArm).x_max, 1e-8);
  EXPECT_NEAR(by_child["left_lower_leg"].lower, jointLimits(kLeftLowerLeg).z_min, 1e-8);

  // Pose the URDF chain with q by joint name and compare every segment origin with FK (in the
  // whole-body frame).
  const std::vector<std::string> names = urdfJointNames();
  ASSERT_EQ(names.size(), 22u);
  std::map<std::string, double> position;
  for (size_t i = 0; i < names.size(); ++i) position[names[i]] = model.q[i];
  const PosedModel posed = forwardKinematics(model);
  for (int segment = 0; segment < kSegmentCount; ++segment) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    std::string link = segmentInfo(segment).name;
    while (link != "body") {
      const UrdfJoint& j = by_child.at(link);
      Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
      step.translation() = j.origin;
      if (j.type == "revolute")
        step.linear() = Eigen::AngleAxisd(position.at(j.name), j.axis).toRotationMatrix();
      pose = step * pose;
      link = j.parent;
    }
    const Eigen::Isometry3d expected = posed.whole_body.inverse() * posed.segments[segment].frame;
    EXPECT_LT((pose.matrix() - expected.matrix()).norm(), 1e-9) << segmentInfo(segment).name;
  }
}

}  // namespace
}  // namespace body_gait_model
