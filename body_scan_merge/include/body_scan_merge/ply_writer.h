// Writes point clouds as binary little-endian PLY (x, y, z float; red, green, blue uchar),
// readable by MeshLab, CloudCompare and PCL, or as binary PCD (x y z rgb, PCL's own format).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace body_scan_merge {

// Points are read as `stride` floats apart: x, y, z at offsets 0..2 and, when rgb_offset >= 0,
// a PCL-style packed rgb float at rgb_offset. Non-finite points are skipped. The file is
// written to a temporary name and renamed, so readers never see half a file. Returns the
// number of points written; throws FileWriteError (a std::runtime_error) naming the path on
// failure.
size_t writePly(const std::string& path, const float* points, size_t count, size_t stride,
                int rgb_offset);

// Reads a PLY file as writePly writes it (binary little endian; float x y z, optional uchar
// red green blue): 4 floats per point, x y z and the packed rgb. Throws std::runtime_error
// naming the file and what it expected.
std::vector<float> readPly(const std::string& path);

// The same points as a binary PCD v0.7 file (FIELDS x y z rgb, unorganized), same rules.
size_t writePcd(const std::string& path, const float* points, size_t count, size_t stride,
                int rgb_offset);

}  // namespace body_scan_merge
