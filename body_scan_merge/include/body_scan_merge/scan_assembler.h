// Collects the pair clouds of whole-body scans (Merge nodelet, DESIGN.md section 3): a scan is
// complete when every expected pair has delivered, or when `timeout` has passed since its first
// cloud (then it is assembled from the pairs that did, and the others are reported missing).
// ROS-agnostic: time is a number of seconds passed in by the caller (tests use a fake clock).
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace body_scan_merge {

template <typename Part>
class ScanAssembler {
 public:
  struct Scan {
    uint32_t scan_id = 0;
    std::vector<std::pair<std::string, Part>> parts;  // in the expected pairs' order
    std::vector<std::string> missing;                 // expected pairs that did not deliver
  };
  enum class Arrival { kAccepted, kUnknownPair, kLate, kRepeated };

  ScanAssembler(std::vector<std::string> expected_pairs, double timeout)
      : expected_(std::move(expected_pairs)), timeout_(timeout) {
    if (expected_.empty()) throw std::invalid_argument("a scan needs at least one expected pair");
  }

  // Adds one pair's cloud; completed scans are appended to `done` (in scan-id order).
  Arrival add(const std::string& pair_id, uint32_t scan_id, Part part, double now,
              std::vector<Scan>& done) {
    const auto slot = std::find(expected_.begin(), expected_.end(), pair_id);
    if (slot == expected_.end()) return Arrival::kUnknownPair;
    if (std::find(finished_.begin(), finished_.end(), scan_id) != finished_.end())
      return Arrival::kLate;
    Pending& pending = pending_[scan_id];
    if (pending.parts.empty()) {
      pending.first_arrival = now;
      pending.parts.resize(expected_.size());
    }
    auto& entry = pending.parts[slot - expected_.begin()];
    if (entry.first) return Arrival::kRepeated;
    entry = {true, std::move(part)};
    if (++pending.count == expected_.size()) finish(scan_id, done);
    return Arrival::kAccepted;
  }

  // Finishes the scans whose timeout has passed; call periodically.
  void poll(double now, std::vector<Scan>& done) {
    std::vector<uint32_t> expired;
    for (const auto& [scan_id, pending] : pending_)
      if (now - pending.first_arrival >= timeout_) expired.push_back(scan_id);
    for (uint32_t scan_id : expired) finish(scan_id, done);
  }

  const std::vector<std::string>& expectedPairs() const { return expected_; }
  size_t pendingScans() const { return pending_.size(); }

 private:
  struct Pending {
    double first_arrival = 0;
    size_t count = 0;
    std::vector<std::pair<bool, Part>> parts;  // (arrived, part) per expected pair
  };

  void finish(uint32_t scan_id, std::vector<Scan>& done) {
    Pending& pending = pending_.at(scan_id);
    Scan scan;
    scan.scan_id = scan_id;
    for (size_t i = 0; i < expected_.size(); ++i) {
      if (pending.parts[i].first)
        scan.parts.emplace_back(expected_[i], std::move(pending.parts[i].second));
      else
        scan.missing.push_back(expected_[i]);
    }
    pending_.erase(scan_id);
    finished_.push_back(scan_id);
    if (finished_.size() > kRememberedScans) finished_.pop_front();
    done.push_back(std::move(scan));
  }

  static constexpr size_t kRememberedScans = 64;  // ids whose late clouds are recognised
  std::vector<std::string> expected_;
  double timeout_;
  std::map<uint32_t, Pending> pending_;
  std::deque<uint32_t> finished_;
};

}  // namespace body_scan_merge
