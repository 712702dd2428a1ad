// ScanAssembler: collects the pair clouds of one whole-body scan by scan id (ROS-agnostic).
// A scan is ready when every expected pair has delivered, or when `timeout` seconds have passed
// since its first cloud (the missing pairs are then reported and the scan goes out without
// them). Clouds of an already-published scan are late and dropped; several scan ids may be
// pending at once, so a newer scan never discards an older incomplete one. Time is passed in
// explicitly (seconds on any monotonic clock), so tests drive it with a fake clock.
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace body_scan {

template <class Cloud>
class ScanAssembler {
 public:
  struct Scan {
    uint32_t scan_id = 0;
    std::map<std::string, Cloud> clouds;  // pair id -> cloud, the pairs present
    std::vector<std::string> missing;     // expected pairs without a cloud (timed out)
    double first_arrival = 0;             // time of the scan's first cloud
  };
  enum class AddResult { kAccepted, kLate, kDuplicate, kUnexpectedPair };

  ScanAssembler(std::vector<std::string> expected_pairs, double timeout)
      : expected_(std::move(expected_pairs)), timeout_(timeout) {}

  const std::vector<std::string>& expectedPairs() const { return expected_; }
  double timeout() const { return timeout_; }
  size_t pendingScans() const { return pending_.size(); }

  // Files `cloud` under (scan_id, pair_id). kLate: the scan was already published.
  AddResult add(const std::string& pair_id, uint32_t scan_id, Cloud cloud, double now) {
    if (std::find(expected_.begin(), expected_.end(), pair_id) == expected_.end())
      return AddResult::kUnexpectedPair;
    if (published_set_.count(scan_id)) return AddResult::kLate;
    auto it = pending_.find(scan_id);
    if (it == pending_.end()) {
      it = pending_.emplace(scan_id, Scan()).first;
      it->second.scan_id = scan_id;
      it->second.first_arrival = now;
    }
    if (it->second.clouds.count(pair_id)) return AddResult::kDuplicate;
    it->second.clouds.emplace(pair_id, std::move(cloud));
    return AddResult::kAccepted;
  }

  // Removes and returns the scans that are complete or timed out at `now`, oldest id first.
  std::vector<Scan> poll(double now) {
    std::vector<Scan> ready;
    for (auto it = pending_.begin(); it != pending_.end();) {
      Scan& scan = it->second;
      const bool complete = scan.clouds.size() == expected_.size();
      if (!complete && now - scan.first_arrival < timeout_) {
        ++it;
        continue;
      }
      for (const std::string& pair : expected_)
        if (!scan.clouds.count(pair)) scan.missing.push_back(pair);
      markPublished(scan.scan_id);
      ready.push_back(std::move(scan));
      it = pending_.erase(it);
    }
    return ready;
  }

 private:
  void markPublished(uint32_t scan_id) {
    published_.push_back(scan_id);
    published_set_.insert(scan_id);
    if (published_.size() > kRememberPublished) {
      published_set_.erase(published_.front());
      published_.pop_front();
    }
  }

  static constexpr size_t kRememberPublished = 256;  // late clouds older than this are new scans
  std::vector<std::string> expected_;
  double timeout_;
  std::map<uint32_t, Scan> pending_;
  std::deque<uint32_t> published_;
  std::set<uint32_t> published_set_;
};

}  // namespace body_scan
