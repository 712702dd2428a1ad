// plan_timing_groups (the CLI) against the library on the same geometry: it reads the pairs'
// calibration files, takes each pose from the file's world_alignment section when there is one
// (else from the rig file) and reports the library's groups and conflicts.
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/rig.h>
#include <body_scan_merge/simulated_scan.h>
#include <body_scan_merge/timing_groups.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

using namespace body_scan_merge;
using namespace body_scan_driver;
namespace fs = std::filesystem;

namespace {

const std::string kRig = body_scan_driver::sim::driverConfigDir() + "/rigs/thesis_rig.yaml";

std::string fileStem(std::string id) {
  std::replace(id.begin(), id.end(), '/', '_');
  return id;
}

// Runs the CLI; returns its exit code and the report (null when none was written).
std::pair<int, YAML::Node> plan(const fs::path& dir, const std::string& suffix,
                                const std::string& options = "") {
  const fs::path report = dir / "plan.yaml";
  fs::remove(report);
  const std::string command = std::string(PLAN_TIMING_GROUPS) + " --calibration-dir " +
                              dir.string() + " --suffix '" + suffix + "' --rig " + kRig +
                              " --report " + report.string() + " " + options + " > " +
                              (dir / "out.txt").string() + " 2>&1";
  const int status = std::system(command.c_str());
  return {WEXITSTATUS(status), fs::exists(report) ? YAML::LoadFile(report.string()) : YAML::Node()};
}

std::vector<std::vector<std::string>> groupsOf(const YAML::Node& report) {
  return report["groups"].as<std::vector<std::vector<std::string>>>();
}

}  // namespace

TEST(PlanTimingGroups, ReportsTheLibrarysPlanWithPosesFromAlignmentOrRig) {
  const fs::path dir =
      fs::temp_directory_path() / ("plan_timing_groups_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const body_scan_driver::sim::Rig rig = body_scan_driver::sim::loadRig(kRig);
  const std::vector<PairGeometry> truth = rigFactoryGeometry(rig);
  for (const PairGeometry& pair : truth)
    saveCalibration((dir / (fileStem(pair.pair_id) + "_factory.yaml")).string(), pair.calibration);

  // Factory files carry no alignment: poses from the rig file.
  const auto [status, report] = plan(dir, "_factory");
  ASSERT_EQ(status, 0);
  const TimingPlan expected = planTimingGroups(truth);
  EXPECT_EQ(groupsOf(report), expected.groups);
  EXPECT_EQ(report["group_count"].as<size_t>(), expected.groups.size());
  EXPECT_DOUBLE_EQ(report["simulated_acquisition_seconds"].as<double>(),
                   0.5 * expected.groups.size());
  EXPECT_EQ(report["conflicts"].size(), expected.conflicts.size());
  // The group period from the hardware: 18 pattern frames, each kept after 2 settle frames of
  // a 30 Hz camera (the usb pair's defaults), 1.8 s.
  const auto [usb_status, usb_report] = plan(dir, "_factory", "--camera-fps 30 --settle-frames 2");
  ASSERT_EQ(usb_status, 0);
  EXPECT_DOUBLE_EQ(usb_report["group_seconds"].as<double>(), 1.8);
  EXPECT_DOUBLE_EQ(usb_report["simulated_acquisition_seconds"].as<double>(),
                   1.8 * expected.groups.size());
  std::cout << "[ figure ] default rig (plan_timing_groups): " << expected.groups.size()
            << " groups, " << 0.5 * expected.groups.size() << " s, " << expected.conflicts.size()
            << " conflicts\n";

  // Aligned files: the alignment's pose wins over the rig's. Pole c "aligned" 3 m higher lights
  // and sees nothing of the subject: its conflicts vanish.
  std::vector<PairGeometry> moved = truth;
  const Eigen::Isometry3d raised(Eigen::Translation3d(0, 0, 3.0));
  for (auto& pair : moved) {
    if (pair.pair_id.rfind("pole_c/", 0) == 0)
      pair.world_from_camera = raised * pair.world_from_camera;
    pair.calibration.alignment =
        body_scan_driver::WorldAlignment{pair.world_from_camera, Eigen::Matrix3d::Identity()};
    saveCalibration((dir / (fileStem(pair.pair_id) + ".yaml")).string(), pair.calibration);
  }
  const auto [aligned_status, aligned_report] = plan(dir, "");
  ASSERT_EQ(aligned_status, 0);
  const TimingPlan moved_plan = planTimingGroups(moved);
  EXPECT_EQ(groupsOf(aligned_report), moved_plan.groups);
  for (const auto& [a, b] : moved_plan.conflicts)
    EXPECT_TRUE(a.rfind("pole_c/", 0) != 0 && b.rfind("pole_c/", 0) != 0) << a << " " << b;
  EXPECT_EQ(aligned_report["conflicts"].size(), moved_plan.conflicts.size());

  // A missing file: exit 1, no report.
  fs::remove(dir / "pole_b_pair_3.yaml");
  const auto [missing_status, missing_report] = plan(dir, "");
  EXPECT_EQ(missing_status, 1);
  EXPECT_TRUE(missing_report.IsNull());
  std::ifstream output(dir / "out.txt");
  const std::string text((std::istreambuf_iterator<char>(output)), {});
  EXPECT_NE(text.find("pole_b_pair_3.yaml"), std::string::npos) << text;
  fs::remove_all(dir);
}
