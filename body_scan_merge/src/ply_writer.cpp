#include <body_scan_driver/atomic_file.h>
#include <body_scan_merge/ply_writer.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace body_scan {

namespace {

// Calls add(x, y, z, packed 0xRRGGBB) for every finite point (white without colour).
template <typename Add>
void forEachFinitePoint(const float* points, size_t count, size_t stride, int rgb_offset, Add add) {
  for (size_t i = 0; i < count; ++i) {
    const float* p = points + i * stride;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    uint32_t rgb = 0xFFFFFF;
    if (rgb_offset >= 0) std::memcpy(&rgb, p + rgb_offset, sizeof rgb);
    add(p[0], p[1], p[2], rgb & 0xFFFFFFu);
  }
}

}  // namespace

size_t writePly(const std::string& path, const float* points, size_t count, size_t stride,
                int rgb_offset) {
  struct Vertex {  // 15 bytes, packed as in the header below
    float x, y, z;
    uint8_t r, g, b;
  } __attribute__((packed));
  std::vector<Vertex> vertices;
  vertices.reserve(count);
  forEachFinitePoint(
      points, count, stride, rgb_offset, [&](float x, float y, float z, uint32_t rgb) {
        vertices.push_back({x, y, z, static_cast<uint8_t>(rgb >> 16),
                            static_cast<uint8_t>(rgb >> 8), static_cast<uint8_t>(rgb)});
      });
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

size_t writePcd(const std::string& path, const float* points, size_t count, size_t stride,
                int rgb_offset) {
  std::vector<float> body;  // x y z rgb, rgb as PCL's packed float
  body.reserve(4 * count);
  forEachFinitePoint(points, count, stride, rgb_offset,
                     [&](float x, float y, float z, uint32_t rgb) {
                       float packed;
                       std::memcpy(&packed, &rgb, sizeof packed);
                       body.insert(body.end(), {x, y, z, packed});
                     });
  const std::string n = std::to_string(body.size() / 4);
  std::string file =
      "# .PCD v0.7 - body_scan point cloud (metres)\nVERSION 0.7\nFIELDS x y z rgb\n"
      "SIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH " +
      n + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA binary\n";
  file.append(reinterpret_cast<const char*>(body.data()), body.size() * sizeof(float));
  writeFileAtomically(path, file);
  return body.size() / 4;
}

}  // namespace body_scan
