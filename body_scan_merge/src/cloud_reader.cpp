#include <body_scan_merge/cloud_reader.h>

#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace body_scan {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error("point cloud '" + path + "': " + what);
}

size_t plyTypeSize(const std::string& type, const std::string& path) {
  static const std::map<std::string, size_t> sizes = {
      {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
      {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  auto it = sizes.find(type);
  if (it == sizes.end()) fail(path, "unsupported PLY property type '" + type + "'");
  return it->second;
}

void keep(std::vector<Eigen::Vector3f>& out, double x, double y, double z) {
  const Eigen::Vector3f p(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
  if (p.allFinite()) out.push_back(p);
}

std::vector<Eigen::Vector3f> readPly(std::ifstream& in, const std::string& path) {
  std::string line, format;
  size_t count = 0;
  bool in_vertex = false, seen_vertex = false;
  struct Property {
    std::string name;
    size_t offset, size;
  };
  std::vector<Property> props;
  size_t stride = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "format") {
      words >> format;
    } else if (key == "element") {
      std::string name;
      words >> name;
      if (seen_vertex) break;  // a later element: its data follows the vertices
      in_vertex = name == "vertex";
      if (!in_vertex) fail(path, "the first PLY element must be 'vertex', got '" + name + "'");
      seen_vertex = true;
      words >> count;
    } else if (key == "property" && in_vertex) {
      std::string type, name;
      words >> type;
      if (type == "list") fail(path, "list properties in the vertex element are not supported");
      words >> name;
      const size_t size = plyTypeSize(type, path);
      props.push_back({name + ":" + type, stride, size});
      stride += size;
    } else if (key == "end_header") {
      break;
    }
  }
  // Skip to end_header if we broke out on a later element.
  while (line != "end_header" && std::getline(in, line))
    if (!line.empty() && line.back() == '\r') line.pop_back();
  int ix = -1, iy = -1, iz = -1;
  for (size_t i = 0; i < props.size(); ++i) {
    const std::string name = props[i].name.substr(0, props[i].name.find(':'));
    if (name == "x") ix = static_cast<int>(i);
    if (name == "y") iy = static_cast<int>(i);
    if (name == "z") iz = static_cast<int>(i);
  }
  if (ix < 0 || iy < 0 || iz < 0) fail(path, "the vertex element has no x, y, z properties");
  std::vector<Eigen::Vector3f> out;
  out.reserve(count);
  if (format == "ascii") {
    std::vector<double> values(props.size());
    for (size_t n = 0; n < count; ++n) {
      for (auto& v : values)
        if (!(in >> v)) fail(path, "the file ends before its " + std::to_string(count) + " points");
      keep(out, values[ix], values[iy], values[iz]);
    }
    return out;
  }
  if (format != "binary_little_endian")
    fail(path, "PLY format '" + format + "' is not supported (binary_little_endian or ascii)");
  std::vector<char> data(stride * count);
  if (!in.read(data.data(), static_cast<std::streamsize>(data.size())))
    fail(path, "the file ends before its " + std::to_string(count) + " points");
  auto value = [&](const char* record, const Property& p) -> double {
    if (p.size == 4) {
      float f;
      std::memcpy(&f, record + p.offset, 4);
      return f;
    }
    if (p.size == 8) {
      double d;
      std::memcpy(&d, record + p.offset, 8);
      return d;
    }
    fail(path, "x, y, z must be float or double");
  };
  for (size_t n = 0; n < count; ++n) {
    const char* record = data.data() + n * stride;
    keep(out, value(record, props[ix]), value(record, props[iy]), value(record, props[iz]));
  }
  return out;
}

std::vector<Eigen::Vector3f> readPcd(std::ifstream& in, const std::string& path) {
  std::vector<std::string> fields;
  std::vector<size_t> sizes, counts;
  size_t points = 0;
  std::string data, line;
  while (data.empty() && std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "FIELDS") {
      for (std::string f; words >> f;) fields.push_back(f);
    } else if (key == "SIZE") {
      for (size_t s; words >> s;) sizes.push_back(s);
    } else if (key == "COUNT") {
      for (size_t c; words >> c;) counts.push_back(c);
    } else if (key == "POINTS") {
      words >> points;
    } else if (key == "DATA") {
      words >> data;
    }
  }
  if (counts.empty()) counts.assign(fields.size(), 1);
  if (sizes.size() != fields.size() || counts.size() != fields.size())
    fail(path, "PCD header FIELDS, SIZE and COUNT differ in length");
  size_t stride = 0;
  std::map<std::string, size_t> offset, column;
  size_t columns = 0;
  for (size_t i = 0; i < fields.size(); ++i) {
    offset[fields[i]] = stride;
    column[fields[i]] = columns;
    stride += sizes[i] * counts[i];
    columns += counts[i];
  }
  for (const char* f : {"x", "y", "z"})
    if (!offset.count(f) || sizes[column[f]] != 4)
      fail(path, std::string("PCD field '") + f + "' missing or not a 4-byte float");
  std::vector<Eigen::Vector3f> out;
  out.reserve(points);
  if (data == "ascii") {
    std::vector<double> values(columns);
    for (size_t n = 0; n < points; ++n) {
      for (auto& v : values)
        if (!(in >> v))
          fail(path, "the file ends before its " + std::to_string(points) + " points");
      keep(out, values[column["x"]], values[column["y"]], values[column["z"]]);
    }
    return out;
  }
  if (data != "binary") fail(path, "PCD DATA '" + data + "' is not supported (binary or ascii)");
  std::vector<char> bytes(stride * points);
  if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size())))
    fail(path, "the file ends before its " + std::to_string(points) + " points");
  for (size_t n = 0; n < points; ++n) {
    float xyz[3];
    const char* record = bytes.data() + n * stride;
    std::memcpy(&xyz[0], record + offset["x"], 4);
    std::memcpy(&xyz[1], record + offset["y"], 4);
    std::memcpy(&xyz[2], record + offset["z"], 4);
    keep(out, xyz[0], xyz[1], xyz[2]);
  }
  return out;
}

}  // namespace

std::vector<Eigen::Vector3f> readPointCloud(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot be opened (check the path)");
  std::string magic;
  std::getline(in, magic);
  if (!magic.empty() && magic.back() == '\r') magic.pop_back();
  if (magic == "ply") return readPly(in, path);
  if (magic.rfind("# .PCD", 0) == 0 || magic.rfind("VERSION", 0) == 0) {
    in.seekg(0);
    return readPcd(in, path);
  }
  fail(path, "is neither PLY nor PCD (first line '" + magic + "')");
}

}  // namespace body_scan
