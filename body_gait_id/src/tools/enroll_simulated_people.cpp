// Enrols simulated people into a gallery database and writes a scene file of one of them on
// another walk: what `make demo` scans live and identifies. Each person's four
// representative poses (thesis 5.3) of walk --trial are scanned and fitted together (fitWalks:
// the full scanner simulation and the walk-level fit by default, as the body fitter fits the live
// walk the demo identifies; through the fit cache), then enrolled as the eta1 and eta2 training
// cycles (5.8.3). The scene file holds the floor and the person's body as a `human`
// object, so full_scanner.launch scans exactly that walk and pose. --walk-body is the enrolment
// rule of gait_id_node's ~walk_body (default median, as recognition.launch). --body mesh enrols
// and writes the skinned mesh human (a `mesh_human` scene object) instead of the ellipsoids.
//
//   enroll_simulated_people --database FILE [--people N] [--trial T] [--seed S]
//       [--scanner full|sampler|truth] [--body ellipsoid|mesh] [--fit walk|scan] [--cache DIR]
//       [--threads T] [--walk-body median|mean]
//       [--scene-out FILE.yaml --scene-person K --scene-trial T --scene-pose P]
//       [--walk-scenes DIR]   (all 4 poses of that walk: DIR/pose_1.yaml .. pose_4.yaml)
#include <body_gait_id/enrollment.h>
#include <body_gait_id/eval/gait_id_evaluation.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/tools/command_line.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>

#include "scanner_choices.h"

namespace {

using namespace body_gait_id;

// The scene of make demo's walking subject with this person's body instead (same floor).
std::string sceneFile(const body_scan_driver::sim::HumanBodySpec& person,
                      body_gait_model::eval::BodyKind body) {
  YAML::Node floor;
  floor["type"] = "plane";
  floor["point"] = std::vector<double>{0, 0, 0};
  floor["normal"] = std::vector<double>{0, 0, 1};
  floor["albedo"] = 0.3;
  floor["half_extent"] = 2.0;
  YAML::Node scene;
  scene["objects"].push_back(floor);
  scene["objects"].push_back(body_gait_model::eval::simulatedBodyToYaml(person, body));
  return "# Written by enroll_simulated_people: " + person.name +
         " (a simulated person) on the floor of the scan volume.\n" + YAML::Dump(scene) + "\n";
}

}  // namespace

int main(int argc, char** argv) {
  namespace tools = body_scan_driver::tools;
  CLI::App app(
      "Enrols simulated people into a gallery database (each person's four representative poses "
      "of walk --trial scanned and fitted, enrolled as the eta1 and eta2 training cycles) and "
      "writes a scene file of one of them on another walk: what make demo scans and identifies.",
      "enroll_simulated_people");
  std::string database_path, scene_path, walk_scenes;
  int people_count = 6, trial = 0, scene_person = 0, scene_trial = 1, scene_pose = 1;
  std::uint32_t seed = 1;
  eval::ScanOptions scan;
  scan.scanner = eval::ScannerKind::kFull;
  bool median_body = true;
  app.add_option("--database", database_path, "gallery database (SQLite)")->required();
  app.add_option("--people", people_count, "simulated people (0: only write scenes)")
      ->capture_default_str()
      ->check(tools::atLeast(0));
  app.add_option("--trial", trial, "the enrolled walk (numbered from 0)")
      ->capture_default_str()
      ->check(tools::atLeast(0));
  app.add_option("--seed", seed, "seed of the simulated people")->capture_default_str();
  tools::addChoice(app, "--scanner", scan.scanner, body_gait_id::tools::kScannerChoices,
                   "full: the 12-pair scanner simulation; sampler: rays cast from its "
                   "viewpoints; truth: no scan and no fit");
  tools::addChoice(app, "--body", scan.body, body_gait_id::tools::kBodyChoices,
                   "the simulated body enrolled and written into the scenes: ellipsoid "
                   "(default) or the skinned mesh human");
  tools::addChoice(app, "--fit", scan.fit, body_gait_id::tools::kFitChoices,
                   body_gait_id::tools::kFitHelp);
  app.add_option("--cache", scan.cache_folder, "fit cache folder (fits are reused)");
  app.add_option("--threads", scan.threads, "scans in parallel")
      ->capture_default_str()
      ->check(tools::inRange(1, 16));
  tools::addChoice(app, "--walk-body", median_body, {{"median", true}, {"mean", false}},
                   "a walk's body measures (gait_id_node's ~walk_body)");
  app.add_option("--scene-out", scene_path, "write the scene of one person's walk (YAML)");
  app.add_option("--walk-scenes", walk_scenes,
                 "write the scenes of all 4 poses of that walk into this folder (pose_1.yaml .. "
                 "pose_4.yaml: a simulated walk session, launch/scripts/simulated_walker)");
  app.add_option("--scene-person", scene_person,
                 "the scene's person (from --people on: not enrolled, a stranger)")
      ->capture_default_str()
      ->check(tools::atLeast(0));
  app.add_option("--scene-trial", scene_trial, "the scene's walk (numbered from 0)")
      ->capture_default_str()
      ->check(tools::atLeast(0));
  app.add_option("--scene-pose", scene_pose, "the scene's representative pose (thesis 5.3)")
      ->capture_default_str()
      ->check(CLI::Range(1, 4));
  if (const auto status = tools::parseCommandLine(app, argc, argv)) return *status;
  // Person i is the same whatever the count (simulatedPeople), so a scene person from --people
  // on is someone the gallery does not hold.
  std::vector<body_gait_model::eval::SimulatedPerson> persons =
      body_gait_model::eval::simulatedPeople(std::max(people_count, scene_person + 1), seed);
  const body_gait_model::eval::SimulatedPerson scene_subject = persons[scene_person];
  persons.resize(people_count);
  try {
    if (!scene_path.empty()) {
      // Facing the rig's front (heading 0), as the demo's walking subject does.
      body_scan_driver::writeFileAtomically(
          scene_path, sceneFile(body_gait_model::eval::walkingSubject(scene_subject, scene_pose,
                                                                      scene_trial, 0.0),
                                scan.body));
      std::printf("scene: %s walk %d pose %d -> %s\n", scene_subject.name.c_str(), scene_trial,
                  scene_pose, scene_path.c_str());
    }
    if (!walk_scenes.empty()) {
      std::filesystem::create_directories(walk_scenes);
      for (int pose = 1; pose <= 4; ++pose)
        body_scan_driver::writeFileAtomically(
            walk_scenes + "/pose_" + std::to_string(pose) + ".yaml",
            sceneFile(body_gait_model::eval::walkingSubject(scene_subject, pose, scene_trial, 0.0),
                      scan.body));
      std::printf("walk scenes: %s walk %d poses 1-4 -> %s/pose_1.yaml .. pose_4.yaml\n",
                  scene_subject.name.c_str(), scene_trial, walk_scenes.c_str());
    }
    eval::PersonSource source;
    for (const auto& person : persons) source.names.push_back(person.name);
    source.spec = [&persons, trial](int person, int pose, int, double heading) {
      return body_gait_model::eval::walkingSubject(persons[person], pose, trial, heading);
    };
    eval::FitSummary summary;
    const eval::FittedWalks walks = eval::fitWalks(source, 1, scan, &summary);
    GalleryDatabase gallery(database_path);
    int enrolled = 0;
    for (std::size_t i = 0; i < persons.size(); ++i) {
      if (!walks[i][0]) {
        std::fprintf(stderr, "not enrolled: %s (a pose could not be fitted)\n",
                     persons[i].name.c_str());
        continue;
      }
      const SubjectInfo info{persons[i].name, persons[i].gender, persons[i].age};
      const body_gait_model::RepresentativePoses& walk = *walks[i][0];
      const std::int64_t id =
          gallery.enroll(info, {}, trainingPoses(median_body ? withMedianBody(walk) : walk));
      std::printf("enrolled %s (%s, %d) as subject %lld: walk %d, %d training poses\n",
                  persons[i].name.c_str(), persons[i].gender.c_str(), persons[i].age,
                  static_cast<long long>(id), trial, kTrainingPoses);
      ++enrolled;
    }
    std::printf("%d of %zu people enrolled in %s (%d scans, %d from the cache, %.1f s)\n", enrolled,
                persons.size(), database_path.c_str(), summary.scans, summary.cached,
                summary.seconds);
    return enrolled == static_cast<int>(persons.size()) ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "enroll_simulated_people: %s\n", e.what());
    return 1;
  }
}
