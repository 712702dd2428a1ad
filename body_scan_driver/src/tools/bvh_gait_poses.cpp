// Prints the four representative poses of thesis 5.3 found in BVH walks (sim/bvh_body.h):
//
//   bvh_gait_poses [--map config/bvh/cmu_joint_map.yaml] WALK.bvh [WALK.bvh ...]
//
// One line per walk: the 1-based frame numbers (as in the file) and times of poses 1-4, the
// walking speed, the stride at pose 1 and the stature the legs imply (girths follow it).
#include <body_scan_driver/sim/bvh_body.h>
#include <body_scan_driver/tools/command_line.h>
#include <body_scan_driver/tools/package_file.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  using namespace body_scan_driver::sim;
  CLI::App app("Prints the four representative poses of thesis 5.3 found in BVH walks.",
               "bvh_gait_poses");
  std::string map_path;
  std::vector<std::string> files;
  app.add_option("--map", map_path,
                 "BVH joint map (default: body_scan_driver's config/bvh/cmu_joint_map.yaml)")
      ->check(CLI::ExistingFile);
  app.add_option("WALK.bvh", files, "motion-capture walks")->required();
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  int failures = 0;
  try {
    if (map_path.empty())
      map_path = body_scan_driver::tools::packageFile("body_scan_driver",
                                                      "config/bvh/cmu_joint_map.yaml", "--map");
    const BvhJointMap map = loadBvhJointMap(map_path);
    std::printf("%-8s %6s %-29s %-33s %9s %9s %9s\n", "walk", "frames",
                "pose frames 1 2 3 4 (1-based)", "times s", "speed m/s", "stride m", "stature m");
    for (const std::string& file : files) {
      try {
        const BvhSubject subject(loadBvh(file), map, std::filesystem::path(file).stem().string());
        const GaitPoseFrames poses = pickGaitPoses(subject);
        const double dt = subject.motion().frame_time;
        const auto stance = subject.joints(poses.frame[0]);
        const double stride = (stance.at("right_ankle") - stance.at("left_ankle")).head<2>().norm();
        std::printf("%-8s %6d %6d %6d %6d %6d        %7.3f %7.3f %7.3f %7.3f  %9.2f %9.2f %9.2f\n",
                    subject.name().c_str(), subject.frameCount(), poses.frame[0] + 1,
                    poses.frame[1] + 1, poses.frame[2] + 1, poses.frame[3] + 1, poses.frame[0] * dt,
                    poses.frame[1] * dt, poses.frame[2] * dt, poses.frame[3] * dt,
                    poses.walking_speed, stride, subject.estimatedStature());
      } catch (const std::exception& error) {
        std::fprintf(stderr, "bvh_gait_poses: %s\n", error.what());
        ++failures;
      }
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "bvh_gait_poses: %s\n", error.what());
    return 1;
  }
  return failures == 0 ? 0 : 1;
}
