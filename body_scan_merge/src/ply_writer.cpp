#include <body_scan_driver/atomic_file.h>
#include <body_scan_merge/ply_writer.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace body_scan {

size_t writePly(const std::string& path, const float* points, size_t count, size_t stride,
                int rgb_offset) {
  struct Vertex {  // 15 bytes, packed as in the header below
    float x, y, z;
    uint8_t r, g, b;
  } __attribute__((packed));
  std::vector<Vertex> vertices;
  vertices.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    const float* p = points + i * stride;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    uint32_t rgb = 0xFFFFFF;
    if (rgb_offset >= 0) std::memcpy(&rgb, p + rgb_offset, sizeof rgb);
    vertices.push_back({p[0], p[1], p[2], static_cast<uint8_t>(rgb >> 16),
                        static_cast<uint8_t>(rgb >> 8), static_cast<uint8_t>(rgb)});
  }
  std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment body_scan point cloud "
      "(metres)\nelement vertex " +
      std::to_string(vertices.size()) +
      "\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "end_header\n";
  header.append(reinterpret_cast<const char*>(vertices.data()), vertices.size() * sizeof(Vertex));
  writeFileAtomically(path, header);
  return vertices.size();
}

}  // namespace body_scan
