// The Merge's view of a pair's cloud message: the one place that reads a PointCloud2's layout
// into a CloudView (Merge nodelet, fuzz target).
#pragma once

#include <body_scan_merge/cloud_merge.h>
#include <sensor_msgs/PointCloud2.h>

namespace body_scan_merge {

// The cloud must have passed body_scan_driver::checkPairCloud (float x y z [rgb], packed rows).
// world_from_cloud stays the identity.
inline CloudView cloudView(const sensor_msgs::PointCloud2& cloud) {
  CloudView view;
  view.points = reinterpret_cast<const float*>(cloud.data.data());
  view.count = static_cast<size_t>(cloud.width) * cloud.height;
  view.stride = cloud.point_step / 4;
  view.rgb_offset = -1;
  for (const auto& field : cloud.fields)
    if (field.name == "rgb") view.rgb_offset = static_cast<int>(field.offset / 4);
  return view;
}

}  // namespace body_scan_merge
