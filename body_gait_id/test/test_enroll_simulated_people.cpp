// enroll_simulated_people --body mesh end to end on a temporary gallery: three mesh people
// scanned (ray-cast sampler) and fitted from their walk 0 and enrolled; the walk scenes it writes
// for the launched scanner hold the same mesh body (a mesh_human object) and the same true
// skeleton the evaluation scans; and the gallery is usable: person 1's other walk, scanned and
// fitted the same way, is identified as person 1 (rankWalk with recognition.launch's settings).
#include <body_gait_id/enrollment.h>
#include <body_gait_id/eval/gait_id_evaluation.h>
#include <body_gait_id/feature_noise_file.h>
#include <body_gait_id/walk_identification.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <body_scan_driver/sim/scene.h>
#include <gtest/gtest.h>
#include <ros/package.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

namespace body_gait_id {
namespace {

namespace fs = std::filesystem;
namespace eval_model = body_gait_model::eval;

constexpr int kPeople = 3;
constexpr int kWalker = 1;  // whose walk 1 the scenes hold and the probe is

TEST(EnrollSimulatedPeople, MeshPeopleGiveAUsableGallery) {
  const fs::path dir =
      fs::temp_directory_path() / ("test_enroll_simulated_people_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string database = (dir / "gallery.db").string();
  const std::string command = std::string(ENROLL_SIMULATED_PEOPLE) + " --database " + database +
                              " --people " + std::to_string(kPeople) +
                              " --scanner sampler --body mesh --walk-scenes " +
                              (dir / "walk").string() + " --scene-person " +
                              std::to_string(kWalker) + " --scene-trial 1 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[4096];
  while (fgets(buffer, sizeof buffer, pipe)) output += buffer;
  ASSERT_EQ(pclose(pipe), 0) << output;

  const GalleryDatabase gallery(database);
  ASSERT_EQ(gallery.subjects().size(), static_cast<size_t>(kPeople)) << output;
  EXPECT_EQ(gallery.poseRecords().size(), static_cast<size_t>(kPeople * kTrainingPoses));

  // The scenes: the walker's mesh body in each pose of walk 1, with the skeleton the evaluation
  // gives the same spec (what the launched scanner scans is what the tools measure).
  const auto people = eval_model::simulatedPeople(kPeople);
  for (int pose = 1; pose <= 4; ++pose) {
    const auto scene = body_scan_driver::sim::loadScene(
        (dir / "walk" / ("pose_" + std::to_string(pose) + ".yaml")).string());
    bool has_skin = false;
    for (const auto& surface : scene.surfaces())
      has_skin |= surface->name == people[kWalker].name + "/skin";
    EXPECT_TRUE(has_skin) << "pose " << pose << ": no mesh skin in the scene";
    body_scan_driver::sim::Scene expected;
    eval_model::addSimulatedBody(eval_model::walkingSubject(people[kWalker], pose, 1, 0.0),
                                 eval_model::BodyKind::kMesh, expected);
    ASSERT_EQ(scene.skeleton().size(), expected.skeleton().size());
    for (size_t j = 0; j < scene.skeleton().size(); ++j)
      EXPECT_LT((scene.skeleton()[j].position - expected.skeleton()[j].position).norm(), 1e-6)
          << "pose " << pose << " " << scene.skeleton()[j].name;
  }

  // The probe: the walker's walk 1, scanned and fitted as the gallery's walks were.
  eval::PersonSource walker;
  walker.names = {people[kWalker].name};
  walker.spec = [&](int, int pose, int, double heading) {
    return eval_model::walkingSubject(people[kWalker], pose, 1, heading);
  };
  eval::ScanOptions scan;
  scan.scanner = eval::ScannerKind::kSampler;
  scan.body = eval_model::BodyKind::kMesh;
  scan.progress = false;
  const eval::FittedWalks probe = eval::fitWalks(walker, 1, scan);
  ASSERT_TRUE(probe[0][0]) << "the probe walk could not be fitted";
  // The product's recognition settings (recognition.launch: body shape, median walk body, noise
  // weights), with the sampler's noise file.
  const FeatureNoise noise = readFeatureNoise(ros::package::getPath("body_gait_id") +
                                              "/config/feature_noise_sampler.yaml");
  const std::vector<WalkMatch> ranked =
      rankWalk(gallery.matcher(FeatureSet::kDynamicStaticShape, View::k3D, &noise),
               withMedianBody(*probe[0][0]));
  ASSERT_EQ(ranked.size(), static_cast<size_t>(kPeople));
  std::string walker_name;
  for (const Subject& subject : gallery.subjects())
    if (subject.id == ranked[0].subject_id) walker_name = subject.info.name;
  EXPECT_EQ(walker_name, people[kWalker].name)
      << "scores: " << ranked[0].score << " " << ranked[1].score << " " << ranked[2].score;
  std::printf("walk 1 of %s: best %s score %.2f, next %.2f\n", people[kWalker].name.c_str(),
              walker_name.c_str(), ranked[0].score, ranked[1].score);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace body_gait_id
