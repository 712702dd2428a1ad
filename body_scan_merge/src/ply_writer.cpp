#include <body_scan_merge/ply_writer.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
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
  const std::filesystem::path target(path);
  if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path());
  const std::string temporary = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream file(temporary, std::ios::binary);
    file << "ply\nformat binary_little_endian 1.0\ncomment body_scan point cloud (metres)\n"
         << "element vertex " << vertices.size() << "\n"
         << "property float x\nproperty float y\nproperty float z\n"
         << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    file.write(reinterpret_cast<const char*>(vertices.data()),
               static_cast<std::streamsize>(vertices.size() * sizeof(Vertex)));
    if (!file.flush())
      throw std::runtime_error("cannot write '" + temporary + "': check the folder is writable");
  }
  std::filesystem::rename(temporary, target);
  return vertices.size();
}

}  // namespace body_scan
