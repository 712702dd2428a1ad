// The mesh human: the kit's skin is closed, the macro morphing reproduces MakeHuman's default
// body, the person spec reaches the statures asked for, skinning at rest is the identity, a BVH
// walk retargeted onto the mesh keeps the BVH's joints, and Embree's hits equal a brute-force
// ray-triangle intersection.
#include <body_scan_driver/sim/bvh_body.h>
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/mesh_human.h>
#include <body_scan_driver/sim/triangle_mesh.h>
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <random>
#include <set>

namespace body_scan_driver::sim {
namespace {

const MeshHumanModel& model() { return meshHumanModel(meshHumanFiles().model); }

TEST(MeshHumanModel, TheMorphedSkinIsAClosedGenusZeroSurface) {
  const MeshHumanModel& m = model();
  EXPECT_EQ(m.body_vertex_count, 13380);
  EXPECT_EQ(m.quads.size(), 13378u);
  EXPECT_EQ(boundaryEdgeCount(m), 0);
  // Euler characteristic V - E + F = 2 (every edge shared by two quads: E = 2F).
  EXPECT_EQ(
      m.body_vertex_count - 2 * static_cast<int>(m.quads.size()) + static_cast<int>(m.quads.size()),
      2);
  // Morphing moves vertices only: an extreme body still encloses a positive volume.
  MacroParameters extreme;
  extreme.gender = 0, extreme.age = 1, extreme.muscle = 1, extreme.weight = 1, extreme.height = 0.2;
  EXPECT_GT(morphMesh(m, extreme).volume, 0.02);
}

// MakeHuman's own default character (every slider 0.5, races 1/3): 165.9 cm and 54.9 L as
// MakeHuman measures it (the kit's README, section 9).
TEST(MeshHumanModel, MorphingReproducesMakeHumansDefaultBody) {
  const MorphedMesh mesh = morphMesh(model(), MacroParameters{});
  EXPECT_NEAR(mesh.stature, 1.659, 0.001);
  EXPECT_NEAR(mesh.volume * 1000, 54.9, 0.1);
  MacroParameters male;
  male.gender = 1;
  EXPECT_NEAR(morphMesh(model(), male).stature, 1.730, 0.001);
  EXPECT_NEAR(morphMesh(model(), male).volume * 1000, 63.3, 0.1);
}

TEST(MeshHumanModel, RejectsSlidersOutsideTheKit) {
  MacroParameters child;
  child.age = 0.3;
  EXPECT_THROW(morphMesh(model(), child), std::invalid_argument);
  MeshPersonSpec giant;
  giant.stature = 2.5;
  EXPECT_THROW(personMacros(model(), giant), std::invalid_argument);
}

// Bad files: a truncated kit and a retarget map without a segment are errors naming the file.
TEST(MeshHumanModel, BadFilesAreErrorsNamingTheFile) {
  const std::string kit = meshHumanFiles().model;
  const std::string cut = ::testing::TempDir() + "mesh_human_cut.bin";
  {
    std::ifstream in(kit, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  try {
    MeshHumanModel::load(cut);
    ADD_FAILURE() << "a truncated kit loaded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(cut), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  const std::string map = ::testing::TempDir() + "mesh_retarget_no_neck.yaml";
  std::ofstream(map) << "segments: {pelvis: [root]}\njoints: {}\n";
  try {
    loadMeshRetargetMap(map);
    ADD_FAILURE() << "a map without segments loaded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(map), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("torso"), std::string::npos) << e.what();
  }
}

// The default person: a 1.75 m man of BMI 23 (70.4 kg): stature on spec, volume 70 L, the
// skeleton's proportions those of an adult (Drillis & Contini: hip 0.53, shoulder 0.82 of H).
TEST(MeshPerson, TheDefaultPersonIsAPlausibleAdult) {
  const auto rig = meshHumanRig(MeshPersonSpec{}, meshHumanFiles());
  const MorphedMesh& mesh = rig->rest();
  EXPECT_NEAR(mesh.stature, 1.75, 0.002);
  EXPECT_NEAR(mesh.volume * 1000, 70.4, 1.0);
  const Anthropometry& a = rig->anthropometry();
  const double hip_z = rig->restFrames().pelvis.origin.z();
  EXPECT_NEAR(hip_z / a.stature, 0.53, 0.03);
  EXPECT_NEAR(a.shoulder_width, 0.36, 0.05);
  EXPECT_NEAR(a.thigh_length + a.shank_length, 0.245 * 1.75 + 0.246 * 1.75, 0.06);
  std::cout << "default person: stature " << mesh.stature << " m, volume " << mesh.volume * 1000
            << " L, hips " << hip_z << " m, shoulder width " << a.shoulder_width << " m, arm "
            << a.upper_arm_length << " + " << a.forearm_length << " + " << a.hand_length << " m\n";
  EXPECT_NEAR(a.upper_arm_length + a.forearm_length + a.hand_length, 0.44 * 1.75, 0.10);
}

// An ANSUR II-like population (statures by sex, BMI 17-30, ages 25-80): every morphed body's
// stature within 1 % of its spec.
TEST(MeshPerson, APopulationsStaturesAreOnSpec) {
  std::mt19937 random(7);
  std::normal_distribution<double> standard(0, 1);
  for (int i = 0; i < 8; ++i) {
    MeshPersonSpec person;
    const bool female = i % 2 == 0;
    person.gender = female ? 0 : 1;
    person.stature = std::clamp(
        (female ? 1.6285 : 1.7562) + (female ? 0.0642 : 0.0686) * standard(random), 1.45, 2.0);
    person.bmi =
        std::clamp((female ? 21 : 23) + 2.5 * standard(random), 17.0, female ? 25.0 : 30.0);
    person.age = std::uniform_real_distribution<double>(25, 80)(random);
    person.muscle = std::uniform_real_distribution<double>(0.3, 0.7)(random);
    const MorphedMesh mesh = morphMesh(model(), personMacros(model(), person));
    EXPECT_NEAR(mesh.stature, person.stature, 0.01 * person.stature) << "person " << i;
    EXPECT_NEAR(1000 * mesh.volume / (mesh.stature * mesh.stature), person.bmi, 0.3)
        << "person " << i;
  }
}

double maxDistance(const std::vector<Eigen::Vector3f>& a, const std::vector<Eigen::Vector3f>& b) {
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, double((a[i] - b[i]).norm()));
  return worst;
}

TEST(MeshHumanRig, SkinningAtTheRestPoseReproducesTheRestMesh) {
  const auto rig = meshHumanRig(MeshPersonSpec{}, meshHumanFiles());
  const std::vector<Eigen::Vector3f> posed = rig->pose(rig->restFrames(), rig->anthropometry());
  const std::vector<Eigen::Vector3f> rest(rig->rest().vertices.begin(),
                                          rig->rest().vertices.begin() + posed.size());
  EXPECT_LT(maxDistance(posed, rest), 1e-5);
}

// Standing by the gait generator's angles: the skin follows its skeleton (the knee's skin stays
// within a few cm of the knee) and the soles stay on the floor.
TEST(MeshHumanRig, AnglePosedBodyFollowsItsSkeleton) {
  const auto rig = meshHumanRig(MeshPersonSpec{}, meshHumanFiles());
  HumanBodySpec spec;
  spec.body = rig->anthropometry();
  spec.pose.left_hip_flexion = 0.4, spec.pose.left_knee_flexion = 0.5;
  spec.pose.right_shoulder_flexion = 0.4;
  const BodySegmentFrames frames = bodySegmentFrames(spec);
  Scene scene;
  addMeshHuman(*rig, spec, scene);
  std::map<std::string, Eigen::Vector3d> joints;
  for (const SkeletonJoint& joint : scene.skeleton()) joints[joint.name] = joint.position;
  const auto* skin = dynamic_cast<const TriangleMesh*>(scene.surfaces().at(0).get());
  ASSERT_NE(skin, nullptr);
  double lowest = 1e9, nearest_left_knee = 1e9;
  for (const Eigen::Vector3f& v : skin->vertices()) {
    lowest = std::min<double>(lowest, v.z());
    nearest_left_knee =
        std::min(nearest_left_knee, (v.cast<double>() - joints["left_knee"]).norm());
  }
  EXPECT_NEAR(lowest, 0.0, 0.02);
  EXPECT_LT(nearest_left_knee, 0.07);  // the knee's skin is ~4-5 cm from its centre
  // The mesh's own knee, carried by the thigh, lands on the forward-kinematics knee.
  EXPECT_LT((rig->posedMeshJoint("lowerleg01.L____head", "left_thigh", frames, spec.body) -
             joints["left_knee"])
                .norm(),
            1e-6);
}

// A CMU walk retargeted onto a mesh person: each thesis joint of the mesh skeleton (carried by
// the segment above it) lands within 10 mm of the BVH's own joint, every frame of the walk.
TEST(MeshHumanRig, RetargetedBvhJointsMatchTheBvhOverAWalk) {
  const BvhSubject subject(loadBvh(cmuWalksDir() + "/07_02.bvh"),
                           loadBvhJointMap(driverConfigDir() + "/bvh/cmu_joint_map.yaml"), "07");
  MeshPersonSpec person;
  person.stature = subject.estimatedStature();
  const auto rig = meshHumanRig(person, meshHumanFiles());
  const MeshRetargetMap map = loadMeshRetargetMap(meshHumanFiles().retarget_map);
  const std::pair<const char*, const char*> kCarriedBy[] = {
      {"shoulder", "torso"}, {"elbow", "upper_arm"}, {"wrist", "forearm"},
      {"hip", "pelvis"},     {"knee", "thigh"},      {"ankle", "shank"}};
  double worst = 0;
  for (int frame = 0; frame < subject.frameCount(); frame += 5) {
    const HumanBodySpec spec = subject.body(frame, rig->anthropometry());
    std::map<std::string, Eigen::Vector3d> bvh;
    for (const SkeletonJoint& joint : humanSkeleton(spec)) bvh[joint.name] = joint.position;
    for (const char* side : {"left_", "right_"})
      for (const auto& [joint, segment] : kCarriedBy) {
        const std::string segment_name =
            std::string(segment) == "torso" || std::string(segment) == "pelvis"
                ? segment
                : side + std::string(segment);
        const Eigen::Vector3d mesh =
            rig->posedMeshJoint(map.joints.at(side + std::string(joint)), segment_name,
                                *spec.segment_frames, spec.body);
        worst = std::max(worst, (mesh - bvh[side + std::string(joint)]).norm());
      }
  }
  EXPECT_LT(worst, 0.010);
  std::cout << "worst retargeted joint error over the walk: " << worst * 1000 << " mm\n";
}

// The scene files: a standing mesh person and a mesh walker on a CMU gait pose.
TEST(MeshHumanScene, SceneFilesPlaceAMeshPerson) {
  for (const char* name : {"mesh_person", "mesh_walker"}) {
    const Scene scene = loadScene(driverConfigDir() + "/scenes/" + name + ".yaml");
    ASSERT_EQ(scene.surfaces().size(), 2u) << name;
    const auto* skin = dynamic_cast<const TriangleMesh*>(scene.surfaces()[1].get());
    ASSERT_NE(skin, nullptr) << name;
    EXPECT_EQ(skin->name, std::string(name) == "mesh_person" ? "person/skin" : "walker/skin");
    std::map<std::string, Eigen::Vector3d> joints;
    for (const SkeletonJoint& joint : scene.skeleton()) joints[joint.name] = joint.position;
    EXPECT_GT(joints["head_top"].z(), 1.5) << name;
    EXPECT_LT(joints["head_top"].z(), 1.95) << name;
    EXPECT_NEAR(joints["pelvis"].x(), 0, 0.05) << name;
    // A ray down onto the head hits the skin at its vertex.
    Hit hit;
    ASSERT_TRUE(scene.intersect(
        Ray{joints["head_top"] + Eigen::Vector3d(0, 0, 1), -Eigen::Vector3d::UnitZ()}, hit));
    EXPECT_NEAR(hit.distance, 1.0, 0.02) << name;
  }
  EXPECT_THROW(parseScene("objects: [{type: mesh_human, gait_pose: 1}]"), std::runtime_error);
}

// Möller-Trumbore over every triangle: the peer Embree's nearest hit must equal.
bool bruteForce(const TriangleMesh& mesh, const Ray& ray, double& distance, int& triangle) {
  distance = std::numeric_limits<double>::infinity();
  for (size_t t = 0; t < mesh.triangles().size(); ++t) {
    const auto& tri = mesh.triangles()[t];
    const Eigen::Vector3d a = mesh.vertices()[tri[0]].cast<double>(),
                          b = mesh.vertices()[tri[1]].cast<double>(),
                          c = mesh.vertices()[tri[2]].cast<double>();
    const Eigen::Vector3d e1 = b - a, e2 = c - a, p = ray.direction.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-15) continue;
    const Eigen::Vector3d s = ray.origin - a;
    const double u = s.dot(p) / det;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = ray.direction.dot(q) / det, d = e2.dot(q) / det;
    if (u < 0 || v < 0 || u + v > 1 || d <= 1e-6 || d >= distance) continue;
    distance = d;
    triangle = static_cast<int>(t);
  }
  return std::isfinite(distance);
}

TEST(TriangleMesh, EmbreeHitsEqualABruteForceIntersection) {
  const auto rig = meshHumanRig(MeshPersonSpec{}, meshHumanFiles());
  const TriangleMesh mesh(rig->rest().vertices, rig->triangles(),
                          {Material{}, Material{0.15}, Material{0.2}}, rig->triangleMaterial());
  std::mt19937 random(3);
  std::uniform_real_distribution<double> height(0.05, 1.8), side(-0.3, 0.3);
  int hits = 0, agree = 0;
  for (int i = 0; i < 200; ++i) {
    const Ray ray{Eigen::Vector3d(2.0, side(random), height(random)),
                  Eigen::Vector3d(-1, 0.1 * side(random), 0.1 * side(random)).normalized()};
    Hit hit;
    double distance;
    int triangle = -1;
    const bool expected = bruteForce(mesh, ray, distance, triangle);
    ASSERT_EQ(mesh.intersect(ray, 1e-6, std::numeric_limits<double>::infinity(), hit), expected)
        << "ray " << i;
    EXPECT_EQ(mesh.occludes(ray, 1e-6, 10.0), expected);
    if (!expected) continue;
    ++hits;
    agree += std::abs(hit.distance - distance) < 1e-5;
    EXPECT_GT(-hit.normal.dot(ray.direction), 0) << "the normal faces the ray";
    // The packet path returns the same hit.
    Hit packed;
    mesh.intersectMany(&ray, 1, 1e-6, &packed);
    EXPECT_EQ(packed.surface, &mesh);
    EXPECT_NEAR(packed.distance, hit.distance, 1e-6);
  }
  EXPECT_GT(hits, 60);
  EXPECT_EQ(agree, hits);
}

}  // namespace
}  // namespace body_scan_driver::sim
