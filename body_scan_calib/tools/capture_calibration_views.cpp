// Captures the views calibrate_pair needs through a running PairDriver: for
// each reference-plane pose of the rig (calibration_rig.h) the board is placed - by the
// simulator's ~set_scene service or by the operator, who presses Enter - and the pair captures
// it `exposures` times (averaged: a static target); then the five evaluation spheres. Writes
// FOLDER/pose_NN/frame_MM.png and FOLDER/spheres (calibrate_pair --images) and/or records the
// raw PatternSets into a bag (bag_to_calibration_folder); optionally runs calibrate_pair on the
// folder. Exits when done (0 = success).
#include <body_scan_calib/calibration_bag.h>
#include <body_scan_calib/calibration_capture.h>
#include <body_scan_calib/calibration_rig.h>
#include <body_scan_calib/capture_folder.h>
#include <body_scan_calib/pattern_set_waiter.h>
#include <body_scan_driver/rig_layout.h>
#include <body_scan_msgs/Capture.h>
#include <body_scan_msgs/PatternSet.h>
#include <body_scan_msgs/SetScene.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>

using namespace body_scan_driver;
namespace fs = std::filesystem;

namespace {

struct Settings {
  std::string folder, bag, targets, driver, pair_file;
  int exposures = 16, pose_count = 0;
  bool spheres = true, calibrate = false;
  double capture_timeout = 30.0;
  std::string calibrate_pair, calibration_file, report_file, plot_file;
  std::string pair_id;  // ~pair_id, else the captured pattern sets' pair_id
};

// One placement of a target: a scene for the simulator, words for the operator.
struct Placement {
  std::string name;  // "pose 3/11", "spheres"
  std::string folder_name;
  std::string scene_yaml;
  std::string instructions;
};

// Scan ids: placement p uses 1000 (p + 1) + exposure, so each placement is one run of
// consecutive ids and bag_to_calibration_folder recovers the placements from a bag.
constexpr uint32_t kScanIdsPerPlacement = 1000;

std::string describeBoardPose(const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d normal = pose.linear().col(2);
  const double tilt_deg = std::acos(std::min(1.0, std::abs(normal.z()))) * 180 / M_PI;
  // Camera optical frame: x right, y down, z forward.
  const Eigen::Vector3d& c = pose.translation();
  char text[200];
  std::snprintf(text, sizeof(text),
                "centre %.0f mm %s, %.0f mm %s, %.0f mm in front of the camera, tilted "
                "%.0f deg from facing it",
                std::abs(c.x()) * 1e3, c.x() < 0 ? "left" : "right", std::abs(c.y()) * 1e3,
                c.y() < 0 ? "up" : "down", c.z() * 1e3, tilt_deg);
  return text;
}

std::vector<Placement> placements(const Settings& settings,
                                  const Eigen::Isometry3d& world_from_camera) {
  const body_scan_calib::Checkerboard board =
      body_scan_calib::referenceBoard();  // calibrate_pair's board
  std::vector<Eigen::Isometry3d> poses = body_scan_calib::rig::defaultBoardPoses();
  if (settings.pose_count > 0 && settings.pose_count < static_cast<int>(poses.size()))
    poses.resize(settings.pose_count);
  std::vector<Placement> result;
  for (size_t p = 0; p < poses.size(); ++p)
    result.push_back({"pose " + std::to_string(p + 1) + "/" + std::to_string(poses.size()),
                      body_scan_calib::poseFolderName(static_cast<int>(p)),
                      body_scan_calib::boardSceneYaml(board, poses[p], world_from_camera),
                      "place the board (" + std::to_string(board.inner_cols) + "x" +
                          std::to_string(board.inner_rows) + " inner corners) with its " +
                          describeBoardPose(poses[p])});
  if (settings.spheres) {
    const auto centers = body_scan_calib::rig::defaultSphereCenters();
    result.push_back({"spheres", body_scan_calib::kSphereFolderName,
                      body_scan_calib::sphereSceneYaml(centers, 0.025, world_from_camera),
                      "remove the board; place the five 25 mm spheres about 1 m in front of the "
                      "pair, one in the centre and one toward each image corner (Fig 3.7)"});
  }
  return result;
}

// calibrate_pair is installed next to this node (devel and install space alike).
std::string siblingCalibratePair() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  return error ? "calibrate_pair" : (self.parent_path() / "calibrate_pair").string();
}

int runCalibratePair(const Settings& settings, int bits, const std::string& pair_id) {
  std::vector<std::string> arguments = {settings.calibrate_pair,
                                        "--images",
                                        settings.folder,
                                        "--pair-id",
                                        pair_id,
                                        "--bits",
                                        std::to_string(bits),
                                        "--exposures",
                                        std::to_string(settings.exposures),
                                        "--output",
                                        settings.calibration_file,
                                        "--report",
                                        settings.report_file,
                                        "--plot",
                                        settings.plot_file};
  std::string line;
  for (const std::string& argument : arguments) line += argument + " ";
  ROS_INFO("running %s", line.c_str());
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  // Made before fork: a child of this multi-threaded node must not allocate.
  const std::string exec_error = "cannot run " + settings.calibrate_pair;
  const pid_t child = fork();
  if (child == 0) {
    execvp(argv[0], argv.data());
    std::perror(exec_error.c_str());
    _exit(127);
  }
  if (child < 0) return -1;
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The node's parameters, checked: throws std::invalid_argument naming the parameter.
Settings readSettings(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
  Settings settings;
  pnh.param<std::string>("folder", settings.folder, "");
  pnh.param<std::string>("bag", settings.bag, "");
  pnh.param<std::string>("targets", settings.targets, "sim");
  pnh.param<std::string>("driver", settings.driver, "driver");
  pnh.param("exposures", settings.exposures, 16);
  pnh.param("pose_count", settings.pose_count, 0);
  pnh.param("spheres", settings.spheres, true);
  pnh.param("capture_timeout", settings.capture_timeout, 30.0);
  pnh.param("calibrate", settings.calibrate, false);
  pnh.param<std::string>("calibrate_pair", settings.calibrate_pair, siblingCalibratePair());
  pnh.param<std::string>("calibration_file", settings.calibration_file, "");
  pnh.param<std::string>("report_file", settings.report_file, "");
  pnh.param<std::string>("plot_file", settings.plot_file, "");
  pnh.param<std::string>("pair_id", settings.pair_id, "");
  // The simulator's scenes are in the world: the pair's pose comes from the driver's pair file.
  if (!pnh.getParam("pair_file", settings.pair_file))
    nh.param<std::string>(settings.driver + "/pair_file", settings.pair_file, "");

  if (settings.folder.empty() && settings.bag.empty())
    throw std::invalid_argument("set ~folder (image folder) and/or ~bag (record the sets)");
  if (settings.targets != "sim" && settings.targets != "operator")
    throw std::invalid_argument("~targets must be 'sim' (placed through " + settings.driver +
                                "/set_scene) or 'operator' (placed by hand), not '" +
                                settings.targets + "'");
  if (settings.exposures < 1 || settings.exposures >= static_cast<int>(kScanIdsPerPlacement))
    throw std::invalid_argument("~exposures must be in 1..999");
  if (settings.calibrate && (settings.folder.empty() || settings.calibration_file.empty() ||
                             settings.report_file.empty() || settings.plot_file.empty()))
    throw std::invalid_argument(
        "~calibrate needs ~folder, ~calibration_file, ~report_file and ~plot_file");
  return settings;
}

// The running PairDriver: its pattern sets, its ~capture and (simulator) ~set_scene services.
struct Driver {
  ros::Subscriber pattern_sub;
  ros::ServiceClient capture_client, scene_client;
};

// Waits (up to ~capture_timeout each) for the services and a pattern set publisher; throws
// naming what is missing and the fix.
void waitForDriver(const Settings& settings, Driver& driver) {
  ROS_INFO("waiting for %s and a publisher on %s", driver.capture_client.getService().c_str(),
           driver.pattern_sub.getTopic().c_str());
  if (!driver.capture_client.waitForExistence(ros::Duration(settings.capture_timeout)))
    throw std::runtime_error("no service " + driver.capture_client.getService() +
                             ": start the PairDriver (or set ~driver to its node name)");
  if (settings.targets == "sim" &&
      !driver.scene_client.waitForExistence(ros::Duration(settings.capture_timeout)))
    throw std::runtime_error("no service " + driver.scene_client.getService() +
                             ": the driver must be the simulator (backend:=sim)");
  for (ros::WallTime end = ros::WallTime::now() + ros::WallDuration(settings.capture_timeout);
       driver.pattern_sub.getNumPublishers() == 0; ros::WallDuration(0.05).sleep())
    if (ros::WallTime::now() > end || !ros::ok())
      throw std::runtime_error("nobody publishes " + driver.pattern_sub.getTopic() +
                               ": remap pattern_set to the driver's topic");
}

// Puts placement `p` of `count` in front of the pair: the simulator's ~set_scene, or the
// operator (Enter when done).
void placeTarget(const Settings& settings, const Placement& placement, size_t p, size_t count,
                 Driver& driver) {
  if (settings.targets == "sim") {
    body_scan_msgs::SetScene set_scene;
    set_scene.request.scene_yaml = placement.scene_yaml;
    // The driver opens its pair before it advertises ~set_scene: one call is the answer.
    if (!driver.scene_client.call(set_scene) || !set_scene.response.success)
      throw std::runtime_error("cannot place the " + placement.name + " target: " +
                               (set_scene.response.message.empty()
                                    ? "no service " + driver.scene_client.getService()
                                    : set_scene.response.message));
    std::cout << "[" << p + 1 << "/" << count << "] " << placement.name
              << ": target placed, capturing " << settings.exposures << " exposure(s)" << std::endl;
  } else {
    std::cout << "[" << p + 1 << "/" << count << "] " << placement.name << ": "
              << placement.instructions << ", then press Enter" << std::endl;
    std::string line;
    if (!std::getline(std::cin, line))
      throw std::runtime_error("no operator input (stdin closed): run with rosrun in a terminal");
  }
}

// What the captures of the run tell the calibration: the sets' bits and pair id.
struct CapturedSets {
  int bits = 0;
  std::string pair_id;
};

// ~exposures captures of placement `p`: each recorded into `bag` (if any); with ~folder, their
// frames averaged and written into the placement's folder.
void capturePlacement(const Settings& settings, const Placement& placement, size_t p,
                      body_scan_calib::PatternSetWaiter& waiter, Driver& driver, rosbag::Bag* bag,
                      CapturedSets& captured) {
  std::vector<std::vector<cv::Mat>> captures;
  for (int exposure = 0; exposure < settings.exposures; ++exposure) {
    body_scan_msgs::Capture capture;
    capture.request.scan_id = kScanIdsPerPlacement * static_cast<uint32_t>(p + 1) + exposure;
    if (!driver.capture_client.call(capture) || !capture.response.success)
      throw std::runtime_error(
          placement.name + ": capture failed: " +
          (capture.response.message.empty() ? "service call failed" : capture.response.message));
    const auto set = waiter.waitFor(capture.response.scan_id, settings.capture_timeout);
    if (!set) {
      const auto rejection = waiter.rejection(capture.response.scan_id);
      throw std::runtime_error(
          placement.name + ": pattern set of scan " + std::to_string(capture.response.scan_id) +
          " not received on " + driver.pattern_sub.getTopic() + " within " +
          std::to_string(settings.capture_timeout) + " s" +
          (rejection ? " (the set of that scan was rejected: " + *rejection + ")" : ""));
    }
    captured.bits = set->bits;
    if (captured.pair_id.empty()) captured.pair_id = set->pair_id;
    if (bag) bag->write(driver.pattern_sub.getTopic(), ros::Time::now(), *set);
    if (!settings.folder.empty()) captures.push_back(body_scan_calib::patternFrames(*set));
  }
  if (!settings.folder.empty()) {
    const std::string folder = (fs::path(settings.folder) / placement.folder_name).string();
    body_scan_calib::savePatternFrames(folder, body_scan_calib::averageCaptures(captures));
    std::cout << "    wrote " << folder << std::endl;
  }
}

int run(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
  const Settings settings = readSettings(nh, pnh);
  Eigen::Isometry3d world_from_camera = Eigen::Isometry3d::Identity();
  if (settings.targets == "sim" && !settings.pair_file.empty())
    world_from_camera = body_scan_driver::loadPairFilePose(settings.pair_file);
  const std::vector<Placement> plan = placements(settings, world_from_camera);

  body_scan_calib::PatternSetWaiter waiter;
  Driver driver;
  driver.pattern_sub =
      nh.subscribe("pattern_set", 4, &body_scan_calib::PatternSetWaiter::onPatternSet, &waiter);
  driver.capture_client = nh.serviceClient<body_scan_msgs::Capture>(settings.driver + "/capture");
  driver.scene_client = nh.serviceClient<body_scan_msgs::SetScene>(settings.driver + "/set_scene");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  waitForDriver(settings, driver);

  // Captures of an earlier run (more poses, spheres) would be read with this run's.
  if (!settings.folder.empty()) {
    const int removed = body_scan_calib::removeOldCaptures(settings.folder);
    if (removed > 0)
      std::cout << "removed " << removed << " capture folders of an earlier run from "
                << settings.folder << std::endl;
  }
  std::unique_ptr<rosbag::Bag> bag;
  const std::string bag_active = settings.bag + ".active";  // renamed when complete
  if (!settings.bag.empty()) {
    if (fs::path(settings.bag).has_parent_path())
      fs::create_directories(fs::path(settings.bag).parent_path());
    bag = std::make_unique<rosbag::Bag>(bag_active, rosbag::bagmode::Write);
  }

  CapturedSets captured{0, settings.pair_id};
  for (size_t p = 0; p < plan.size(); ++p) {
    placeTarget(settings, plan[p], p, plan.size(), driver);
    capturePlacement(settings, plan[p], p, waiter, driver, bag.get(), captured);
  }
  if (bag) {
    bag->close();
    fs::rename(bag_active, settings.bag);
    std::cout << "recorded " << plan.size() * settings.exposures << " pattern sets into "
              << settings.bag << " (bag_to_calibration_folder " << settings.bag << " FOLDER"
              << (settings.spheres ? " --spheres-last" : "") << ")" << std::endl;
  }
  if (!settings.calibrate) return 0;
  std::cout << "calibrating from " << settings.folder << std::endl;
  const int status = runCalibratePair(settings, captured.bits,
                                      captured.pair_id.empty() ? "pair" : captured.pair_id);
  if (status != 0)
    throw std::runtime_error("calibrate_pair failed (exit status " + std::to_string(status) +
                             "); its error is printed above");
  std::cout << "calibration written to " << settings.calibration_file << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "capture_calibration_views");
  ros::NodeHandle nh, pnh("~");
  try {
    return run(nh, pnh);
  } catch (const std::exception& e) {
    ROS_ERROR("capture_calibration_views: %s", e.what());
    return 1;
  }
}
