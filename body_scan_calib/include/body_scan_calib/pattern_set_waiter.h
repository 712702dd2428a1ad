// The pattern sets capture_calibration_views waits for, by scan id. Any node may publish on the
// topic: a set that fails checkPatternSet (body_scan_driver/ros/message_checks.h) is not kept;
// its problem is logged (throttled) and remembered for its scan id, so that a capture whose set
// never arrives whole fails naming the field instead of a bare time-out.
#pragma once

#include <body_scan_driver/ros/message_checks.h>
#include <body_scan_msgs/PatternSet.h>

#include <condition_variable>
#include <map>
#include <mutex>
#include <optional>
#include <string>

namespace body_scan_calib {

class PatternSetWaiter {
 public:
  // The subscriber callback; never throws.
  void onPatternSet(const body_scan_msgs::PatternSet::ConstPtr& set);

  // The checked set of `scan_id`, waiting up to `timeout_s` (less once ROS shuts down); nullptr
  // if none arrived. Forgets every set received so far.
  body_scan_msgs::PatternSet::ConstPtr waitFor(uint32_t scan_id, double timeout_s);

  // Why the last set of `scan_id` that failed the check was rejected, if one did.
  std::optional<std::string> rejection(uint32_t scan_id) const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::map<uint32_t, body_scan_msgs::PatternSet::ConstPtr> received_;
  std::map<uint32_t, std::string> rejected_;
  body_scan_driver::ProblemThrottle throttle_;
};

}  // namespace body_scan_calib
