// Gathers the 4 scans of a walk session (thesis 5.3: representative poses s1..s4 scanned in
// turn, each stamped with its walk id and pose index 1..4) as they arrive, in any order, and
// hands the walk over once all 4 are in. Used for clouds by the body fitter and for fitted
// models by the recognizer.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace body_gait_model {

constexpr int kWalkPoses = 4;  // s1..s4

template <typename Item>
class WalkCollector {
 public:
  using Walk = std::array<Item, kWalkPoses>;  // [pose_index - 1]

  // Walks still incomplete when a newer walk makes more than `open_walks` are dropped (a walk
  // abandoned half way must not hold its scans forever).
  explicit WalkCollector(std::size_t open_walks = 2) : open_walks_(open_walks) {}

  // Adds pose `pose_index` (1..4) of walk `walk_id` (> 0). Returns the whole walk, poses in
  // order, when this was its last missing pose; a pose given twice replaces the earlier one.
  // Throws std::invalid_argument for walk id 0 or a pose index outside 1..4.
  std::optional<Walk> add(std::uint32_t walk_id, int pose_index, Item item) {
    if (walk_id == 0) throw std::invalid_argument("walk id 0 is a single scan, not a walk");
    if (pose_index < 1 || pose_index > kWalkPoses)
      throw std::invalid_argument("pose index " + std::to_string(pose_index) + " of walk " +
                                  std::to_string(walk_id) + " is not 1.." +
                                  std::to_string(kWalkPoses));
    auto open = open_.begin();
    while (open != open_.end() && open->walk_id != walk_id) ++open;
    if (open == open_.end()) {
      open_.push_back({walk_id, {}, {}});
      open = std::prev(open_.end());
    }
    open->items[pose_index - 1] = std::move(item);
    open->present[pose_index - 1] = true;
    for (bool present : open->present)
      if (!present) {
        while (open_.size() > open_walks_) {
          dropped_.push_back(open_.front().walk_id);
          open_.pop_front();
        }
        return std::nullopt;
      }
    Walk walk = std::move(open->items);
    open_.erase(open);
    return walk;
  }

  // Walks dropped incomplete since the last call (for a warning).
  std::deque<std::uint32_t> takeDropped() { return std::exchange(dropped_, {}); }
  // Poses of walk `walk_id` received so far (0 if none or already handed over).
  int posesOf(std::uint32_t walk_id) const {
    for (const Open& open : open_)
      if (open.walk_id == walk_id) {
        int count = 0;
        for (bool present : open.present) count += present;
        return count;
      }
    return 0;
  }

 private:
  struct Open {
    std::uint32_t walk_id;
    Walk items;
    std::array<bool, kWalkPoses> present;
  };
  std::size_t open_walks_;
  std::deque<Open> open_;
  std::deque<std::uint32_t> dropped_;
};

}  // namespace body_gait_model
