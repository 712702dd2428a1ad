// Conversions between the core types and ROS messages (the ROS layer only).
#pragma once

#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/pair_device.h>
#include <body_scan_msgs/PatternSet.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

namespace body_scan_driver {

// Copies a CV_8UC1 (mono8) or CV_8UC3 (rgb8) image into a message.
void toImageMessage(const cv::Mat& image, const std_msgs::Header& header, sensor_msgs::Image& msg);
sensor_msgs::CameraInfo toCameraInfo(const PinholeCamera& camera, const std_msgs::Header& header);
body_scan_msgs::PatternSetPtr toPatternSet(const PatternCapture& capture,
                                           const PatternLayout& layout, const PinholeCamera& camera,
                                           const std_msgs::Header& header,
                                           const std::string& pair_id, uint32_t scan_id);

// Lays out a cloud of float32 x y z (and PCL's packed rgb) points: fields, steps, little
// endian, data sized for width x height points (contents left to the caller).
void layoutFloatCloud(sensor_msgs::PointCloud2& cloud, uint32_t width, uint32_t height, bool rgb);

}  // namespace body_scan_driver
