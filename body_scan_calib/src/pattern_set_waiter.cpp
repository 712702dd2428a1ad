#include <body_scan_calib/pattern_set_waiter.h>
#include <ros/ros.h>

#include <chrono>

namespace body_scan_calib {
namespace {

// Sets of scan ids nobody waits for (another sender's) are dropped beyond this many.
constexpr size_t kMaxKept = 64;

template <typename Map>
void keepBounded(Map& map) {
  while (map.size() > kMaxKept) map.erase(map.begin());
}

}  // namespace

void PatternSetWaiter::onPatternSet(const body_scan_msgs::PatternSet::ConstPtr& set) {
  try {
    const auto problem = body_scan_driver::checkPatternSet(*set);
    std::lock_guard<std::mutex> lock(mutex_);
    if (problem) {
      rejected_[set->scan_id] = *problem;
      keepBounded(rejected_);
      if (throttle_.shouldReport(*problem, ros::WallTime::now().toSec()))
        ROS_ERROR("pattern set of '%s' (scan %u) rejected: %s", set->pair_id.c_str(), set->scan_id,
                  problem->c_str());
      return;
    }
    received_[set->scan_id] = set;
    keepBounded(received_);
    arrived_.notify_all();
  } catch (const std::exception& e) {  // bad_alloc: lose the set, not the node
    ROS_ERROR_THROTTLE(5.0, "pattern set of scan %u dropped: %s", set->scan_id, e.what());
  }
}

body_scan_msgs::PatternSet::ConstPtr PatternSetWaiter::waitFor(uint32_t scan_id, double timeout_s) {
  std::unique_lock<std::mutex> lock(mutex_);
  arrived_.wait_for(lock, std::chrono::duration<double>(timeout_s),
                    [&] { return received_.count(scan_id) > 0 || !ros::ok(); });
  const auto found = received_.find(scan_id);
  body_scan_msgs::PatternSet::ConstPtr set = found == received_.end() ? nullptr : found->second;
  received_.clear();
  return set;
}

std::optional<std::string> PatternSetWaiter::rejection(uint32_t scan_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto found = rejected_.find(scan_id);
  if (found == rejected_.end()) return std::nullopt;
  return found->second;
}

}  // namespace body_scan_calib
