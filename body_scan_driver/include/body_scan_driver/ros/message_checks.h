// Checks of the messages our nodes receive, one function per message type: a message from the
// network may declare any size, step, encoding or count. Each returns what is wrong, naming the
// field and what a sender must publish instead, or nullopt when the message is safe to use as
// its type promises. Callbacks check first and touch nothing of a message that fails.
#pragma once

#include <body_scan_msgs/PairCloud.h>
#include <body_scan_msgs/PatternSet.h>
#include <body_scan_msgs/TimingGroups.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

namespace body_scan_driver {

using MessageProblem = std::optional<std::string>;

// A frame id tf can use: not empty, no spaces or control characters. `field` names it.
MessageProblem checkFrameId(const std::string& frame_id, const std::string& field);

// An image of `encoding` (mono8 or rgb8): width, height > 0, step >= width x bytes per pixel,
// data holds step x height bytes. `field` names it in the answer (e.g. "frames[3]").
MessageProblem checkImage(const sensor_msgs::Image& image, const std::string& encoding,
                          const std::string& field);

// A Gray-code pattern set Triangulate can decode: scheme "gray", bits in range, the frame count
// of its layout, every frame a complete mono8 image of one size, the texture empty or a complete
// rgb8 image of that size, a pair id and a frame id.
MessageProblem checkPatternSet(const body_scan_msgs::PatternSet& set);

// A cloud of float32 x y z at offsets 0, 4, 8 (and an optional float32 rgb), points packed row
// after row (row_step = width x point_step), little endian, data holding every point. This is
// the layout Triangulate publishes and Merge reads. `field` names it.
MessageProblem checkFloatCloud(const sensor_msgs::PointCloud2& cloud, const std::string& field);

// A pair's cloud for Merge: a pair id, a frame id and a float cloud.
MessageProblem checkPairCloud(const body_scan_msgs::PairCloud& part);

// A timing plan: finite, non-negative group_seconds, no empty group.
MessageProblem checkTimingGroups(const body_scan_msgs::TimingGroups& groups);

// One error per distinct problem per period: a sender repeating a bad message does not flood
// the log, and a different problem (another field, another sender) is still reported at once.
// Thread-safe.
class ProblemThrottle {
 public:
  explicit ProblemThrottle(double period_seconds = 5.0) : period_(period_seconds) {}
  // Whether to log `problem` now (wall time in seconds).
  bool shouldReport(const std::string& problem, double now_seconds);

 private:
  std::mutex mutex_;
  std::unordered_map<std::string, double> last_report_;
  double period_;
};

}  // namespace body_scan_driver
