// A recorded walk's fitted models from a bag (gait_gallery enroll / identify --bag): record.launch
// records the body fitter's /body_gait/model, and each model carries its walk id and pose index.
#pragma once

#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/walk_collector.h>
#include <body_scan_msgs/BodyModel.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace body_gait_id::tools {

struct RecordedWalk {
  std::uint32_t walk_id = 0;
  std::vector<body_gait_model::BodyModel> poses;  // s1..s4
  std::vector<std::uint32_t> scan_ids;            // of poses 1..4
};

// The walk `walk_id` (0: the last walk whose 4 poses are all in the bag) from every
// body_scan_msgs/BodyModel message of the bag, whatever its topic; a pose recorded twice counts
// once (the later). Throws std::runtime_error naming the problem and the fix.
inline RecordedWalk readWalkFromBag(const std::string& path, std::uint32_t walk_id = 0) {
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read the bag '" + path + "': " + e.what());
  }
  std::map<std::uint32_t, std::map<int, body_scan_msgs::BodyModel>> walks;  // walk -> pose -> model
  std::vector<std::uint32_t> order;                                         // walks as they end
  int models = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (m.getDataType() != "body_scan_msgs/BodyModel") continue;
    const auto model = m.instantiate<body_scan_msgs::BodyModel>();
    if (!model) continue;
    ++models;
    if (model->walk_id == 0 || model->pose_index < 1 ||
        model->pose_index > body_gait_model::kWalkPoses)
      continue;
    auto& poses = walks[model->walk_id];
    poses[model->pose_index] = *model;
    if (poses.size() == static_cast<std::size_t>(body_gait_model::kWalkPoses))
      order.push_back(model->walk_id);
  }
  if (models == 0)
    throw std::runtime_error(
        "the bag '" + path +
        "' holds no body_scan_msgs/BodyModel messages: record the walk with record.launch while "
        "the body fitter runs (full_scanner.launch), or replay a bag of its pattern sets with "
        "replay.launch body_model:=true and record /replay/body_gait/model");
  if (walks.empty())
    throw std::runtime_error("the bag '" + path + "' holds " + std::to_string(models) +
                             " models but none of a walk (walk id 0): capture the walk with "
                             "/body_scan/capture_walk");
  if (walk_id == 0) {
    if (order.empty())
      throw std::runtime_error("no walk in '" + path + "' has all " +
                               std::to_string(body_gait_model::kWalkPoses) +
                               " poses: record the whole walk session");
    walk_id = order.back();
  }
  const auto walk = walks.find(walk_id);
  if (walk == walks.end()) {
    std::string ids;
    for (const auto& [id, poses] : walks) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
    throw std::runtime_error("no walk " + std::to_string(walk_id) + " in '" + path +
                             "'; it holds walks " + ids);
  }
  if (walk->second.size() != static_cast<std::size_t>(body_gait_model::kWalkPoses)) {
    std::string have;
    for (const auto& [pose, model] : walk->second)
      have += (have.empty() ? "" : ", ") + std::to_string(pose);
    throw std::runtime_error("walk " + std::to_string(walk_id) + " in '" + path + "' has poses " +
                             have + " of 1-4: record the whole walk session");
  }
  RecordedWalk recorded;
  recorded.walk_id = walk_id;
  for (const auto& [pose, model] : walk->second) {
    recorded.poses.push_back(body_gait_model::fromMsg(model));
    recorded.scan_ids.push_back(model.scan_id);
  }
  return recorded;
}

}  // namespace body_gait_id::tools
