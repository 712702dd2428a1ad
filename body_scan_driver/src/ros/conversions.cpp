#include <body_scan_driver/ros/conversions.h>
#include <sensor_msgs/image_encodings.h>

namespace body_scan_driver {

void toImageMessage(const cv::Mat& image, const std_msgs::Header& header, sensor_msgs::Image& msg) {
  msg.header = header;
  msg.height = image.rows;
  msg.width = image.cols;
  msg.encoding = image.channels() == 3 ? sensor_msgs::image_encodings::RGB8
                                       : sensor_msgs::image_encodings::MONO8;
  msg.is_bigendian = false;
  msg.step = static_cast<uint32_t>(image.cols * image.elemSize());
  msg.data.resize(static_cast<size_t>(msg.step) * image.rows);
  for (int v = 0; v < image.rows; ++v)
    std::copy(image.ptr<uint8_t>(v), image.ptr<uint8_t>(v) + msg.step, &msg.data[v * msg.step]);
}

sensor_msgs::CameraInfo toCameraInfo(const PinholeCamera& c, const std_msgs::Header& header) {
  sensor_msgs::CameraInfo info;
  info.header = header;
  info.width = c.width;
  info.height = c.height;
  info.distortion_model = "plumb_bob";
  info.D = {c.k1, c.k2, 0, 0, 0};
  info.K = {c.alpha, c.gamma, c.u0, 0, c.beta, c.v0, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {c.alpha, c.gamma, c.u0, 0, 0, c.beta, c.v0, 0, 0, 0, 1, 0};
  return info;
}

body_scan_msgs::PatternSetPtr toPatternSet(const PatternCapture& capture,
                                           const PatternLayout& layout, const PinholeCamera& camera,
                                           const std_msgs::Header& header,
                                           const std::string& pair_id, uint32_t scan_id) {
  body_scan_msgs::PatternSetPtr set(new body_scan_msgs::PatternSet);
  set->header = header;
  set->pair_id = pair_id;
  set->scan_id = scan_id;
  set->scheme = "gray";
  set->bits = static_cast<uint8_t>(layout.bits());
  set->inverse_frames = layout.inverseFrames();
  toImageMessage(capture.texture, header, set->texture);
  set->frames.resize(capture.frames.size());
  for (size_t i = 0; i < capture.frames.size(); ++i)
    toImageMessage(capture.frames[i], header, set->frames[i]);
  set->camera_info = toCameraInfo(camera, header);
  return set;
}

void layoutFloatCloud(sensor_msgs::PointCloud2& cloud, uint32_t width, uint32_t height, bool rgb) {
  const char* names[] = {"x", "y", "z", "rgb"};
  cloud.fields.clear();
  for (uint32_t i = 0; i < (rgb ? 4u : 3u); ++i) {
    sensor_msgs::PointField field;
    field.name = names[i];
    field.offset = 4 * i;
    field.datatype = sensor_msgs::PointField::FLOAT32;
    field.count = 1;
    cloud.fields.push_back(field);
  }
  cloud.width = width;
  cloud.height = height;
  cloud.point_step = rgb ? 16 : 12;
  cloud.row_step = cloud.point_step * width;
  cloud.is_bigendian = false;
  cloud.data.resize(static_cast<size_t>(cloud.row_step) * height);
}

}  // namespace body_scan_driver
