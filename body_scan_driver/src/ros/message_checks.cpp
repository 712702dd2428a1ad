#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/ros/message_checks.h>
#include <sensor_msgs/image_encodings.h>

#include <cmath>
#include <cstdint>

namespace body_scan_driver {
namespace {

std::string str(uint64_t value) { return std::to_string(value); }

}  // namespace

MessageProblem checkFrameId(const std::string& frame_id, const std::string& field) {
  if (frame_id.empty()) return field + " is empty; set the sensor's tf frame";
  for (const char c : frame_id)
    if (static_cast<unsigned char>(c) <= ' ' || c == 0x7f)
      return field + " '" + frame_id + "' holds a space or control character; tf frames cannot";
  return std::nullopt;
}

MessageProblem checkImage(const sensor_msgs::Image& image, const std::string& encoding,
                          const std::string& field) {
  const int bytes_per_pixel = encoding == sensor_msgs::image_encodings::RGB8 ? 3 : 1;
  if (image.encoding != encoding)
    return field + ".encoding is '" + image.encoding + "'; publish " + encoding;
  if (image.width == 0 || image.height == 0)
    return field + " is " + str(image.width) + "x" + str(image.height) + "; publish a whole image";
  const uint64_t min_step = uint64_t{image.width} * bytes_per_pixel;
  if (image.step < min_step)
    return field + ".step " + str(image.step) + " is less than width x " + str(bytes_per_pixel) +
           " = " + str(min_step) + " bytes; publish step >= " + str(min_step);
  const uint64_t size = uint64_t{image.step} * image.height;
  if (image.data.size() < size)
    return field + ".data holds " + str(image.data.size()) +
           " bytes, not step x height = " + str(size) + "; publish the whole image";
  return std::nullopt;
}

MessageProblem checkPatternSet(const body_scan_msgs::PatternSet& set) {
  if (set.pair_id.empty()) return std::string("pair_id is empty; set the pair's \"pole/pair\" id");
  if (auto problem = checkFrameId(set.header.frame_id, "header.frame_id")) return problem;
  if (set.scheme != "gray")
    return "scheme '" + set.scheme + "' is not supported; the driver must send scheme 'gray'";
  if (set.bits < kMinBits || set.bits > kMaxBits)
    return "bits " + str(set.bits) + " is outside [" + str(kMinBits) + ", " + str(kMaxBits) + "]";
  const PatternLayout layout(set.bits, set.inverse_frames);
  if (set.frames.size() != static_cast<size_t>(layout.frameCount()))
    return "frames holds " + str(set.frames.size()) + " images; " + str(set.bits) + " bits" +
           (set.inverse_frames ? " with inverses" : "") + " need " + str(layout.frameCount());
  for (size_t i = 0; i < set.frames.size(); ++i) {
    const std::string field = "frames[" + str(i) + "]";
    if (auto problem = checkImage(set.frames[i], sensor_msgs::image_encodings::MONO8, field))
      return problem;
    if (set.frames[i].width != set.frames[0].width || set.frames[i].height != set.frames[0].height)
      return field + " is " + str(set.frames[i].width) + "x" + str(set.frames[i].height) +
             ", frames[0] " + str(set.frames[0].width) + "x" + str(set.frames[0].height) +
             "; every frame of a set has one size";
  }
  const sensor_msgs::Image& texture = set.texture;
  const bool no_texture = texture.width == 0 && texture.height == 0 && texture.data.empty();
  if (!no_texture) {
    if (auto problem = checkImage(texture, sensor_msgs::image_encodings::RGB8, "texture"))
      return problem;
    if (texture.width != set.frames[0].width || texture.height != set.frames[0].height)
      return "texture is " + str(texture.width) + "x" + str(texture.height) + ", the frames " +
             str(set.frames[0].width) + "x" + str(set.frames[0].height) +
             "; send the texture of the same camera (or none)";
  }
  return std::nullopt;
}

MessageProblem checkFloatCloud(const sensor_msgs::PointCloud2& cloud, const std::string& field) {
  if (cloud.is_bigendian) return field + ".is_bigendian is set; publish little-endian clouds";
  const char* names[] = {"x", "y", "z"};
  for (uint32_t i = 0; i < 3; ++i) {
    bool found = false;
    for (const auto& f : cloud.fields)
      if (f.name == names[i]) {
        if (f.offset != 4 * i || f.datatype != sensor_msgs::PointField::FLOAT32 || f.count != 1)
          return field + ".fields '" + names[i] + "' is not one FLOAT32 at offset " + str(4 * i) +
                 "; publish float x y z first";
        found = true;
      }
    if (!found) return field + ".fields has no '" + names[i] + "'; publish float x y z";
  }
  if (cloud.point_step < 12 || cloud.point_step % 4 != 0)
    return field + ".point_step " + str(cloud.point_step) +
           " is not a multiple of 4 bytes >= 12; publish float x y z [rgb]";
  for (const auto& f : cloud.fields)
    if (f.name == "rgb" && (f.datatype != sensor_msgs::PointField::FLOAT32 || f.offset % 4 != 0 ||
                            uint64_t{f.offset} + 4 > cloud.point_step))
      return field + ".fields 'rgb' is not a FLOAT32 inside point_step; publish PCL's packed rgb";
  const uint64_t row = uint64_t{cloud.width} * cloud.point_step;
  if (cloud.row_step != row)
    return field + ".row_step " + str(cloud.row_step) + " is not width x point_step = " + str(row) +
           "; publish packed rows";
  const uint64_t size = row * cloud.height;
  if (cloud.data.size() < size)
    return field + ".data holds " + str(cloud.data.size()) +
           " bytes, less than row_step x height = " + str(size);
  return std::nullopt;
}

MessageProblem checkPairCloud(const body_scan_msgs::PairCloud& part) {
  if (part.pair_id.empty()) return std::string("pair_id is empty; set the pair's \"pole/pair\" id");
  if (auto problem = checkFrameId(part.cloud.header.frame_id, "cloud.header.frame_id"))
    return problem;
  return checkFloatCloud(part.cloud, "cloud");
}

MessageProblem checkTimingGroups(const body_scan_msgs::TimingGroups& groups) {
  if (!std::isfinite(groups.group_seconds) || groups.group_seconds < 0)
    return "group_seconds " + std::to_string(groups.group_seconds) +
           " is not a finite duration >= 0";
  for (size_t i = 0; i < groups.groups.size(); ++i)
    if (groups.groups[i].find_first_not_of(' ') == std::string::npos)
      return "groups[" + str(i) + "] is empty; every group names its pairs";
  return std::nullopt;
}

bool ProblemThrottle::shouldReport(const std::string& problem, double now_seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (last_report_.size() > 256) last_report_.clear();  // bounded, whatever the senders vary
  const auto [it, first] = last_report_.emplace(problem, now_seconds);
  if (first) return true;
  if (now_seconds - it->second < period_) return false;
  it->second = now_seconds;
  return true;
}

}  // namespace body_scan_driver
