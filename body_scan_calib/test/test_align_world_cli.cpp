// The alignment tools end to end: align_simulated_rig against the simulator (saving its images),
// then align_world on those images; both write aligned calibration files and the same E_h; bad
// folders fail with a message naming the fix.
#include <body_scan_driver/calibration_file.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

// Runs `executable` with `arguments`; returns its exit status and its stderr.
int runTool(const std::string& executable, const std::string& arguments,
            std::string* errors = nullptr) {
  const std::string error_file =
      testing::TempDir() + "/align_world_stderr_" + std::to_string(::getpid()) + ".txt";
  const int status =
      std::system((executable + " " + arguments + " > /dev/null 2> " + error_file).c_str());
  if (errors) {
    std::ifstream in(error_file);
    std::stringstream text;
    text << in.rdbuf();
    *errors = text.str();
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int runAlignWorld(const std::string& arguments, std::string* errors = nullptr) {
  return runTool(ALIGN_WORLD_EXECUTABLE, arguments, errors);
}

TEST(AlignWorldCli, SimulatedRigThenAlignWorldOnTheSavedImages) {
  const fs::path root =
      fs::path(testing::TempDir()) / ("align_world_cli_" + std::to_string(::getpid()));
  fs::remove_all(root);
  const std::string live_out = (root / "live").string(), images = (root / "images").string();
  ASSERT_EQ(runTool(ALIGN_SIMULATED_RIG_EXECUTABLE, "--calibration-out " + live_out +
                                                        " --save-images " + images + " --report " +
                                                        live_out + "/report.yaml"),
            0);
  const YAML::Node live = YAML::LoadFile(live_out + "/report.yaml");
  EXPECT_EQ(live["pairs"].size(), 4u);
  EXPECT_GE(live["E_h"]["shared_points"].as<int>(), 33);
  EXPECT_LE(live["E_h"]["mean_mm"].as<double>(), 1.0);
  EXPECT_GT(fs::file_size(live_out + "/report.png"), 10000u) << "the plot next to the report";
  for (const char* stem : {"pole_a_pair_1", "pole_a_pair_2", "pole_b_pair_1", "pole_b_pair_2"}) {
    const body_scan_driver::PairCalibration calibration =
        body_scan_driver::loadCalibration(live_out + "/" + stem + ".yaml");
    EXPECT_TRUE(calibration.alignment.has_value()) << stem;
    EXPECT_TRUE(fs::exists(images + "/" + stem + "/frame_17.png")) << stem;
  }

  const std::string offline_out = (root / "offline").string();
  ASSERT_EQ(
      runAlignWorld("--images " + images + " --calibration-in " + live_out + " --calibration-out " +
                    offline_out + " --report " + offline_out + "/report.yaml"),
      0);
  const YAML::Node offline = YAML::LoadFile(offline_out + "/report.yaml");
  EXPECT_EQ(offline["E_h"]["shared_points"].as<int>(), live["E_h"]["shared_points"].as<int>());
  EXPECT_EQ(offline["E_h"]["mean_mm"].as<std::string>(), live["E_h"]["mean_mm"].as<std::string>());
  EXPECT_TRUE(body_scan_driver::loadCalibration(offline_out + "/pole_b_pair_2.yaml").alignment);

  std::string errors;
  EXPECT_EQ(runAlignWorld("--images " + (root / "missing").string(), &errors), 1);
  EXPECT_NE(errors.find("--save-images"), std::string::npos) << errors;
  EXPECT_EQ(runAlignWorld("--images " + images + " --calibration-out " + offline_out, &errors), 1);
  EXPECT_NE(errors.find("--calibration-in"), std::string::npos) << errors;
  EXPECT_EQ(runAlignWorld("--no-such-option", &errors), 2);
  // The product tool has no simulator mode: without --images it names the option.
  EXPECT_EQ(runAlignWorld("--calibration-out " + offline_out, &errors), 2);
  EXPECT_NE(errors.find("--images"), std::string::npos) << errors;
  fs::remove_all(root);
}

}  // namespace
