// The procedural human body: anthropometric ratios, forward kinematics, pose conventions,
// ray-measured shape, and the scene-file reader.
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/human_body.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <set>

namespace body_scan_driver::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;

std::map<std::string, Eigen::Vector3d> jointsByName(const std::vector<SkeletonJoint>& joints) {
  std::map<std::string, Eigen::Vector3d> named;
  for (const SkeletonJoint& joint : joints) named[joint.name] = joint.position;
  return named;
}

std::map<std::string, Eigen::Vector3d> skeleton(const HumanBodySpec& spec) {
  return jointsByName(humanSkeleton(spec));
}

Scene sceneOf(const HumanBodySpec& spec) {
  Scene scene;
  addHumanBody(spec, scene);
  return scene;
}

// First hit of a ray, or nullopt-like (surface == nullptr).
Hit cast(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  Hit hit;
  scene.intersect(Ray{origin, direction.normalized()}, hit);
  return hit;
}

// Perimeter of the body's cross-section through centre, perpendicular to axis, measured by
// rays aimed at the centre from start_radius away (the sections are convex).
double measuredGirth(const Scene& scene, const Eigen::Vector3d& centre, const Eigen::Vector3d& axis,
                     double start_radius) {
  const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.normalized().cross(u);
  const int rays = 720;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < rays; ++i) {
    const double angle = 2 * kPi * i / rays;
    const Eigen::Vector3d outward = std::cos(angle) * u + std::sin(angle) * v;
    const Eigen::Vector3d origin = centre + start_radius * outward;
    const Hit hit = cast(scene, origin, -outward);
    EXPECT_NE(hit.surface, nullptr);
    points.push_back(origin - hit.distance * outward);
  }
  double perimeter = 0;
  for (int i = 0; i < rays; ++i) perimeter += (points[(i + 1) % rays] - points[i]).norm();
  return perimeter;
}

TEST(Anthropometry, FromStatureFollowsTheSegmentRatios) {
  const double h = 1.75;
  const Anthropometry body = Anthropometry::fromStature(h);
  EXPECT_NEAR(body.thigh_length, (0.530 - 0.285) * h, 1e-3);
  EXPECT_NEAR(body.shank_length, (0.285 - 0.039) * h, 1e-3);
  EXPECT_NEAR(body.torso_length, (0.818 - 0.530) * h, 1e-3);
  EXPECT_NEAR(body.ankle_height, 0.039 * h, 1e-3);
  EXPECT_NEAR(body.upper_arm_length, 0.186 * h, 1e-3);
  EXPECT_NEAR(body.forearm_length, 0.146 * h, 1e-3);
  EXPECT_NEAR(body.hand_length, 0.108 * h, 1e-3);
  EXPECT_NEAR(body.head_height, 0.130 * h, 1e-3);
  EXPECT_NEAR(body.foot_length, 0.152 * h, 1e-3);
  EXPECT_NEAR(body.ankle_height + body.shank_length + body.thigh_length + body.torso_length +
                  body.neck_length + body.head_height,
              h, 1e-9);
  // Joint centres lie inside the outer breadths.
  EXPECT_LT(body.shoulder_width, 0.259 * h);
  EXPECT_LT(body.hip_width, 0.191 * h);
  EXPECT_NEAR(body.chest_girth, 0.98, 0.02);
  EXPECT_NEAR(Anthropometry::fromStature(2 * h).calf_girth, 2 * body.calf_girth, 1e-12);
  EXPECT_THROW(Anthropometry::fromStature(0), std::runtime_error);

  HumanBodySpec spec;
  spec.body = body;
  const auto joints = skeleton(spec);
  EXPECT_NEAR(joints.at("left_shoulder").z(), 0.818 * h, 0.01);
  EXPECT_NEAR(joints.at("right_shoulder").z(), 0.818 * h, 0.01);
  EXPECT_NEAR(joints.at("left_hip").z(), 0.530 * h, 0.01);
  EXPECT_NEAR(joints.at("left_knee").z(), 0.285 * h, 0.01);
  EXPECT_NEAR(joints.at("left_ankle").z(), 0.039 * h, 0.01);
  EXPECT_NEAR(joints.at("head_top").z(), h, 0.01);
}

TEST(HumanSkeleton, NamesEveryJointOnce) {
  const auto joints = humanSkeleton(HumanBodySpec{});
  std::set<std::string> names;
  for (const auto& joint : joints) names.insert(joint.name);
  EXPECT_EQ(names.size(), joints.size());
  for (const char* name : {"head_top", "neck", "chest", "pelvis"}) EXPECT_EQ(names.count(name), 1u);
  for (const char* side : {"left_", "right_"}) {
    for (const char* joint :
         {"shoulder", "elbow", "wrist", "hand_tip", "hip", "knee", "ankle", "toe"})
      EXPECT_EQ(names.count(std::string(side) + joint), 1u) << side << joint;
  }
}

TEST(HumanSkeleton, ForwardKinematicsPreservesBoneLengths) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> angle(-kPi / 2, kPi / 2), offset(-2, 2);
  for (int trial = 0; trial < 20; ++trial) {
    HumanBodySpec spec;
    spec.body = Anthropometry::fromStature(1.5 + 0.02 * trial);
    spec.position = {offset(random), offset(random), 0.1 * offset(random)};
    for (double* joint_angle :
         {&spec.pose.heading, &spec.pose.torso_lean, &spec.pose.neck_flexion,
          &spec.pose.left_shoulder_flexion, &spec.pose.left_shoulder_abduction,
          &spec.pose.left_elbow_flexion, &spec.pose.right_shoulder_flexion,
          &spec.pose.right_shoulder_abduction, &spec.pose.right_elbow_flexion,
          &spec.pose.left_hip_flexion, &spec.pose.left_hip_abduction, &spec.pose.left_knee_flexion,
          &spec.pose.right_hip_flexion, &spec.pose.right_hip_abduction,
          &spec.pose.right_knee_flexion})
      *joint_angle = angle(random);
    const Anthropometry& b = spec.body;
    const auto joints = skeleton(spec);
    auto length = [&](const std::string& from, const std::string& to) {
      return (joints.at(from) - joints.at(to)).norm();
    };
    EXPECT_NEAR(length("left_shoulder", "right_shoulder"), b.shoulder_width, 1e-9);
    EXPECT_NEAR(length("left_hip", "right_hip"), b.hip_width, 1e-9);
    EXPECT_NEAR(length("pelvis", "neck"), b.torso_length, 1e-9);
    EXPECT_NEAR(length("neck", "head_top"), b.neck_length + b.head_height, 1e-9);
    for (const std::string side : {"left_", "right_"}) {
      EXPECT_NEAR(length(side + "shoulder", side + "elbow"), b.upper_arm_length, 1e-9);
      EXPECT_NEAR(length(side + "elbow", side + "wrist"), b.forearm_length, 1e-9);
      EXPECT_NEAR(length(side + "wrist", side + "hand_tip"), b.hand_length, 1e-9);
      EXPECT_NEAR(length(side + "hip", side + "knee"), b.thigh_length, 1e-9);
      EXPECT_NEAR(length(side + "knee", side + "ankle"), b.shank_length, 1e-9);
      EXPECT_NEAR((joints.at(side + "hip") - joints.at("pelvis")).norm(), b.hip_width / 2, 1e-9);
    }
  }
}

TEST(HumanSkeleton, PoseAnglesFollowTheConventions) {
  HumanBodySpec standing;
  standing.pose.left_hip_abduction = standing.pose.right_hip_abduction = 0;  // exact sines below
  const auto rest = skeleton(standing);

  HumanBodySpec flexed = standing;
  flexed.pose.left_hip_flexion = 30 * kDegree;
  auto joints = skeleton(flexed);
  EXPECT_NEAR(joints.at("left_knee").x(), standing.body.thigh_length * std::sin(30 * kDegree),
              1e-9);
  EXPECT_LT(joints.at("left_ankle").z(), joints.at("left_knee").z());
  EXPECT_NEAR(joints.at("right_knee").x(), 0, 1e-12);  // the other leg stays put

  flexed.pose.left_knee_flexion = 60 * kDegree;  // the knee bends the shank backward
  joints = skeleton(flexed);
  EXPECT_LT(joints.at("left_ankle").x(), joints.at("left_knee").x());

  flexed.pose.left_shoulder_flexion = 45 * kDegree;  // the arm swings forward...
  flexed.pose.left_elbow_flexion = 90 * kDegree;     // ...and the forearm forward and up
  joints = skeleton(flexed);
  EXPECT_GT(joints.at("left_elbow").x(), rest.at("left_elbow").x() + 0.1);
  EXPECT_GT(joints.at("left_wrist").x(), joints.at("left_elbow").x() + 0.1);
  EXPECT_GT(joints.at("left_wrist").z(), joints.at("left_elbow").z());

  HumanBodySpec abducted = standing;
  abducted.pose.left_shoulder_abduction = abducted.pose.right_shoulder_abduction = kPi / 2;
  joints = skeleton(abducted);
  EXPECT_GT(joints.at("left_hand_tip").y(), 0.7);  // arms out to the sides
  EXPECT_LT(joints.at("right_hand_tip").y(), -0.7);
  EXPECT_NEAR(joints.at("left_hand_tip").z(), joints.at("left_shoulder").z(), 1e-9);

  HumanBodySpec leaning = standing;
  leaning.pose.torso_lean = 20 * kDegree;
  leaning.pose.neck_flexion = 20 * kDegree;
  joints = skeleton(leaning);
  EXPECT_GT(joints.at("neck").x(), 0.1);
  EXPECT_GT(joints.at("head_top").x() - joints.at("neck").x(),
            (leaning.body.neck_length + leaning.body.head_height) * std::sin(35 * kDegree));
  EXPECT_NEAR(joints.at("left_knee").x(), 0, 1e-12);  // the legs stay put

  // Heading 90 deg turns the subject's front to world +y; its left to world -x.
  HumanBodySpec turned = flexed;
  turned.pose.heading = 90 * kDegree;
  turned.position = {1, 2, 0};
  joints = skeleton(turned);
  const Eigen::Vector3d knee = joints.at("left_knee") - turned.position;
  EXPECT_NEAR(knee.y(), turned.body.thigh_length * std::sin(30 * kDegree), 1e-9);
  EXPECT_GT(joints.at("left_toe").y(), joints.at("left_ankle").y());
  EXPECT_LT(joints.at("left_hip").x(), turned.position.x());
  EXPECT_NEAR(joints.at("pelvis").x(), 1, 1e-12);
  EXPECT_NEAR(joints.at("pelvis").y(), 2, 1e-12);
}

TEST(AddHumanBody, BuildsNamedEllipsoidsAndTheSkeleton) {
  HumanBodySpec spec;
  spec.name = "alice";
  const Scene scene = sceneOf(spec);
  std::set<std::string> names;
  for (const auto& surface : scene.surfaces()) {
    EXPECT_NE(dynamic_cast<const Ellipsoid*>(surface.get()), nullptr) << surface->name;
    EXPECT_EQ(surface->name.rfind("alice/", 0), 0u) << surface->name;
    names.insert(surface->name);
  }
  EXPECT_EQ(names.size(), scene.surfaces().size());
  for (const char* segment :
       {"head", "hair", "neck", "chest", "abdomen", "pelvis", "left_upper_arm", "left_forearm",
        "left_hand", "right_thigh", "right_shank", "right_foot", "left_knee", "right_elbow"})
    EXPECT_EQ(names.count(std::string("alice/") + segment), 1u) << segment;
  EXPECT_EQ(scene.skeleton().size(), humanSkeleton(spec).size());
}

TEST(AddHumanBody, RaysMeetTheBodyWhereTheGirthsSay) {
  HumanBodySpec spec;  // 1.75 m, standing at the origin facing +x
  const Scene scene = sceneOf(spec);
  const auto joints = skeleton(spec);
  const Eigen::Vector3d backward(-1, 0, 0);

  const double chest_height = joints.at("chest").z();
  Hit hit = cast(scene, {2, 0, chest_height}, backward);
  ASSERT_NE(hit.surface, nullptr);
  EXPECT_EQ(hit.surface->name, "person/chest");
  const double chest_front = 2 - hit.distance;
  EXPECT_GT(chest_front, 0.08);
  EXPECT_LT(chest_front, 0.2);
  // Depth front to back is below the round-chest bound girth / pi.
  hit = cast(scene, {-2, 0, chest_height}, -backward);
  ASSERT_NE(hit.surface, nullptr);
  const double chest_depth = chest_front - (hit.distance - 2);
  EXPECT_GT(chest_depth, 0.2);
  EXPECT_LT(chest_depth, spec.body.chest_girth / kPi);

  const double waist_height = 0.5 * (joints.at("pelvis").z() + joints.at("chest").z());
  hit = cast(scene, {2, 0, waist_height}, backward);
  ASSERT_NE(hit.surface, nullptr);
  EXPECT_GT(2 - hit.distance, 0.07);
  EXPECT_LT(2 - hit.distance, spec.body.waist_girth / (2 * kPi));

  const Eigen::Vector3d mid_thigh = 0.5 * (joints.at("left_hip") + joints.at("left_knee"));
  hit = cast(scene, {2, mid_thigh.y(), mid_thigh.z()}, backward);
  ASSERT_NE(hit.surface, nullptr);
  EXPECT_EQ(hit.surface->name, "person/left_thigh");
  EXPECT_NEAR(2 - hit.distance, spec.body.thigh_girth / (2 * kPi), 0.005);

  // From above: hair on top of the head, at the stature.
  const Eigen::Vector3d head_top = joints.at("head_top");
  hit = cast(scene, {head_top.x(), head_top.y(), 3}, {0, 0, -1});
  ASSERT_NE(hit.surface, nullptr);
  EXPECT_EQ(hit.surface->name, "person/hair");
  EXPECT_DOUBLE_EQ(hit.surface->material().albedo, 0.15);
  EXPECT_NEAR(3 - hit.distance, spec.body.stature, 0.02);

  // The face is skin; the trunks are clothing.
  hit = cast(scene, {2, 0, head_top.z() - 0.5 * spec.body.head_height}, backward);
  ASSERT_NE(hit.surface, nullptr);
  EXPECT_EQ(hit.surface->name, "person/head");
  hit = cast(scene, {2, 0, joints.at("pelvis").z()}, backward);
  ASSERT_NE(hit.surface, nullptr);
  EXPECT_EQ(hit.surface->name, "person/pelvis");
  EXPECT_DOUBLE_EQ(hit.surface->material().albedo, 0.15);

  // Standing on the floor: a ray up from below meets the sole within a few millimetres of z = 0.
  const Eigen::Vector3d ankle = joints.at("left_ankle");
  hit = cast(scene, {ankle.x() + 0.03, ankle.y(), -1}, {0, 0, 1});
  ASSERT_NE(hit.surface, nullptr);
  EXPECT_EQ(hit.surface->name, "person/left_foot");
  EXPECT_NEAR(hit.distance - 1, 0, 0.005);
}

TEST(AddHumanBody, CrossSectionsMeasureTheGirths) {
  // Arms out and legs apart so each limb's cross-section is clear of the others.
  HumanBodySpec spec;
  spec.pose.left_shoulder_abduction = spec.pose.right_shoulder_abduction = kPi / 2;
  spec.pose.left_elbow_flexion = spec.pose.right_elbow_flexion = 0;
  spec.pose.left_hip_abduction = spec.pose.right_hip_abduction = 25 * kDegree;
  const Scene scene = sceneOf(spec);
  const auto joints = skeleton(spec);
  const Anthropometry& b = spec.body;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  auto middle = [&](const std::string& from, const std::string& to) {
    return Eigen::Vector3d(0.5 * (joints.at(from) + joints.at(to)));
  };
  auto along = [&](const std::string& from, const std::string& to) {
    return Eigen::Vector3d(joints.at(to) - joints.at(from));
  };
  EXPECT_NEAR(measuredGirth(scene, joints.at("chest"), up, 1.0), b.chest_girth,
              0.01 * b.chest_girth);
  // The waist: the abdomen's widest section, 0.3 torso lengths above the hip line.
  EXPECT_NEAR(
      measuredGirth(scene, middle("left_hip", "right_hip") + 0.3 * b.torso_length * up, up, 1.0),
      b.waist_girth, 0.01 * b.waist_girth);
  EXPECT_NEAR(measuredGirth(scene, middle("left_shoulder", "left_elbow"),
                            along("left_shoulder", "left_elbow"), 0.2),
              b.upper_arm_girth, 0.01 * b.upper_arm_girth);
  EXPECT_NEAR(measuredGirth(scene, middle("right_elbow", "right_wrist"),
                            along("right_elbow", "right_wrist"), 0.2),
              b.forearm_girth, 0.01 * b.forearm_girth);
  EXPECT_NEAR(
      measuredGirth(scene, middle("left_hip", "left_knee"), along("left_hip", "left_knee"), 0.15),
      b.thigh_girth, 0.01 * b.thigh_girth);
  EXPECT_NEAR(measuredGirth(scene, middle("right_knee", "right_ankle"),
                            along("right_knee", "right_ankle"), 0.15),
              b.calf_girth, 0.01 * b.calf_girth);
}

TEST(HumanBodyFromYaml, ReadsOverridesPoseAndMaterials) {
  const YAML::Node node = YAML::Load(R"(
    type: human
    name: bob
    stature: 1.60
    thigh_length: 0.45
    position: [1, -0.5, 0]
    heading_deg: 90
    pose: {left_knee_flexion_deg: 20, torso_lean_deg: -5}
    materials: {skin_albedo: 0.5, hair_albedo: 0.1, clothing_color: [0.2, 0.3, 0.4]}
  )");
  const HumanBodySpec spec = humanBodyFromYaml(node);
  EXPECT_EQ(spec.name, "bob");
  EXPECT_DOUBLE_EQ(spec.body.stature, 1.60);
  EXPECT_DOUBLE_EQ(spec.body.thigh_length, 0.45);                      // overridden
  EXPECT_NEAR(spec.body.shank_length, (0.285 - 0.039) * 1.60, 1e-12);  // from the stature
  EXPECT_NEAR(spec.body.chest_girth, 0.98 * 1.60 / 1.75, 1e-12);
  EXPECT_TRUE(spec.position.isApprox(Eigen::Vector3d(1, -0.5, 0)));
  EXPECT_NEAR(spec.pose.heading, kPi / 2, 1e-12);
  EXPECT_NEAR(spec.pose.left_knee_flexion, 20 * kDegree, 1e-12);
  EXPECT_NEAR(spec.pose.torso_lean, -5 * kDegree, 1e-12);
  EXPECT_DOUBLE_EQ(spec.pose.right_knee_flexion, BodyPose{}.right_knee_flexion);  // default
  EXPECT_DOUBLE_EQ(spec.materials.skin.albedo, 0.5);
  EXPECT_DOUBLE_EQ(spec.materials.hair.albedo, 0.1);
  EXPECT_DOUBLE_EQ(spec.materials.clothing.albedo, 0.15);
  EXPECT_TRUE(spec.materials.clothing.color.isApprox(Eigen::Vector3d(0.2, 0.3, 0.4)));
  // The override reaches the skeleton.
  const auto joints = skeleton(spec);
  EXPECT_NEAR((joints.at("left_hip") - joints.at("left_knee")).norm(), 0.45, 1e-9);
}

TEST(HumanBodyToYaml, WritesWhatTheReaderReadsBack) {
  HumanBodySpec spec;
  spec.name = "ann";
  spec.body = Anthropometry::fromStature(1.62);
  spec.body.thigh_length = 0.41;
  spec.body.calf_girth = 0.352;
  spec.position = {0.1, -0.2, 0};
  spec.pose.heading = 0.3;
  spec.pose.right_hip_flexion = 0.41;
  spec.pose.left_knee_flexion = 0.27;
  spec.materials.hair.albedo = 0.07;
  spec.materials.skin.color = {0.7, 0.5, 0.4};
  // Through text, as a scene file would carry it.
  const HumanBodySpec back = humanBodyFromYaml(YAML::Load(YAML::Dump(humanBodyToYaml(spec))));
  EXPECT_EQ(back.name, "ann");
  EXPECT_NEAR(back.body.thigh_length, 0.41, 1e-12);
  EXPECT_NEAR(back.body.calf_girth, 0.352, 1e-12);
  EXPECT_NEAR(back.body.shank_length, spec.body.shank_length, 1e-12);
  EXPECT_TRUE(back.position.isApprox(spec.position, 1e-12));
  EXPECT_NEAR(back.pose.heading, 0.3, 1e-12);
  EXPECT_NEAR(back.pose.right_hip_flexion, 0.41, 1e-12);
  EXPECT_NEAR(back.pose.left_knee_flexion, 0.27, 1e-12);
  EXPECT_NEAR(back.pose.left_shoulder_abduction, spec.pose.left_shoulder_abduction, 1e-12);
  EXPECT_NEAR(back.materials.hair.albedo, 0.07, 1e-12);
  EXPECT_TRUE(back.materials.skin.color.isApprox(spec.materials.skin.color, 1e-12));
  // The same body: every true joint in the same place.
  const auto joints = skeleton(spec), joints_back = skeleton(back);
  for (const auto& [name, position] : joints)
    EXPECT_LT((joints_back.at(name) - position).norm(), 1e-9) << name;
}

void expectErrorMentioning(const std::string& yaml, const std::vector<std::string>& words) {
  try {
    humanBodyFromYaml(YAML::Load(yaml));
    ADD_FAILURE() << "no error for: " << yaml;
  } catch (const std::runtime_error& error) {
    for (const std::string& word : words)
      EXPECT_NE(std::string(error.what()).find(word), std::string::npos)
          << "'" << word << "' missing from: " << error.what();
  }
}

TEST(HumanBodyFromYaml, RejectsBadInputNamingTheKey) {
  expectErrorMentioning("{type: human, stature_cm: 175}", {"stature_cm", "stature", "heading_deg"});
  expectErrorMentioning("{pose: {left_knee_deg: 20}}", {"left_knee_deg", "left_knee_flexion_deg"});
  expectErrorMentioning("{materials: {skin: 0.5}}", {"skin", "skin_albedo"});
  expectErrorMentioning("{stature: -1.7}", {"stature", "> 0"});
  expectErrorMentioning("{forearm_length: 0}", {"forearm_length", "> 0"});
  expectErrorMentioning("{stature: tall}", {"stature", "number"});
  expectErrorMentioning("{position: [1, 2]}", {"position"});
  expectErrorMentioning("{materials: {hair_albedo: 1.5}}", {"hair_albedo"});
}

TEST(HumanBodyFromYaml, ReadsTheExampleScene) {
  const std::filesystem::path file =
      std::filesystem::path(sim::driverConfigDir()) / "scenes" / "standing_person.yaml";
  const YAML::Node root = YAML::LoadFile(file.string());
  const YAML::Node person = root["objects"][1];
  ASSERT_EQ(person["type"].as<std::string>(), "human");
  const HumanBodySpec spec = humanBodyFromYaml(person);
  EXPECT_EQ(spec.name, "person");
  EXPECT_DOUBLE_EQ(spec.body.stature, 1.75);
  EXPECT_NEAR(spec.pose.left_shoulder_abduction, 12 * kDegree, 1e-12);
  EXPECT_NEAR(spec.pose.right_shoulder_abduction, 12 * kDegree, 1e-12);
  EXPECT_DOUBLE_EQ(spec.materials.hair.albedo, 0.15);
}

}  // namespace
}  // namespace body_scan_driver::sim
