// full_scanner.launch with backend:=usb and no devices attached (see usb_full_scanner.test):
// every pair reports ERROR on /diagnostics naming its missing camera, the three pole managers
// stay up with all their nodelets, and /body_scan/capture answers with a failure that names
// every missing pair instead of hanging.
#include <body_scan_driver/test_time_scale.h>
#include <body_scan_msgs/Scan.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nodelet/NodeletList.h>
#include <ros/ros.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

using body_scan_driver::scaledSeconds;

namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::vector<std::string> param(ros::NodeHandle& pnh, const std::string& name) {
  std::vector<std::string> values;
  pnh.getParam(name, values);
  return values;
}

// The nodelets a pole's manager runs, or nothing if its list service does not answer.
std::vector<std::string> nodeletsOf(const std::string& pole) {
  nodelet::NodeletList list;
  if (!ros::service::call("/" + pole + "/manager/list", list)) return {};
  return list.response.nodelets;
}

}  // namespace

TEST(UsbFullScanner, EveryPairReportsItsMissingDeviceAndNothingCrashes) {
  ros::NodeHandle nh, pnh("~");
  const std::vector<std::string> pairs = param(pnh, "pairs");
  const std::vector<std::string> devices = param(pnh, "missing_devices");  // one per pair
  const std::vector<std::string> poles = param(pnh, "poles");
  ASSERT_EQ(pairs.size(), 12u);
  ASSERT_EQ(devices.size(), pairs.size());
  const ros::WallTime start = ros::WallTime::now();

  // 1. Every pair's latest status is an ERROR naming its own camera (drivers come up, poll).
  std::mutex mutex;
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> latest;  // by pair id
  const auto diagnostics_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 100, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& array) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& status : array->status)
          for (const std::string& pair : pairs)
            if (contains(status.name, "pair " + pair)) latest[pair] = status;
      });
  const auto all_report_their_device = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    for (size_t i = 0; i < pairs.size(); ++i) {
      const auto it = latest.find(pairs[i]);
      if (it == latest.end() || it->second.level != diagnostic_msgs::DiagnosticStatus::ERROR ||
          !contains(it->second.message, devices[i]))
        return false;
    }
    return true;
  };
  const ros::WallTime deadline =
      start + ros::WallDuration(scaledSeconds(pnh.param("startup_timeout", 30.0)));
  while (!all_report_their_device() && ros::WallTime::now() < deadline)
    ros::WallDuration(0.05).sleep();
  {
    std::lock_guard<std::mutex> lock(mutex);
    for (size_t i = 0; i < pairs.size(); ++i) {
      const auto it = latest.find(pairs[i]);
      ASSERT_NE(it, latest.end()) << "no /diagnostics status for pair " << pairs[i];
      const auto& status = it->second;
      EXPECT_EQ(status.level, diagnostic_msgs::DiagnosticStatus::ERROR)
          << pairs[i] << ": " << status.message;
      EXPECT_TRUE(contains(status.message, devices[i])) << pairs[i] << ": " << status.message;
      EXPECT_TRUE(contains(status.hardware_id, devices[i])) << status.hardware_id;
    }
    std::cout << "[ figure ] all 12 pairs ERROR after " << (ros::WallTime::now() - start).toSec()
              << " s; e.g. \"" << latest[pairs[0]].message << "\"\n";
  }

  // 2. /body_scan/capture answers, failed, naming every pair missing. In a thread of its own
  // so that a hang is a failure with a message, not a test timeout.
  ASSERT_TRUE(ros::service::waitForService("/body_scan/capture", ros::Duration(scaledSeconds(30))));
  auto scan = std::make_shared<body_scan_msgs::Scan>();
  std::promise<bool> answered;
  std::future<bool> answer = answered.get_future();
  std::thread([scan, done = std::move(answered)]() mutable {
    done.set_value(ros::service::call("/body_scan/capture", *scan));
  }).detach();
  const double capture_timeout = scaledSeconds(pnh.param("capture_timeout", 20.0));
  ASSERT_EQ(answer.wait_for(std::chrono::duration<double>(capture_timeout)),
            std::future_status::ready)
      << "/body_scan/capture did not answer within " << capture_timeout << " s";
  ASSERT_TRUE(answer.get()) << "/body_scan/capture call failed";
  const auto& response = scan->response;
  std::cout << "[ figure ] capture response: " << response.message << "\n";
  EXPECT_FALSE(response.success);
  std::vector<std::string> expected_missing = pairs;
  std::sort(expected_missing.begin(), expected_missing.end());
  EXPECT_EQ(response.pairs_missing, expected_missing);
  for (const std::string& pair : pairs)
    EXPECT_TRUE(contains(response.message, "missing " + pair)) << response.message;

  // 3. Nothing crashed: every pole's manager still answers and runs its 4 drivers and 4
  // Triangulates.
  for (const std::string& pole : poles) {
    const std::vector<std::string> nodelets = nodeletsOf(pole);
    EXPECT_EQ(nodelets.size(), 8u) << "/" << pole << "/manager does not answer or lost nodelets";
    for (int i = 1; i <= 4; ++i) {
      const std::string driver = "/" + pole + "/pair_" + std::to_string(i) + "/driver";
      EXPECT_NE(std::find(nodelets.begin(), nodelets.end(), driver), nodelets.end())
          << driver << " is not loaded in /" << pole << "/manager";
    }
  }
  std::cout << "[ figure ] test took " << (ros::WallTime::now() - start).toSec() << " s\n";
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_usb_full_scanner");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
