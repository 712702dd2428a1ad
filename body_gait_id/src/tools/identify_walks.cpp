// Cross-walk identification of people from their fitted walks (eval/cross_walk.h):
//
//   identify_walks [--out report.yaml] WALK_MODELS.yaml [...]
//
// Each file holds one walk's 4 fitted poses s1..s4 ('poses:', models_file.h) and its 'person'
// and 'walk' (evaluate_body_fit --bvh ... --models DIR writes them; without 'person' the file
// name up to its first '_' is used, CMU style). Every person needs 2 or more walks: one in the
// gallery, the others probed, in turn. Prints, per view (3D; the frontal and side 2D views of
// 5.8.4) and feature set (dynamic; dynamic + static), the frame identification rate (95 % CI), the
// pose error and the walks identified by vote.
#include <body_gait_id/eval/cross_walk.h>
#include <body_gait_id/models_file.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/tools/command_line.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <filesystem>
#include <sstream>

int main(int argc, char** argv) {
  using namespace body_gait_id;
  CLI::App app(
      "Cross-walk identification of people from their fitted walks (evaluate_body_fit --bvh ... "
      "--models DIR writes them): every person needs 2 or more walks.",
      "identify_walks");
  std::string out;
  std::vector<std::string> files;
  app.add_option("--out", out, "YAML report");
  app.add_option("WALK_MODELS.yaml", files, "one walk's 4 fitted poses s1..s4 per file")
      ->required()
      ->check(CLI::ExistingFile);
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  std::vector<eval::WalkModels> walks;
  try {
    for (const std::string& file : files) {
      eval::WalkModels walk;
      const YAML::Node root = YAML::LoadFile(file);
      const std::string stem = std::filesystem::path(file).stem().string();
      walk.walk = root["walk"] ? root["walk"].as<std::string>() : stem;
      walk.person =
          root["person"] ? root["person"].as<std::string>() : stem.substr(0, stem.find('_'));
      const auto models = readBodyModels(file);
      if (models.size() != 4)
        throw std::runtime_error("'" + file + "' holds " + std::to_string(models.size()) +
                                 " poses; a walk needs its 4 representative poses s1..s4");
      std::copy(models.begin(), models.end(), walk.poses.begin());
      walks.push_back(walk);
    }
    std::ostringstream yaml;
    const std::pair<const char*, FeatureSet> kSets[] = {
        {"dynamic", FeatureSet::kDynamic}, {"dynamic_static", FeatureSet::kDynamicStatic}};
    const std::pair<const char*, View> kViews[] = {
        {"3d", View::k3D}, {"frontal", View::kFrontal}, {"side", View::kSide}};
    for (const auto& [view_name, view] : kViews)
      for (const auto& [set_name, set] : kSets) {
        const std::string name = std::string(view_name) + "_" + set_name;
        const eval::CrossWalkResult result = eval::identifyAcrossWalks(walks, set, view);
        const auto& id = result.metrics.identification;
        std::printf(
            "%-22s frames identified %3d/%d = %5.1f %% (95 %% CI %.1f-%.1f), pose error %.2f "
            "frames (cyclic %.2f), walks identified by vote %d/%zu\n",
            name.c_str(), id.count, id.n, 100 * id.rate, 100 * id.ci_low, 100 * id.ci_high,
            result.metrics.average_pose_error, result.metrics.average_cyclic_pose_error,
            result.walks_right, result.walks.size());
        yaml << name << ":\n  frames_identified: " << id.count << "\n  frames: " << id.n
             << "\n  identification_rate: " << id.rate << "\n  ci95: [" << id.ci_low << ", "
             << id.ci_high << "]\n  pose_error_frames: " << result.metrics.average_pose_error
             << "\n  equal_error_rate: " << result.metrics.equal_error_rate
             << "\n  walks_identified: " << result.walks_right << "\n  walks:\n";
        for (const auto& walk : result.walks) {
          std::string gallery;
          for (const auto& g : walk.gallery_walks) gallery += (gallery.empty() ? "" : ",") + g;
          if (view == View::k3D)
            std::printf("    probe %-8s (person %s) vs gallery %s: %2d/20 frames right, voted %s\n",
                        walk.probe_walk.c_str(), walk.person.c_str(), gallery.c_str(),
                        walk.frames_right, walk.voted_person.c_str());
          yaml << "    - {probe: '" << walk.probe_walk << "', person: '" << walk.person
               << "', gallery: '" << gallery << "', frames_right: " << walk.frames_right
               << ", voted: '" << walk.voted_person << "'}\n";
        }
      }
    if (!out.empty()) body_scan_driver::writeFileAtomically(out, yaml.str());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "identify_walks: %s\n", error.what());
    return 1;
  }
  return 0;
}
