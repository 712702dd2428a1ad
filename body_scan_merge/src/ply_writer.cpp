#include <body_scan_driver/atomic_file.h>
#include <body_scan_merge/ply_writer.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace body_scan_merge {

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
  body_scan_driver::writeFileAtomically(path, header);
  return vertices.size();
}

std::vector<float> readPly(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error("cannot open PLY file '" + path + "'");
  auto fail = [&](const std::string& what) {
    return std::runtime_error("PLY file '" + path + "': " + what +
                              " (expected binary_little_endian with float x y z [uchar red "
                              "green blue], as save_cloud writes)");
  };
  std::string line;
  std::getline(file, line);
  if (line != "ply") throw fail("no 'ply' magic line");
  size_t count = 0;
  std::vector<std::string> properties;
  while (std::getline(file, line) && line != "end_header") {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      std::string format;
      words >> format;
      if (format != "binary_little_endian") throw fail("format " + format);
    } else if (keyword == "element") {
      std::string name;
      words >> name >> count;
      if (name != "vertex") throw fail("element " + name);
    } else if (keyword == "property") {
      std::string type, name;
      words >> type >> name;
      properties.push_back(type + " " + name);
    }
  }
  const std::vector<std::string> xyz = {"float x", "float y", "float z"};
  const std::vector<std::string> xyzrgb = {"float x",   "float y",     "float z",
                                           "uchar red", "uchar green", "uchar blue"};
  const bool coloured = properties == xyzrgb;
  if (!coloured && properties != xyz) throw fail("other vertex properties");
  const size_t vertex_size = coloured ? 15 : 12;
  std::string body(count * vertex_size, '\0');
  if (!file.read(body.data(), static_cast<std::streamsize>(body.size())))
    throw fail("it ends before its " + std::to_string(count) + " vertices");
  std::vector<float> points(4 * count);
  for (size_t i = 0; i < count; ++i) {
    std::memcpy(&points[4 * i], body.data() + i * vertex_size, 12);
    uint32_t rgb = 0xFFFFFF;
    if (coloured) {
      const auto* c = reinterpret_cast<const uint8_t*>(body.data() + i * vertex_size + 12);
      rgb = (uint32_t{c[0]} << 16) | (uint32_t{c[1]} << 8) | c[2];
    }
    std::memcpy(&points[4 * i + 3], &rgb, sizeof rgb);
  }
  return points;
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
  body_scan_driver::writeFileAtomically(path, file);
  return body.size() / 4;
}

}  // namespace body_scan_merge
