// The body driven by motion capture: the joint map, the body posed on BVH frames (same joints,
// placed in the scanner) and the four gait poses of thesis 5.3 picked in the CMU walks (skipped
// when ../shared/data/bvh is absent).
#include <body_scan_driver/sim/bvh_body.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <filesystem>

namespace body_scan_driver::sim {
namespace {

namespace fs = std::filesystem;

const std::string kMapPath = BODY_SCAN_DRIVER_CONFIG_DIR "/bvh/cmu_joint_map.yaml";
const char* const kCmuWalks[] = {"07_02", "07_08", "08_03", "08_08", "35_01", "35_02"};

std::string bvhPath(const std::string& walk) {
  const char* dir = std::getenv("BODY_SCAN_BVH_DIR");
  return std::string(dir ? dir : BODY_SCAN_BVH_DIR) + "/" + walk + ".bvh";
}

#define SKIP_WITHOUT_CMU_WALKS()                              \
  if (!fs::exists(bvhPath("07_02")))                          \
  GTEST_SKIP() << "CMU walks not found (" << bvhPath("07_02") \
               << "); set BODY_SCAN_BVH_DIR to the folder with 07_02.bvh ..."

std::map<std::string, Eigen::Vector3d> skeletonOf(const HumanBodySpec& spec) {
  std::map<std::string, Eigen::Vector3d> joints;
  for (const SkeletonJoint& joint : humanSkeleton(spec)) joints[joint.name] = joint.position;
  return joints;
}

// poseBodyOnSkeleton is the angle-posed body's own geometry: fed that body's joints and segment
// orientations it rebuilds the same skeleton and the same surfaces.
TEST(PoseBodyOnSkeleton, RebuildsTheAnglePosedBodyFromItsOwnSkeleton) {
  HumanBodySpec spec;
  spec.name = "walker";
  spec.body = Anthropometry::fromStature(1.68);
  spec.position = Eigen::Vector3d(0.05, -0.03, 0);
  BodyPose& pose = spec.pose;
  pose.heading = 0.4;
  pose.torso_lean = 0.05;
  pose.neck_flexion = 0.1;
  pose.right_hip_flexion = 0.35, pose.right_knee_flexion = 0.1;
  pose.left_hip_flexion = -0.3, pose.left_knee_flexion = 0.5;
  pose.left_shoulder_flexion = 0.3, pose.right_shoulder_flexion = -0.25;
  pose.left_elbow_flexion = 0.4;
  const BodySegmentFrames frames = bodySegmentFrames(spec);
  SkeletonPose skeleton;
  skeleton.joints = skeletonOf(spec);
  skeleton.orientations = {{"pelvis", frames.pelvis.rotation},
                           {"torso", frames.torso.rotation},
                           {"neck", frames.neck.rotation}};
  const char* const kSides[2] = {"left_", "right_"};
  for (int side = 0; side < 2; ++side) {
    const std::string prefix = kSides[side];
    skeleton.orientations[prefix + "upper_arm"] = frames.upper_arm[side].rotation;
    skeleton.orientations[prefix + "forearm"] = frames.forearm[side].rotation;
    skeleton.orientations[prefix + "hand"] = frames.hand[side].rotation;
    skeleton.orientations[prefix + "thigh"] = frames.thigh[side].rotation;
    skeleton.orientations[prefix + "shank"] = frames.shank[side].rotation;
    skeleton.orientations[prefix + "foot"] = frames.foot[side].rotation;
  }
  HumanBodySpec rebuilt;
  rebuilt.name = spec.name;
  rebuilt.body = Anthropometry::fromStature(1.68);  // girths and ankle height
  rebuilt.body.thigh_length = 1;                    // lengths come from the joints
  poseBodyOnSkeleton(skeleton, rebuilt);
  for (const auto& [name, position] : skeletonOf(rebuilt))
    EXPECT_LT((position - skeleton.joints.at(name)).norm(), 1e-9) << name;
  EXPECT_NEAR(rebuilt.body.thigh_length, spec.body.thigh_length, 1e-9);
  EXPECT_NEAR(rebuilt.body.torso_length, spec.body.torso_length, 1e-9);
  EXPECT_NEAR(rebuilt.body.head_height, spec.body.head_height, 1e-9);
  Scene original, copy;
  addHumanBody(spec, original);
  addHumanBody(rebuilt, copy);
  ASSERT_EQ(original.surfaces().size(), copy.surfaces().size());
  for (size_t i = 0; i < original.surfaces().size(); ++i) {
    const auto* a = dynamic_cast<const Ellipsoid*>(original.surfaces()[i].get());
    const auto* b = dynamic_cast<const Ellipsoid*>(copy.surfaces()[i].get());
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->name, b->name);
    EXPECT_LT((a->center() - b->center()).norm(), 1e-9) << a->name;
    EXPECT_LT((a->radii() - b->radii()).norm(), 1e-9) << a->name;
    EXPECT_LT((a->orientation() - b->orientation()).norm(), 1e-9) << a->name;
  }
}

TEST(BvhJointMap, CmuMapLoadsWithYUpAndZForward) {
  const BvhJointMap map = loadBvhJointMap(kMapPath);
  EXPECT_EQ(map.scheme, "cmu");
  EXPECT_DOUBLE_EQ(map.unit_scale, 0.056444);
  // BVH +z (forward) -> world +x, BVH +x (the subject's left) -> world +y, BVH +y -> world +z.
  EXPECT_TRUE(map.to_world.isApprox((Eigen::Matrix3d() << 0, 0, 1, 1, 0, 0, 0, 1, 0).finished()));
  for (const char* name :
       {"Hips",         "LeftUpLeg",     "LeftLeg",  "LeftFoot",     "LeftToeBase", "LowerBack",
        "Spine",        "Spine1",        "Neck",     "Neck1",        "Head",        "LeftShoulder",
        "LeftArm",      "LeftForeArm",   "LeftHand", "RightUpLeg",   "RightLeg",    "RightFoot",
        "RightToeBase", "RightShoulder", "RightArm", "RightForeArm", "RightHand"}) {
    bool mapped = false;
    for (const auto& entry : map.joints) mapped = mapped || entry.second == name;
    EXPECT_TRUE(mapped) << name;
  }
}

TEST(BvhJointMap, BadMapsNameTheProblem) {
  auto error = [](const std::string& yaml) {
    try {
      bvhJointMapFromYaml(YAML::Load(yaml), "map");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string good = YAML::Dump(YAML::LoadFile(kMapPath));
  EXPECT_EQ(error(good), "accepted");
  EXPECT_NE(error(good + "\nunit: 1\n").find("unknown key 'unit'"), std::string::npos);
  YAML::Node no_knee = YAML::LoadFile(kMapPath);
  no_knee["joints"].remove("left_knee");
  EXPECT_NE(error(YAML::Dump(no_knee)).find("needs 'left_knee'"), std::string::npos);
  YAML::Node bad_axis = YAML::LoadFile(kMapPath);
  bad_axis["up_axis"] = "up";
  EXPECT_NE(error(YAML::Dump(bad_axis)).find("'up_axis' must be one of"), std::string::npos);
  YAML::Node same_axes = YAML::LoadFile(kMapPath);
  same_axes["forward_axis"] = "-y";
  EXPECT_NE(error(YAML::Dump(same_axes)).find("must differ"), std::string::npos);
  YAML::Node bad_scale = YAML::LoadFile(kMapPath);
  bad_scale["unit_scale_m"] = -1;
  EXPECT_NE(error(YAML::Dump(bad_scale)).find("must be > 0"), std::string::npos);
  EXPECT_THROW(loadBvhJointMap("/nonexistent/map.yaml"), std::runtime_error);
}

TEST(BvhSubject, MotionWithoutAMappedJointIsRejected) {
  const BvhMotion motion = parseBvh(
      "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: 1\n"
      "Frame Time: 0.1\n0\n");
  try {
    BvhSubject(motion, loadBvhJointMap(kMapPath), "tiny");
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("which the motion does not have"), std::string::npos)
        << e.what();
  }
}

// The posed body's skeleton is the BVH skeleton moved rigidly into the scanner: every distance
// between joints is kept; the pelvis stands over the origin, facing +x, feet on the floor.
TEST(BvhSubject, BodyStandsOnTheBvhJointsInTheScanner) {
  SKIP_WITHOUT_CMU_WALKS();
  const BvhJointMap map = loadBvhJointMap(kMapPath);
  for (const char* walk : {"07_02", "35_01"}) {
    const BvhSubject subject(loadBvh(bvhPath(walk)), map, walk);
    for (int frame : {0, 77, 150}) {
      SCOPED_TRACE(std::string(walk) + " frame " + std::to_string(frame));
      const HumanBodySpec spec = subject.body(frame);
      const auto body = skeletonOf(spec);
      const auto bvh = subject.joints(frame);
      // Every joint where the BVH has it (the far ends use each side's own length) ...
      const char* const kJoints[] = {"left_shoulder", "right_shoulder", "left_elbow", "right_elbow",
                                     "left_wrist",    "right_wrist",    "left_hip",   "right_hip",
                                     "left_knee",     "right_knee",     "left_ankle", "right_ankle",
                                     "left_toe",      "right_toe"};
      for (const char* a : kJoints)
        for (const char* b : kJoints)
          EXPECT_NEAR((body.at(a) - body.at(b)).norm(), (bvh.at(a) - bvh.at(b)).norm(), 1e-9)
              << a << " - " << b;
      // ... but the CMU map takes the hand and head lengths from the body, along the BVH's
      // directions (its End Sites there are marker stubs).
      ASSERT_TRUE(map.hand_length_from_body && map.head_height_from_body);
      for (const std::string side : {"left_", "right_"}) {
        const Eigen::Vector3d hand = body.at(side + "hand_tip") - body.at(side + "wrist");
        const Eigen::Vector3d bvh_hand = bvh.at(side + "hand_tip") - bvh.at(side + "wrist");
        EXPECT_NEAR(hand.norm(), spec.body.hand_length, 1e-9);
        EXPECT_NEAR(
            hand.normalized().dot((body.at(side + "elbow") - body.at(side + "wrist")).normalized()),
            bvh_hand.normalized().dot(
                (bvh.at(side + "elbow") - bvh.at(side + "wrist")).normalized()),
            1e-9);
      }
      const Eigen::Vector3d shoulders = (body.at("left_shoulder") + body.at("right_shoulder")) / 2;
      EXPECT_NEAR((body.at("head_top") - shoulders).norm(),
                  spec.body.neck_length + spec.body.head_height, 1e-9);
      EXPECT_NEAR(spec.body.neck_length + spec.body.head_height, 0.182 * subject.estimatedStature(),
                  1e-9);
      const Eigen::Vector3d hip_mid = (body.at("left_hip") + body.at("right_hip")) / 2;
      EXPECT_NEAR(hip_mid.head<2>().norm(), 0, 1e-9);
      EXPECT_NEAR(body.at("pelvis").head<2>().norm(), 0, 1e-9);
      EXPECT_NEAR((body.at("left_hip") - body.at("right_hip")).x(), 0, 1e-9);
      EXPECT_GT((body.at("left_hip") - body.at("right_hip")).y(), 0.1);
      EXPECT_NEAR(std::min(body.at("left_ankle").z(), body.at("right_ankle").z()),
                  spec.body.ankle_height, 1e-9);
      // Lengths from the BVH offsets: the left shank is |LeftFoot offset| * 0.056444.
      const BvhMotion& motion = subject.motion();
      const double left_shank = motion.joints[motion.jointIndex("LeftFoot")].offset.norm(),
                   right_shank = motion.joints[motion.jointIndex("RightFoot")].offset.norm();
      EXPECT_NEAR(spec.body.shank_length, 0.056444 * (left_shank + right_shank) / 2, 1e-9);
      // A standing adult: 1.5-1.9 m from the leg length; the head top 1.4-1.9 m up.
      EXPECT_GT(subject.estimatedStature(), 1.5);
      EXPECT_LT(subject.estimatedStature(), 1.9);
      EXPECT_GT(body.at("head_top").z(), 1.45);
      EXPECT_LT(body.at("head_top").z(), 1.95);
      // The ellipsoids dress it: a ray along the lower leg's front normal toward its middle
      // hits that shank.
      Scene scene;
      addHumanBody(spec, scene);
      const Eigen::Vector3d mid_shank = (body.at("left_knee") + body.at("left_ankle")) / 2;
      Hit hit;
      ASSERT_TRUE(scene.intersect(
          Ray{mid_shank + Eigen::Vector3d(0, 1.5, 0), -Eigen::Vector3d::UnitY()}, hit));
      EXPECT_EQ(hit.surface->name.substr(hit.surface->name.find('/') + 1).find("left_"), 0u)
          << hit.surface->name;
    }
  }
}

// Thesis 5.3: pose 1 right leg in front with the longest stride, pose 2 right leg vertical and
// the left leg behind; 3 and 4 mirrored. Checked on the placed bodies of every walk.
TEST(GaitPoses, PickedPosesMatchTheThesisDefinitions) {
  SKIP_WITHOUT_CMU_WALKS();
  const BvhJointMap map = loadBvhJointMap(kMapPath);
  for (const char* walk : kCmuWalks) {
    SCOPED_TRACE(walk);
    const BvhSubject subject(loadBvh(bvhPath(walk)), map, walk);
    const GaitPoseFrames poses = pickGaitPoses(subject);
    EXPECT_GT(poses.walking_speed, 1.1);
    EXPECT_LT(poses.walking_speed, 1.9);
    for (int pose = 0; pose < 4; ++pose) {
      SCOPED_TRACE("pose " + std::to_string(pose + 1) + " at frame " +
                   std::to_string(poses.frame[pose] + 1));
      const auto joints = skeletonOf(subject.body(poses.frame[pose]));
      const std::string lead = pose < 2 ? "right_" : "left_", trail = pose < 2 ? "left_" : "right_";
      const double stride = joints.at(lead + "ankle").x() - joints.at(trail + "ankle").x();
      if (pose % 2 == 0) {
        // Heel strike: the leading foot well ahead (a stride of 0.5-0.9 m at these speeds).
        EXPECT_GT(stride, 0.45);
        EXPECT_LT(stride, 0.95);
      } else {
        // Mid-stance: the stance leg about vertical (ankle under the hip), the other behind.
        EXPECT_NEAR(joints.at(lead + "ankle").x(), joints.at(lead + "hip").x(), 0.06);
        EXPECT_LT(joints.at(trail + "ankle").x(), joints.at(lead + "ankle").x() - 0.1);
      }
    }
    // Mid-stance follows its heel strike within a third of a second.
    for (int strike : {0, 2}) {
      EXPECT_GT(poses.frame[strike + 1], poses.frame[strike]);
      EXPECT_LT((poses.frame[strike + 1] - poses.frame[strike]) * subject.motion().frame_time,
                0.35);
    }
  }
}

// A scene file places a BVH frame like any human: turned by heading_deg, moved to position.
TEST(BvhHumanScene, SceneObjectPlacesTheChosenFrame) {
  SKIP_WITHOUT_CMU_WALKS();
  const std::string object =
      "objects:\n  - type: bvh_human\n    name: w\n    bvh: " + bvhPath("07_02") +
      "\n    joint_map: " + kMapPath + "\n";
  const Scene scene =
      parseScene(object + "    gait_pose: 3\n    position: [1, 0.5, 0]\n    heading_deg: 90\n");
  const BvhSubject subject(loadBvh(bvhPath("07_02")), loadBvhJointMap(kMapPath), "w");
  const int frame = pickGaitPoses(subject).frame[2];
  const auto placed = skeletonOf(subject.body(frame));
  ASSERT_FALSE(scene.skeleton().empty());
  for (const SkeletonJoint& joint : scene.skeleton()) {
    const Eigen::Vector3d& p = placed.at(joint.name);
    // 90 deg about z: (x, y) -> (-y, x), then + (1, 0.5).
    EXPECT_LT((joint.position - Eigen::Vector3d(1 - p.y(), 0.5 + p.x(), p.z())).norm(), 1e-9)
        << joint.name;
  }
  EXPECT_EQ(scene.surfaces().front()->name.rfind("w/", 0), 0u);
  // The shipped scene file finds the walk next to the repository (its relative path).
  if (fs::exists(BODY_SCAN_BVH_DIR "/07_02.bvh")) {
    EXPECT_GT(loadScene(BODY_SCAN_DRIVER_CONFIG_DIR "/scenes/bvh_walker.yaml").skeleton().size(),
              10u);
  }
  auto error = [&](const std::string& keys) {
    try {
      parseScene(object + keys);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error("    frame: 12\n"), "accepted");
  EXPECT_NE(error("    frame: 12\n    gait_pose: 1\n").find("either 'frame'"), std::string::npos);
  EXPECT_NE(error("    frame: 201\n").find("'frame' must be 1..200"), std::string::npos);
  EXPECT_NE(error("    gait_pose: 5\n").find("'gait_pose' must be 1..4"), std::string::npos);
  EXPECT_NE(error("    frame: 1\n    speed: 2\n").find("unknown key 'speed'"), std::string::npos);
  EXPECT_NE(error("    frame: 1\n    stature: -1\n").find("stature"), std::string::npos);
}

TEST(GaitPoses, ShortClipIsAClearError) {
  SKIP_WITHOUT_CMU_WALKS();
  BvhMotion motion = loadBvh(bvhPath("07_02"));
  motion.frames.resize(40);  // a third of a second: no complete set
  const BvhSubject subject(motion, loadBvhJointMap(kMapPath), "short");
  try {
    pickGaitPoses(subject);
    ADD_FAILURE() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no heel strike and mid-stance"), std::string::npos)
        << e.what();
  }
}

TEST(ParseBvhWalkFile, PersonFromTheCmuNameOrGiven) {
  const BvhWalkFile cmu = parseBvhWalkFile("../data/bvh/07_02.bvh");
  EXPECT_EQ(cmu.person, "07");
  EXPECT_EQ(cmu.walk, "07_02");
  EXPECT_EQ(cmu.file, "../data/bvh/07_02.bvh");
  const BvhWalkFile named = parseBvhWalkFile("ada=/walks/take1.bvh");
  EXPECT_EQ(named.person, "ada");
  EXPECT_EQ(named.walk, "take1");
  EXPECT_EQ(named.file, "/walks/take1.bvh");
}

}  // namespace
}  // namespace body_scan_driver::sim
