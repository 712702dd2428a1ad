// plan_rig: searches rig layouts for the fewest timing groups that still cover the subjects
// (eval/rig_design.h), prints the trade-off and writes the chosen rig file:
//   plan_rig [--poles 3,4] [--pairs-per-pole 4,5] [--sweep 20 40] [--candidates 200] [--seed 1]
//            [--subject SCENE.yaml ...] [--gait-poses] [--people N]
//            [--out RIG.yaml] [--table T.md] [--plot T.png]
//   plan_rig --check RIG.yaml [subjects]: the simulator's figures of one rig file.
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/human_body.h>
#include <body_scan_driver/tools/command_line.h>
#include <body_scan_merge/eval/rig_design.h>
#include <body_scan_merge/simulated_scan.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

using namespace body_scan_merge;
namespace fs = std::filesystem;

namespace {

// Relative file names in a scene (bvh, joint_map) made absolute, so the scene can be rewritten
// elsewhere.
void absolutePaths(YAML::Node object, const fs::path& folder) {
  for (const char* key : {"bvh", "joint_map"})
    if (object[key] && fs::path(object[key].as<std::string>()).is_relative())
      object[key] = fs::weakly_canonical(folder / object[key].as<std::string>()).string();
}

// The subjects: each scene file, with --gait-poses each of the 4 gait poses of a scene that
// names one, with --people N each `human` in N builds (stature 1.55-1.95 m, girths 0.9-1.15 of
// the stature's). The scanned body is renamed `person` (the evaluation's name).
std::vector<design::Subject> loadSubjects(const std::vector<std::string>& files, bool gait_poses,
                                          int people) {
  std::vector<design::Subject> subjects;
  const fs::path scratch = fs::temp_directory_path() / ("plan_rig_" + std::to_string(::getpid()));
  fs::create_directories(scratch);
  for (const std::string& file : files) {
    const YAML::Node original = YAML::LoadFile(file);
    const std::string stem = fs::path(file).stem().string();
    bool has_gait_pose = false;
    bool has_human = false;
    for (const YAML::Node& object : original["objects"]) {
      has_gait_pose = has_gait_pose || static_cast<bool>(object["gait_pose"]);
      has_human = has_human || object["type"].as<std::string>("") == "human";
    }
    const int poses = gait_poses && has_gait_pose ? 4 : 1;
    const int builds = has_human ? std::max(1, people) : 1;
    for (int pose = 1; pose <= poses; ++pose)
      for (int build = 0; build < builds; ++build) {
        YAML::Node scene = YAML::Clone(original);
        for (YAML::Node object : scene["objects"]) {
          const std::string type = object["type"].as<std::string>("");
          if (type == "plane") continue;
          object["name"] = "person";
          absolutePaths(object, fs::path(file).parent_path());
          if (poses > 1) object["gait_pose"] = pose;
          if (type == "human" && builds > 1) {
            const double t = static_cast<double>(build) / (builds - 1);
            const double stature = 1.55 + 0.40 * t;
            const double girth = 0.90 + 0.25 * ((build * 7) % builds) / std::max(1, builds - 1);
            const auto body = body_scan_driver::sim::Anthropometry::fromStature(stature);
            object["stature"] = stature;
            object["chest_girth"] = girth * body.chest_girth;
            object["waist_girth"] = girth * body.waist_girth;
            object["hip_girth"] = girth * body.hip_girth;
            object["thigh_girth"] = girth * body.thigh_girth;
            object["upper_arm_girth"] = girth * body.upper_arm_girth;
          }
        }
        std::string name = stem;
        if (poses > 1) name += "_pose_" + std::to_string(pose);
        if (builds > 1) name += "_person_" + std::to_string(build);
        const fs::path path = scratch / (name + ".yaml");
        YAML::Emitter out;
        out << scene;
        std::ofstream(path) << out.c_str() << "\n";
        subjects.push_back({name, std::make_shared<const body_scan_driver::sim::Scene>(
                                      body_scan_driver::sim::loadScene(path.string()))});
      }
  }
  fs::remove_all(scratch);
  return subjects;
}

void printScore(const design::SimulatedScore& score) {
  std::cout << std::fixed << std::setprecision(1);
  for (const auto& [name, a] : score.per_subject) {
    std::cout << "  " << name << ": " << a.points << " points, mean " << std::setprecision(3)
              << 1000 * a.mean_distance << " mm, coverage " << std::setprecision(1)
              << 100 * a.body.fraction() << " %;";
    for (const auto& [region, coverage] : a.regions)
      if (region != eval::Region::kOther && region != eval::Region::kSoles)
        std::cout << " " << eval::regionName(region) << " " << 100 * coverage.fraction() << " %";
    std::cout << "\n";
  }
  std::cout << "least coverage " << 100 * score.min_coverage << " %, least standing "
            << 100 * score.min_standing_coverage << " %, least hard region "
            << 100 * score.min_region_coverage << " %, mean distance " << std::setprecision(3)
            << 1000 * score.mean_distance << " mm\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Searches whole-body rig layouts (pole positions, pair heights and pitches, projector "
      "sweep) for the fewest timing groups that still cover the subjects: every layout is "
      "scored on a coarse proxy, the best per group count are scanned by the simulator; prints "
      "the trade-off and writes the chosen rig file.",
      "plan_rig");
  std::vector<int> poles{3}, pairs_per_pole{4};
  std::vector<double> sweep{20, 40};
  design::DesignOptions options;
  design::CoverageTargets targets;
  const std::string scenes = body_scan_driver::sim::driverConfigDir() + "/scenes/";
  std::vector<std::string> subject_files{scenes + "standing_person.yaml",
                                         scenes + "walking_person.yaml"};
  bool gait_poses = false;
  int people = 1;
  std::string out_path, table_path, plot_path, check_path;
  app.add_option("--poles", poles, "pole counts to search (3: two front, one behind; 4)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--pairs-per-pole", pairs_per_pole, "pairs per pole to search")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--sweep", sweep, "projector sweep range, degrees (min max)")
      ->expected(2)
      ->capture_default_str();
  app.add_option("--candidates", options.candidates, "random layouts per template")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000));
  app.add_option("--refine-steps", options.refine_steps,
                 "local search steps per group count (the 3 fewest)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000));
  app.add_option("--floor-radius", options.floor_radius,
                 "the timing-group planner's floor disc, m (the ScanCoordinator's ~floor_radius)")
      ->capture_default_str()
      ->check(body_scan_driver::tools::atLeast(0));
  app.add_option("--seed", options.seed, "random seed (the search is deterministic)")
      ->capture_default_str();
  app.add_option("--finalists", options.finalists,
                 "layouts per group count scanned by the simulator")
      ->capture_default_str()
      ->check(CLI::Range(1, 20));
  app.add_option("--min-proxy-coverage", options.min_proxy_coverage,
                 "layouts below this proxy coverage are not simulated")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--subject", subject_files, "subject scene files")->check(CLI::ExistingFile);
  app.add_flag("--gait-poses", gait_poses,
               "scan each of the 4 gait poses of a scene with gait_pose (bvh walkers)");
  app.add_option("--people", people, "builds of each `human` subject (stature 1.55-1.95 m)")
      ->capture_default_str()
      ->check(CLI::Range(1, 50));
  app.add_option("--target-coverage", targets.body, "least body coverage of any subject")
      ->capture_default_str();
  app.add_option("--target-standing", targets.standing, "least coverage of standing subjects")
      ->capture_default_str();
  app.add_option("--target-region", targets.region, "least coverage of any hard region")
      ->capture_default_str();
  app.add_option("--out", out_path, "write the chosen rig file here");
  app.add_option("--table", table_path, "write the trade-off table (markdown)");
  app.add_option("--plot", plot_path, "write the trade-off plot (PNG)");
  std::string finalists_dir;
  app.add_option("--finalists-dir", finalists_dir,
                 "write every simulated layout's rig file here (finalist_N.yaml, N = its index "
                 "in the search)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--check", check_path,
                 "no search: scan the subjects with this rig file and its planned groups, and "
                 "measure the interference within the groups on the first subject")
      ->check(CLI::ExistingFile);
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  try {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<design::Subject> subjects = loadSubjects(subject_files, gait_poses, people);
    std::cout << subjects.size() << " subjects\n";
    if (!check_path.empty()) {
      const body_scan_driver::sim::Rig rig = body_scan_driver::sim::loadRig(check_path);
      const design::SimulatedScore score =
          design::scoreInSimulator(rig, subjects, options.floor_radius);
      const design::ProxyScore proxy =
          design::scoreOnProxy(rig, options.proxy_spacing, options.floor_radius);
      std::cout << rig.pairs.size() << " pairs, " << score.groups.size()
                << " timing groups (proxy coverage " << 100 * proxy.coverage << " %):";
      for (const auto& group : score.groups) {
        std::cout << " {";
        for (const auto& id : group) std::cout << " " << id;
        std::cout << " }";
      }
      std::cout << "\n";
      printScore(score);
      const design::InterferenceScore interference =
          design::measureInterference(rig, score.groups, subjects.front().scene);
      std::cout << "wrong stripes on " << subjects.front().name << ", worst pair: alone "
                << std::setprecision(3) << 100 * interference.worst_alone
                << " %, in its timing group " << 100 * interference.worst_grouped << " %\n";
    } else {
      if (sweep[0] > sweep[1] || sweep[0] <= 0)
        throw std::invalid_argument("--sweep needs 0 < min <= max degrees");
      std::vector<design::RigTemplate> templates;
      for (int p : poles)
        for (int n : pairs_per_pole)
          templates.push_back(design::RigTemplate::standard(p, n, {sweep[0], sweep[1]}));
      const design::DesignResult result =
          design::designRig(templates, subjects, options, targets,
                            [](const std::string& line) { std::cout << line << std::endl; });
      const std::string table = design::tradeOffTable(result);
      std::cout << table;
      if (!table_path.empty()) body_scan_driver::writeFileAtomically(table_path, table);
      if (!plot_path.empty()) design::writeTradeOffPlot(result, plot_path);
      if (!finalists_dir.empty())
        for (size_t i = 0; i < result.candidates.size(); ++i)
          if (result.candidates[i].simulated) {
            const std::string name = "finalist_" + std::to_string(i);
            body_scan_driver::writeFileAtomically(
                finalists_dir + "/" + name + ".yaml",
                design::rigFileYaml(result.candidates[i].choice, name, "plan_rig finalist"));
          }
      if (result.chosen < 0)
        std::cout << "no layout met the targets (coverage >= " << 100 * targets.body
                  << " %, standing >= " << 100 * targets.standing
                  << " %, hard regions >= " << 100 * targets.region << " %)"
                  << (result.closest < 0 ? ": nothing written\n"
                                         : "; the closest (most least coverage) is written\n");
      const int pick = result.chosen >= 0 ? result.chosen : result.closest;
      if (pick >= 0) {
        const design::Candidate& chosen = result.candidates[pick];
        std::cout << (result.chosen >= 0 ? "chosen: " : "closest: ") << chosen.choice.poles
                  << " poles x " << chosen.choice.pairs_per_pole << " pairs, "
                  << chosen.simulation.groups.size() << " timing groups\n";
        printScore(chosen.simulation);
        if (!out_path.empty()) {
          std::ostringstream comment;
          comment << "Written by plan_rig (seed " << options.seed << ")"
                  << (result.chosen < 0 ? ", MISSING the coverage targets: " : ": ")
                  << chosen.simulation.groups.size() << " timing groups; least coverage "
                  << std::fixed << std::setprecision(1) << 100 * chosen.simulation.min_coverage
                  << " % of " << subjects.size() << " subjects.\nFormat: see thesis_rig.yaml.";
          body_scan_driver::writeFileAtomically(
              out_path, design::rigFileYaml(chosen.choice, fs::path(out_path).stem().string(),
                                            comment.str()));
          std::cout << "rig written to " << out_path << "\n";
        }
      }
    }
    std::cout << "run time " << std::setprecision(1)
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
              << " s\n";
  } catch (const std::exception& e) {
    std::cerr << "plan_rig: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
