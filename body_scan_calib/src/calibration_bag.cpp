#include <body_scan_calib/calibration_bag.h>
#include <body_scan_calib/calibration_capture.h>
#include <body_scan_calib/capture_folder.h>
#include <body_scan_driver/ros/message_checks.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <filesystem>
#include <map>
#include <set>

namespace body_scan_calib {

std::vector<cv::Mat> patternFrames(const body_scan_msgs::PatternSet& set) {
  if (const auto problem = body_scan_driver::checkPatternSet(set))
    throw CalibrationBagError("pattern set of scan " + std::to_string(set.scan_id) + " (" +
                              set.pair_id + "): " + *problem +
                              "; record the PairDriver's pattern_set topic unchanged");
  std::vector<cv::Mat> frames;
  for (const sensor_msgs::Image& image : set.frames)
    frames.push_back(cv::Mat(static_cast<int>(image.height), static_cast<int>(image.width), CV_8UC1,
                             const_cast<uint8_t*>(image.data.data()), image.step)
                         .clone());
  return frames;
}

BagConversionResult bagToCalibrationFolder(
    const std::string& bag_path, const std::string& folder, const BagConversionOptions& options,
    const std::function<void(const std::string&)>& progress) {
  rosbag::Bag bag;
  try {
    bag.open(bag_path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw CalibrationBagError("cannot open bag '" + bag_path + "': " + e.what() +
                              " (check the path; record with rosbag record)");
  }
  const std::string type = ros::message_traits::DataType<body_scan_msgs::PatternSet>::value();
  rosbag::View view = options.topic.empty() ? rosbag::View(bag, rosbag::TypeQuery(type))
                                            : rosbag::View(bag, rosbag::TopicQuery(options.topic));

  // Two passes keep one placement in memory at a time (a 16-exposure calibration is ~1 GB):
  // the first checks the pairs and finds the runs of scan ids, the second converts them.
  std::set<std::string> pairs;
  std::vector<uint32_t> scan_ids;
  uint8_t bits = 0;
  bool inverse_frames = false;
  for (const rosbag::MessageInstance& message : view) {
    const body_scan_msgs::PatternSet::ConstPtr set =
        message.instantiate<body_scan_msgs::PatternSet>();
    if (!set)
      throw CalibrationBagError("topic " + message.getTopic() + " of '" + bag_path + "' holds " +
                                message.getDataType() + ", not " + type);
    if (!options.pair_id.empty() && set->pair_id != options.pair_id) continue;
    if (scan_ids.empty()) {
      bits = set->bits;
      inverse_frames = set->inverse_frames;
    } else if (set->bits != bits || set->inverse_frames != inverse_frames) {
      throw CalibrationBagError("scan " + std::to_string(set->scan_id) +
                                " uses another pattern set (bits, inverses) than the first; "
                                "record one calibration with one pattern set");
    }
    pairs.insert(set->pair_id);
    scan_ids.push_back(set->scan_id);
  }
  if (scan_ids.empty())
    throw CalibrationBagError("'" + bag_path + "' holds no " + type + " messages" +
                              (options.topic.empty() ? "" : " on " + options.topic) +
                              (options.pair_id.empty() ? "" : " of pair " + options.pair_id) +
                              "; record the pair's pattern_set topic (see docs/REAL_RIG.md, "
                              "'Capture the calibration views')");
  if (pairs.size() > 1) {
    std::string list;
    for (const std::string& pair : pairs) list += " " + pair;
    throw CalibrationBagError("'" + bag_path + "' holds pattern sets of several pairs (" +
                              list.substr(1) + "); choose one with --pair-id");
  }

  const std::vector<std::vector<size_t>> groups = groupConsecutiveScanIds(scan_ids);
  const int removed = removeOldCaptures(folder);
  if (progress && removed > 0)
    progress("removed " + std::to_string(removed) + " capture folders of an earlier run from " +
             folder);
  BagConversionResult result;
  result.pattern_sets = scan_ids.size();
  result.bits = bits;
  size_t group = 0;
  std::vector<std::vector<cv::Mat>> captures;
  for (const rosbag::MessageInstance& message : view) {
    const body_scan_msgs::PatternSet::ConstPtr set =
        message.instantiate<body_scan_msgs::PatternSet>();
    if (!options.pair_id.empty() && set->pair_id != options.pair_id) continue;
    captures.push_back(patternFrames(*set));
    if (captures.size() < groups[group].size()) continue;
    // The placement's last set: average and write it.
    const std::string scans = std::to_string(scan_ids[groups[group].front()]) + ".." +
                              std::to_string(scan_ids[groups[group].back()]);
    const bool spheres = options.spheres_last && group + 1 == groups.size();
    const std::string name = spheres ? kSphereFolderName : poseFolderName(static_cast<int>(group));
    const std::string path = (std::filesystem::path(folder) / name).string();
    try {
      savePatternFrames(path, averageCaptures(captures));
    } catch (const std::invalid_argument& e) {
      throw CalibrationBagError("scans " + scans + ": " + e.what());
    }
    result.folders.push_back(path);
    if (progress)
      progress("wrote " + path + ": scans " + scans + " (" + std::to_string(captures.size()) +
               " averaged)");
    captures.clear();
    ++group;
  }
  return result;
}

}  // namespace body_scan_calib
