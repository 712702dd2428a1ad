// Watches /diagnostics and the simulated pair's pattern sets for a few seconds (see
// usb_missing_device.test): the usb pair without its camera reports ERROR naming the device and
// list_devices, keeps retrying with growing intervals, and the simulated pair in the same
// manager keeps publishing; a pair with an unknown backend reports ERROR naming the backends.
#include <body_scan_driver/test_time_scale.h>
#include <body_scan_msgs/PatternSet.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <algorithm>
#include <mutex>

using body_scan_driver::scaledSeconds;

namespace {

struct Observed {
  ros::WallTime time;
  diagnostic_msgs::DiagnosticStatus status;
};

std::string valueOf(const diagnostic_msgs::DiagnosticStatus& status, const std::string& key) {
  for (const auto& kv : status.values)
    if (kv.key == key) return kv.value;
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(UsbMissingDevice, ErrorDiagnosticsRetriesAndTheSimPairKeepsWorking) {
  ros::NodeHandle nh, pnh("~");
  const std::string usb_pair = pnh.param<std::string>("usb_pair", "pole_b/pair_2");
  const std::string missing = pnh.param<std::string>("missing_device", "1234:5678/NOSUCHCAM");
  const std::string sim_topic =
      pnh.param<std::string>("sim_pattern_topic", "/pole_a/pair_1/pattern_set");
  const double duration = scaledSeconds(pnh.param("duration", 6.0));

  std::mutex mutex;
  const std::string unknown_backend_pair =
      pnh.param<std::string>("unknown_backend_pair", "pole_c/pair_1");
  std::vector<Observed> usb_statuses, sim_statuses, unknown_backend_statuses;
  std::vector<ros::WallTime> sim_sets;
  const auto diagnostics_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 50, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& array) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& status : array->status) {
          if (contains(status.name, "pair " + usb_pair))
            usb_statuses.push_back({ros::WallTime::now(), status});
          else if (contains(status.name, "pair pole_a/pair_1"))
            sim_statuses.push_back({ros::WallTime::now(), status});
          else if (contains(status.name, "pair " + unknown_backend_pair))
            unknown_backend_statuses.push_back({ros::WallTime::now(), status});
        }
      });
  const auto sets_sub = nh.subscribe<body_scan_msgs::PatternSet>(
      sim_topic, 10, [&](const body_scan_msgs::PatternSet::ConstPtr&) {
        std::lock_guard<std::mutex> lock(mutex);
        sim_sets.push_back(ros::WallTime::now());
      });

  // Wait for the first usb diagnostic (nodelets loading), then watch for `duration`.
  const ros::WallTime start = ros::WallTime::now();
  while (ros::ok() && (ros::WallTime::now() - start).toSec() < scaledSeconds(30)) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (!usb_statuses.empty()) break;
    }
    ros::WallDuration(0.05).sleep();
  }
  {
    std::lock_guard<std::mutex> lock(mutex);
    ASSERT_FALSE(usb_statuses.empty()) << "no /diagnostics status for pair " << usb_pair;
    usb_statuses.clear();
    sim_sets.clear();
    sim_statuses.clear();
  }
  ros::WallDuration(duration).sleep();
  std::lock_guard<std::mutex> lock(mutex);

  // ERROR naming the missing device and how to list devices, in every message.
  ASSERT_GE(usb_statuses.size(), 10u) << "diagnostics must keep coming";
  for (const Observed& observed : usb_statuses) {
    const auto& status = observed.status;
    EXPECT_EQ(status.level, diagnostic_msgs::DiagnosticStatus::ERROR) << status.message;
    EXPECT_TRUE(contains(status.message, missing)) << status.message;
    EXPECT_TRUE(contains(status.message, "rosrun body_scan_driver list_devices")) << status.message;
    EXPECT_TRUE(contains(status.hardware_id, missing)) << status.hardware_id;
    EXPECT_EQ(valueOf(status, "state"), "ERROR");
  }
  std::cout << "[ figure ] usb pair: \"" << usb_statuses.back().status.message << "\"\n";

  // Retries continue, each with a longer interval than the one before (until the maximum).
  std::vector<int> attempts;
  std::vector<double> intervals, first_seen;
  for (const Observed& observed : usb_statuses) {
    const int attempt = std::stoi(valueOf(observed.status, "connection attempts"));
    if (!attempts.empty() && attempt == attempts.back()) continue;
    attempts.push_back(attempt);
    intervals.push_back(std::stod(valueOf(observed.status, "retry interval (s)")));
    first_seen.push_back((observed.time - start).toSec());
  }
  ASSERT_GE(attempts.size(), 3u) << "retries must continue during " << duration << " s";
  for (size_t i = 1; i < attempts.size(); ++i) {
    EXPECT_GT(attempts[i], attempts[i - 1]);
    EXPECT_TRUE(intervals[i] > intervals[i - 1] || intervals[i] == 4.0)
        << "retry interval " << intervals[i] << " after " << intervals[i - 1];
  }
  // The measured time between observed attempts grows too.
  const size_t n = first_seen.size();
  EXPECT_GT(first_seen[n - 1] - first_seen[n - 2], first_seen[1] - first_seen[0]);
  std::cout << "[ figure ] usb pair retries seen:";
  for (size_t i = 0; i < n; ++i)
    std::cout << " #" << attempts[i] << " (next in " << intervals[i] << " s)";
  std::cout << "\n";

  // The simulated pair in the same manager keeps working: pattern sets throughout the window
  // (its rate is 2 Hz; rendering on a loaded machine may be slower, but never stops).
  std::cout << "[ figure ] simulated pair: " << sim_sets.size() << " pattern sets in " << duration
            << " s\n";
  ASSERT_GE(sim_sets.size(), 3u);
  double longest_gap = 0;
  for (size_t i = 1; i < sim_sets.size(); ++i)
    longest_gap = std::max(longest_gap, (sim_sets[i] - sim_sets[i - 1]).toSec());
  std::cout << "[ figure ] simulated pair: longest gap between pattern sets " << longest_gap
            << " s\n";
  EXPECT_LT(longest_gap, scaledSeconds(3.0));
  ASSERT_FALSE(sim_statuses.empty());
  EXPECT_EQ(sim_statuses.back().status.level, diagnostic_msgs::DiagnosticStatus::OK);

  // The pair whose backend does not exist: ERROR naming it and the backends there are.
  ASSERT_FALSE(unknown_backend_statuses.empty()) << "no status for " << unknown_backend_pair;
  const auto& unknown = unknown_backend_statuses.back().status;
  std::cout << "[ figure ] unknown backend: \"" << unknown.message << "\"\n";
  EXPECT_EQ(unknown.level, diagnostic_msgs::DiagnosticStatus::ERROR);
  EXPECT_TRUE(contains(unknown.message, "backend 'nosuch' is unknown")) << unknown.message;
  EXPECT_TRUE(contains(unknown.message, "available backends: sim, usb")) << unknown.message;
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_usb_missing_device");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
