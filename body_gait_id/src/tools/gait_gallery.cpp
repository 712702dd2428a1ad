// gait_gallery: the gait gallery database from the command line (no ROS needed).
#include <body_gait_id/enrollment.h>
#include <body_gait_id/feature_noise_file.h>
#include <body_gait_id/gallery_database.h>
#include <body_gait_id/models_file.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>

namespace {

constexpr const char* kUsage = R"(usage: gait_gallery [--database FILE] COMMAND ...

  list                                  enrolled subjects (id, name, gender, age, poses, scans)
  enroll --name NAME [--gender G] [--age YEARS] --models FILE.yaml [--scan PATH]...
         [--walk-body mean|median]      enrol a person from 4 fitted representative poses
                                        s1..s4 (YAML 'poses:' list, see models_file.h): the
                                        eta1 and eta2 training cycles, 40 poses; median: the
                                        body measures are the median of the 4 fits
  remove ID                             remove a subject with their scans and poses
  export [--format yaml|csv] [--output FILE]
                                        the whole gallery (YAML) or one row per pose (CSV)
  identify --models FILE.yaml [--feature-set dynamic|dynamic_static|dynamic_static_shape]
           [--view 3d|frontal|side] [--feature-noise FILE.yaml]
                                        nearest gallery pose of every model in the file;
                                        with a noise file (evaluate_gait_id --write-noise)
                                        each component weighted by between / within SD

  --database FILE   default $ROS_HOME/gait_gallery.db (the gait_id_node's default)
)";

struct Arguments {
  std::string command;
  std::vector<std::string> positional;
  std::multimap<std::string, std::string> options;
  std::string one(const std::string& key, const std::string& fallback = "") const {
    const auto it = options.find(key);
    return it == options.end() ? fallback : it->second;
  }
  std::string required(const std::string& key) const {
    const auto it = options.find(key);
    if (it == options.end())
      throw std::invalid_argument(command + " needs --" + key + " (see gait_gallery --help)");
    return it->second;
  }
};

// A whole decimal integer, or an error naming the option and what was given.
long long integer(const std::string& text, const std::string& what) {
  std::size_t used = 0;
  long long value = 0;
  try {
    value = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size())
    throw std::invalid_argument(what + " must be a whole number, not '" + text + "'");
  return value;
}

Arguments parse(int argc, char** argv) {
  Arguments args;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "-h" || word == "--help") throw std::invalid_argument("");
    if (word.rfind("--", 0) == 0) {
      if (i + 1 >= argc) throw std::invalid_argument(word + " needs a value");
      args.options.emplace(word.substr(2), argv[++i]);
    } else if (args.command.empty()) {
      args.command = word;
    } else {
      args.positional.push_back(word);
    }
  }
  if (args.command.empty()) throw std::invalid_argument("no command given");
  return args;
}

int run(const Arguments& args) {
  using namespace body_gait_id;
  GalleryDatabase db(args.one("database", defaultGalleryPath()));
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
    const SubjectInfo info{args.required("name"), args.one("gender"),
                           static_cast<int>(integer(args.one("age", "0"), "--age"))};
    std::vector<std::string> scans;
    for (auto [it, end] = args.options.equal_range("scan"); it != end; ++it)
      scans.push_back(it->second);
    const body_gait_model::RepresentativePoses s =
        representativePoses(readBodyModels(args.required("models")));
    const std::string walk_body = args.one("walk-body", "mean");
    if (walk_body != "mean" && walk_body != "median")
      throw std::invalid_argument("--walk-body must be mean or median, got '" + walk_body + "'");
    const std::vector<PoseRecord> poses =
        trainingPoses(walk_body == "median" ? withMedianBody(s) : s);
    const std::int64_t id = db.enroll(info, scans, poses);
    std::printf("enrolled '%s' as subject %ld (%zu poses) in %s\n", info.name.c_str(),
                static_cast<long>(id), poses.size(), db.path().c_str());
    return 0;
  }
  if (args.command == "remove") {
    if (args.positional.size() != 1)
      throw std::invalid_argument("remove needs one subject id (see gait_gallery list)");
    const std::int64_t id = integer(args.positional[0], "the subject id");
    if (!db.remove(id)) {
      std::fprintf(stderr, "gait_gallery: no subject %ld in %s (see gait_gallery list)\n",
                   static_cast<long>(id), db.path().c_str());
      return 1;
    }
    std::printf("removed subject %ld from %s\n", static_cast<long>(id), db.path().c_str());
    return 0;
  }
  if (args.command == "export") {
    const std::string format = args.one("format", "yaml");
    if (format != "yaml" && format != "csv")
      throw std::invalid_argument("unknown --format '" + format + "': use yaml or csv");
    const std::string output = args.one("output");
    std::ofstream file;
    if (!output.empty()) {
      file.open(output);
      if (!file) throw std::runtime_error("cannot write '" + output + "': check the directory");
    }
    std::ostream& out = output.empty() ? std::cout : file;
    if (format == "csv")
      exportGalleryCsv(db, out);
    else
      exportGalleryYaml(db, out);
    if (!out) throw std::runtime_error("writing the export failed (disk full?)");
    return 0;
  }
  if (args.command == "identify") {
    const View view = parseView(args.one("view", "3d"));
    std::optional<FeatureNoise> noise;
    if (!args.one("feature-noise").empty()) noise = readFeatureNoise(args.one("feature-noise"));
    const Matcher matcher = db.matcher(parseFeatureSet(args.one("feature-set", "dynamic_static")),
                                       view, noise ? &*noise : nullptr);
    std::map<std::int64_t, std::string> names;
    for (const Subject& s : db.subjects()) names[s.id] = s.info.name;
    const std::vector<body_gait_model::BodyModel> models = readBodyModels(args.required("models"));
    for (std::size_t i = 0; i < models.size(); ++i) {
      const Match m = matcher.identify(gaitFeatures(models[i], view));
      std::printf("pose %zu: subject %ld '%s', sequence %d, frame %d, score %.4f\n", i + 1,
                  static_cast<long>(m.subject_id), names[m.subject_id].c_str(), m.sequence, m.frame,
                  m.score);
    }
    return 0;
  }
  throw std::invalid_argument("unknown command '" + args.command + "'");
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  try {
    args = parse(argc, argv);
  } catch (const std::invalid_argument& e) {
    if (*e.what()) std::fprintf(stderr, "gait_gallery: %s\n\n", e.what());
    std::fputs(kUsage, *e.what() ? stderr : stdout);
    return *e.what() ? 2 : 0;
  }
  try {
    return run(args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gait_gallery: %s\n", e.what());
    return 1;
  }
}
