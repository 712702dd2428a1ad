// gait_gallery: the gait gallery database from the command line (no ROS needed).
#include <body_gait_id/enrollment.h>
#include <body_gait_id/feature_noise_file.h>
#include <body_gait_id/gallery_database.h>
#include <body_gait_id/models_file.h>
#include <body_gait_id/walk_identification.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/tools/command_line.h>

#include <cstdio>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "walk_bag.h"

namespace {

// The command line: one subcommand and its options (see --help).
struct Arguments {
  std::string command, database;
  std::string name, gender, models, bag, walk_body = "mean", format = "yaml", output, view = "3d",
                                         feature_set = "dynamic_static", feature_noise;
  int age = 0;
  std::uint32_t walk_id = 0;
  double walk_threshold = body_gait_id::kDefaultWalkAcceptThreshold;
  std::vector<std::string> scans;
  std::int64_t subject_id = 0;
};

// Returns the exit status when the tool should stop (--help, a usage error).
std::optional<int> parse(int argc, char** argv, Arguments& args) {
  CLI::App app("The gait gallery database from the command line (no ROS needed).", "gait_gallery");
  app.require_subcommand(0, 1);
  args.database = body_gait_id::defaultGalleryPath();
  app.add_option("--database", args.database, "gallery file (gait_id_node's default)")
      ->capture_default_str();
  app.add_subcommand("list", "enrolled subjects (id, name, gender, age, poses, scans)");
  CLI::App* enroll = app.add_subcommand(
      "enroll",
      "enrol a person from 4 fitted representative poses s1..s4 (YAML 'poses:' list, see "
      "models_file.h): the eta1 and eta2 training cycles, 40 poses");
  enroll->add_option("--name", args.name, "the person's name")->required();
  enroll->add_option("--gender", args.gender, "the person's gender");
  enroll->add_option("--age", args.age, "age in years")->check(body_scan_driver::tools::atLeast(0));
  auto* enroll_models = enroll->add_option("--models", args.models, "the 4 fitted poses (YAML)");
  auto* enroll_bag = enroll->add_option(
      "--bag", args.bag, "a recorded walk session (record.launch): its 4 fitted models");
  enroll_models->excludes(enroll_bag);
  enroll->add_option("--walk", args.walk_id, "--bag: the walk id (default: the last complete)");
  enroll->add_option("--scan", args.scans, "a scan of the person to keep with them (repeat)");
  enroll
      ->add_option("--walk-body", args.walk_body,
                   "the body measures: the mean of the 4 fits, or their median")
      ->capture_default_str()
      ->check(CLI::IsMember({"mean", "median"}));
  CLI::App* remove = app.add_subcommand("remove", "remove a subject with their scans and poses");
  remove->add_option("ID", args.subject_id, "subject id (gait_gallery list)")->required();
  CLI::App* export_command =
      app.add_subcommand("export", "the whole gallery (YAML) or one row per pose (CSV)");
  export_command->add_option("--format", args.format, "yaml or csv")
      ->capture_default_str()
      ->check(CLI::IsMember({"yaml", "csv"}));
  export_command->add_option("--output", args.output, "file (default: standard output)");
  CLI::App* identify = app.add_subcommand(
      "identify",
      "nearest gallery pose of every model in the file; with a noise file (evaluate_gait_id "
      "--write-noise) each component weighted by between / within SD");
  auto* identify_models =
      identify->add_option("--models", args.models, "the models to identify (YAML)");
  auto* identify_bag = identify->add_option(
      "--bag", args.bag,
      "a recorded walk session: its 4 scans one by one, then the walk (its gait cycle against "
      "the gallery, one decision)");
  identify_models->excludes(identify_bag);
  identify->add_option("--walk", args.walk_id, "--bag: the walk id (default: the last complete)");
  identify
      ->add_option("--walk-body", args.walk_body,
                   "--bag: the walk's body measures, the mean of the 4 fits or their median")
      ->capture_default_str()
      ->check(CLI::IsMember({"mean", "median"}));
  identify
      ->add_option("--walk-threshold", args.walk_threshold,
                   "--bag: the largest accepted walk score (gait_id_node's ~walk_accept_threshold)")
      ->capture_default_str();
  identify
      ->add_option("--feature-set", args.feature_set,
                   "dynamic, dynamic_static or dynamic_static_shape")
      ->capture_default_str();
  identify->add_option("--view", args.view, "3d, frontal or side")->capture_default_str();
  identify->add_option("--feature-noise", args.feature_noise, "feature noise file (YAML)");
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv)) return status;
  if (app.get_subcommands().empty()) {
    std::fprintf(stderr,
                 "gait_gallery: give a command: list, enroll, remove, export or identify\nRun "
                 "with --help for more information.\n");
    return 2;
  }
  args.command = app.get_subcommands().front()->get_name();
  if ((args.command == "enroll" || args.command == "identify") && args.models.empty() &&
      args.bag.empty()) {
    std::fprintf(stderr,
                 "gait_gallery %s: give the models, --models FILE.yaml or --bag WALK.bag\nRun "
                 "with --help for more information.\n",
                 args.command.c_str());
    return 2;
  }
  return std::nullopt;
}

int run(const Arguments& args) {
  using namespace body_gait_id;
  GalleryDatabase db(args.database);
  if (args.command == "list") {
    const std::vector<Subject> subjects = db.subjects();
    std::printf("%s: %zu subjects\n", db.path().c_str(), subjects.size());
    std::printf("%6s  %-24s %-8s %4s %6s  %s\n", "id", "name", "gender", "age", "poses",
                "enrolled / scans");
    for (const Subject& s : subjects) {
      std::printf("%6ld  %-24s %-8s %4d %6d  %s\n", static_cast<long>(s.id), s.info.name.c_str(),
                  s.info.gender.c_str(), s.info.age, s.pose_count, s.enrolled.c_str());
      for (const std::string& scan : s.scans) std::printf("%50s%s\n", "", scan.c_str());
    }
    return 0;
  }
  if (args.command == "enroll") {
    const SubjectInfo info{args.name, args.gender, args.age};
    std::vector<std::string> scans = args.scans;
    std::vector<body_gait_model::BodyModel> models;
    if (!args.bag.empty()) {
      const tools::RecordedWalk walk = tools::readWalkFromBag(args.bag, args.walk_id);
      models = walk.poses;
      scans.push_back(args.bag + " (walk " + std::to_string(walk.walk_id) + ")");
      std::printf("walk %u of %s: scans %u %u %u %u\n", walk.walk_id, args.bag.c_str(),
                  walk.scan_ids[0], walk.scan_ids[1], walk.scan_ids[2], walk.scan_ids[3]);
    } else {
      models = readBodyModels(args.models);
    }
    const body_gait_model::RepresentativePoses s = representativePoses(models);
    const std::vector<PoseRecord> poses =
        trainingPoses(args.walk_body == "median" ? withMedianBody(s) : s);
    const std::int64_t id = db.enroll(info, scans, poses);
    std::printf("enrolled '%s' as subject %ld (%zu poses) in %s\n", info.name.c_str(),
                static_cast<long>(id), poses.size(), db.path().c_str());
    return 0;
  }
  if (args.command == "remove") {
    const std::int64_t id = args.subject_id;
    if (!db.remove(id)) {
      std::fprintf(stderr, "gait_gallery: no subject %ld in %s (see gait_gallery list)\n",
                   static_cast<long>(id), db.path().c_str());
      return 1;
    }
    std::printf("removed subject %ld from %s\n", static_cast<long>(id), db.path().c_str());
    return 0;
  }
  if (args.command == "export") {
    const std::string& format = args.format;
    const std::string& output = args.output;
    std::ostringstream text;
    if (format == "csv")
      exportGalleryCsv(db, text);
    else
      exportGalleryYaml(db, text);
    if (output.empty()) {
      std::cout << text.str();
      if (!std::cout) throw std::runtime_error("writing the export failed (disk full?)");
    } else {  // names and biometrics: readable by the owner only, like the gallery
      body_scan_driver::writeFileAtomically(output, text.str(), /*owner_only=*/true);
    }
    return 0;
  }
  if (args.command == "identify") {
    const View view = parseView(args.view);
    std::optional<FeatureNoise> noise;
    if (!args.feature_noise.empty()) noise = readFeatureNoise(args.feature_noise);
    const Matcher matcher =
        db.matcher(parseFeatureSet(args.feature_set), view, noise ? &*noise : nullptr);
    std::map<std::int64_t, std::string> names;
    for (const Subject& s : db.subjects()) names[s.id] = s.info.name;
    std::optional<tools::RecordedWalk> walk;
    if (!args.bag.empty()) walk = tools::readWalkFromBag(args.bag, args.walk_id);
    const std::vector<body_gait_model::BodyModel> models =
        walk ? walk->poses : readBodyModels(args.models);
    for (std::size_t i = 0; i < models.size(); ++i) {
      const Match m = matcher.identify(gaitFeatures(models[i], view));
      std::printf("pose %zu: subject %ld '%s', sequence %d, frame %d, score %.4f\n", i + 1,
                  static_cast<long>(m.subject_id), names[m.subject_id].c_str(), m.sequence, m.frame,
                  m.score);
    }
    if (walk) {
      const body_gait_model::RepresentativePoses s = representativePoses(walk->poses);
      const std::vector<WalkMatch> ranked =
          rankWalk(matcher, args.walk_body == "median" ? withMedianBody(s) : s, view);
      if (ranked.empty()) throw std::runtime_error("the gallery is empty: enrol people first");
      const bool accepted = ranked[0].score <= args.walk_threshold;
      std::printf("walk %u: subject %ld '%s', score %.4f, %s (walk threshold %.2f)\n",
                  walk->walk_id, static_cast<long>(ranked[0].subject_id),
                  names[ranked[0].subject_id].c_str(), ranked[0].score,
                  accepted ? "accepted" : "rejected: unknown person", args.walk_threshold);
      for (std::size_t i = 0; i < ranked.size() && i < 5; ++i)
        std::printf("  rank %zu: '%s' %.4f\n", i + 1, names[ranked[i].subject_id].c_str(),
                    ranked[i].score);
    }
    return 0;
  }
  throw std::invalid_argument("unknown command '" + args.command + "'");
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  if (const auto status = parse(argc, argv, args)) return *status;
  try {
    return run(args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gait_gallery: %s\n", e.what());
    return 1;
  }
}
