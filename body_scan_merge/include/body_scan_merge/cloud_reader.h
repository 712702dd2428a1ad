// Reads the point clouds writePly / writePcd (ply_writer.h) and other tools write, for the
// evaluation tools.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace body_scan {

// x, y, z of a binary little-endian or ASCII PLY (first element "vertex", float or double
// x y z, any other scalar properties) or a binary or ASCII PCD (x y z of 4-byte floats among
// any other fields). Non-finite points are dropped. Throws std::runtime_error naming the file
// and the unsupported feature.
std::vector<Eigen::Vector3f> readPointCloud(const std::string& path);

}  // namespace body_scan
