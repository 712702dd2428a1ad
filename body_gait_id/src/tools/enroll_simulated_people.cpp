// Enrols simulated people into a gallery database and writes a scene file of one of them on
// another walk: what `make demo` scans live and identifies (issue 6). Each person's four
// representative poses (thesis 5.3) of walk --trial are scanned and fitted (fitWalks: the full
// scanner simulation by default, through the fit cache), then enrolled as the eta1 and eta2
// training cycles (5.8.3). The scene file holds the floor and the person's body as a `human`
// object, so full_scanner.launch scans exactly that walk and pose. --walk-body is the enrolment
// rule of gait_id_node's ~walk_body (default median, as recognition.launch).
//
//   enroll_simulated_people --database FILE [--people N] [--trial T] [--seed S]
//       [--scanner full|sampler|truth] [--cache DIR] [--threads T] [--walk-body median|mean]
//       [--scene-out FILE.yaml --scene-person K --scene-trial T --scene-pose P]
#include <body_gait_id/enrollment.h>
#include <body_gait_id/eval/gait_id_evaluation.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <body_scan_driver/atomic_file.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

using namespace body_gait_id;

[[noreturn]] void usage(const std::string& problem) {
  std::fprintf(stderr,
               "enroll_simulated_people: %s\n"
               "usage: enroll_simulated_people --database FILE [--people N (default 6)] "
               "[--trial T (default 0)] [--seed S] [--scanner full|sampler|truth (default full)] "
               "[--cache DIR] [--threads T] [--walk-body median|mean] [--scene-out FILE.yaml "
               "--scene-person K "
               "--scene-trial T --scene-pose P (1..4)]\n",
               problem.c_str());
  std::exit(2);
}

int integer(const char* text, const std::string& flag) {
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (end == text || *end != '\0') usage(flag + " needs a whole number, got '" + text + "'");
  return static_cast<int>(value);
}

// The scene of make demo's walking subject with this person's body instead (same floor).
std::string sceneFile(const body_scan_driver::sim::HumanBodySpec& person) {
  YAML::Node floor;
  floor["type"] = "plane";
  floor["point"] = std::vector<double>{0, 0, 0};
  floor["normal"] = std::vector<double>{0, 0, 1};
  floor["albedo"] = 0.3;
  floor["half_extent"] = 2.0;
  YAML::Node scene;
  scene["objects"].push_back(floor);
  scene["objects"].push_back(body_scan_driver::sim::humanBodyToYaml(person));
  return "# Written by enroll_simulated_people: " + person.name +
         " (a simulated person) on the floor of the scan volume.\n" + YAML::Dump(scene) + "\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::string database_path, scene_path;
  int people_count = 6, trial = 0, scene_person = 0, scene_trial = 1, scene_pose = 1;
  std::uint32_t seed = 1;
  eval::ScanOptions scan;
  scan.scanner = eval::ScannerKind::kFull;
  bool median_body = true;
  for (int i = 1; i < argc; i += 2) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) usage(flag + " needs a value");
    const char* value = argv[i + 1];
    if (flag == "--database") {
      database_path = value;
    } else if (flag == "--people") {
      people_count = integer(value, flag);
    } else if (flag == "--trial") {
      trial = integer(value, flag);
    } else if (flag == "--seed") {
      seed = static_cast<std::uint32_t>(integer(value, flag));
    } else if (flag == "--scanner") {
      const std::string kind = value;
      if (kind == "full")
        scan.scanner = eval::ScannerKind::kFull;
      else if (kind == "sampler")
        scan.scanner = eval::ScannerKind::kSampler;
      else if (kind == "truth")
        scan.scanner = eval::ScannerKind::kTruth;
      else
        usage("--scanner must be full, sampler or truth, got '" + kind + "'");
    } else if (flag == "--cache") {
      scan.cache_folder = value;
    } else if (flag == "--threads") {
      scan.threads = integer(value, flag);
    } else if (flag == "--walk-body") {
      const std::string rule = value;
      if (rule != "median" && rule != "mean")
        usage("--walk-body must be median or mean, got '" + rule + "'");
      median_body = rule == "median";
    } else if (flag == "--scene-out") {
      scene_path = value;
    } else if (flag == "--scene-person") {
      scene_person = integer(value, flag);
    } else if (flag == "--scene-trial") {
      scene_trial = integer(value, flag);
    } else if (flag == "--scene-pose") {
      scene_pose = integer(value, flag);
    } else {
      usage("unknown option " + flag);
    }
  }
  if (database_path.empty()) usage("--database is required");
  if (people_count < 1) usage("--people must be >= 1");
  if (trial < 0 || scene_trial < 0) usage("walks (--trial, --scene-trial) are numbered from 0");
  if (scene_person < 0 || scene_person >= people_count)
    usage("--scene-person must be 0.." + std::to_string(people_count - 1));
  if (scene_pose < 1 || scene_pose > 4) usage("--scene-pose must be 1..4 (thesis 5.3)");
  if (scan.threads < 1 || scan.threads > 16) usage("--threads must be 1..16");

  const std::vector<body_gait_model::eval::SimulatedPerson> persons =
      body_gait_model::eval::simulatedPeople(people_count, seed);
  try {
    if (!scene_path.empty()) {
      // Facing the rig's front (heading 0), as the demo's walking subject does.
      body_scan_driver::writeFileAtomically(
          scene_path, sceneFile(body_gait_model::eval::walkingSubject(
                          persons[scene_person], scene_pose, scene_trial, 0.0)));
      std::printf("scene: %s walk %d pose %d -> %s\n", persons[scene_person].name.c_str(),
                  scene_trial, scene_pose, scene_path.c_str());
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
