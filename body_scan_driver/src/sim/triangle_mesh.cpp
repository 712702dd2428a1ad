#include <body_scan_driver/sim/triangle_mesh.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

namespace body_scan_driver::sim {
namespace {

// One Embree device for the process. Its own build threads: none (builds run on the caller).
RTCDevice device() {
  static std::once_flag once;
  static RTCDevice shared = nullptr;
  std::call_once(once, [] {
    shared = rtcNewDevice("threads=1,set_affinity=0");
    if (!shared)
      throw std::runtime_error("Embree: cannot create a device (error " +
                               std::to_string(rtcGetDeviceError(nullptr)) + ")");
  });
  return shared;
}

}  // namespace

struct TriangleMesh::Embree {
  RTCScene scene = nullptr;
};

TriangleMesh::TriangleMesh(std::vector<Eigen::Vector3f> vertices,
                           std::vector<std::array<int, 3>> triangles,
                           std::vector<Material> materials, std::vector<uint8_t> triangle_material)
    : Surface(materials.empty() ? Material{} : materials[0]),
      vertices_(std::move(vertices)),
      triangles_(std::move(triangles)),
      materials_(std::move(materials)),
      triangle_material_(std::move(triangle_material)) {
  if (triangle_material_.size() != triangles_.size())
    throw std::invalid_argument("TriangleMesh: one material index per triangle is needed");
  for (const uint8_t m : triangle_material_)
    if (m >= materials_.size())
      throw std::invalid_argument("TriangleMesh: material index " + std::to_string(m) +
                                  " out of range");
  normals_.assign(vertices_.size(), Eigen::Vector3f::Zero());
  for (const auto& t : triangles_) {
    for (const int i : t)
      if (i < 0 || i >= static_cast<int>(vertices_.size()))
        throw std::invalid_argument("TriangleMesh: vertex index " + std::to_string(i) +
                                    " out of range");
    // Area-weighted face normals summed at the vertices.
    const Eigen::Vector3f n =
        (vertices_[t[1]] - vertices_[t[0]]).cross(vertices_[t[2]] - vertices_[t[0]]);
    for (const int i : t) normals_[i] += n;
  }
  for (auto& n : normals_) n.normalize();
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity()), hi = -lo;
  for (const auto& v : vertices_) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  bounding_center_ = (0.5f * (lo + hi)).cast<double>();
  bounding_radius_ = 0.5 * (hi - lo).cast<double>().norm() + 1e-4;

  embree_ = new Embree;
  embree_->scene = rtcNewScene(device());
  rtcSetSceneBuildQuality(embree_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(device(), RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertex_buffer = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices_.size()));
  for (size_t i = 0; i < vertices_.size(); ++i)
    for (int k = 0; k < 3; ++k) vertex_buffer[3 * i + k] = vertices_[i][k];
  auto* index_buffer = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), triangles_.size()));
  for (size_t i = 0; i < triangles_.size(); ++i)
    for (int k = 0; k < 3; ++k) index_buffer[3 * i + k] = static_cast<unsigned>(triangles_[i][k]);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(embree_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(embree_->scene);
}

TriangleMesh::~TriangleMesh() {
  if (embree_) rtcReleaseScene(embree_->scene);
  delete embree_;
}

Eigen::Vector3d TriangleMesh::normalAt(int triangle, float u, float v) const {
  const auto& t = triangles_[triangle];
  return ((1 - u - v) * normals_[t[0]] + u * normals_[t[1]] + v * normals_[t[2]])
      .cast<double>()
      .normalized();
}

namespace {

void setRay(RTCRay& r, const Ray& ray, double t_min, double t_max) {
  r.org_x = static_cast<float>(ray.origin.x());
  r.org_y = static_cast<float>(ray.origin.y());
  r.org_z = static_cast<float>(ray.origin.z());
  r.dir_x = static_cast<float>(ray.direction.x());
  r.dir_y = static_cast<float>(ray.direction.y());
  r.dir_z = static_cast<float>(ray.direction.z());
  r.tnear = static_cast<float>(t_min);
  r.tfar =
      std::isfinite(t_max) ? static_cast<float>(t_max) : std::numeric_limits<float>::infinity();
  r.mask = 0xFFFFFFFFu;
  r.flags = 0;
  r.time = 0;
}

}  // namespace

bool TriangleMesh::intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit query;
  setRay(query.ray, ray, t_min, t_max);
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(embree_->scene, &context, &query);
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit.distance = query.ray.tfar;
  hit.primitive = static_cast<int>(query.hit.primID);
  hit.normal = normalAt(hit.primitive, query.hit.u, query.hit.v);
  hit.surface = this;
  return true;
}

void TriangleMesh::intersectMany(const Ray* rays, int count, double t_min, Hit* hits) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  for (int start = 0; start < count; start += 16) {
    const int n = std::min(16, count - start);
    alignas(64) int valid[16];
    alignas(64) RTCRayHit16 packet;
    for (int i = 0; i < 16; ++i) {
      valid[i] = i < n ? -1 : 0;
      const int k = start + std::min(i, n - 1);
      RTCRay single;
      setRay(single, rays[k], t_min, hits[k].distance);
      packet.ray.org_x[i] = single.org_x;
      packet.ray.org_y[i] = single.org_y;
      packet.ray.org_z[i] = single.org_z;
      packet.ray.dir_x[i] = single.dir_x;
      packet.ray.dir_y[i] = single.dir_y;
      packet.ray.dir_z[i] = single.dir_z;
      packet.ray.tnear[i] = single.tnear;
      packet.ray.tfar[i] = single.tfar;
      packet.ray.mask[i] = single.mask;
      packet.ray.id[i] = i;
      packet.ray.flags[i] = 0;
      packet.ray.time[i] = 0;
      packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, embree_->scene, &context, &packet);
    for (int i = 0; i < n; ++i) {
      if (packet.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
      Hit& hit = hits[start + i];
      hit.distance = packet.ray.tfar[i];
      hit.primitive = static_cast<int>(packet.hit.primID[i]);
      hit.normal = normalAt(hit.primitive, packet.hit.u[i], packet.hit.v[i]);
      hit.surface = this;
    }
  }
}

bool TriangleMesh::occludes(const Ray& ray, double t_min, double t_max) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay query;
  setRay(query, ray, t_min, t_max);
  rtcOccluded1(embree_->scene, &context, &query);
  return query.tfar < 0;  // Embree sets tfar to -inf on a hit
}

void TriangleMesh::setParts(std::vector<std::string> part_names,
                            std::vector<uint8_t> triangle_part) {
  if (triangle_part.size() != triangles_.size())
    throw std::invalid_argument("TriangleMesh: one part index per triangle is needed");
  for (const uint8_t part : triangle_part)
    if (part >= part_names.size())
      throw std::invalid_argument("TriangleMesh: part index out of range");
  part_names_ = std::move(part_names);
  triangle_part_ = std::move(triangle_part);
}

double TriangleMesh::albedoAtHit(const Hit& hit, const Eigen::Vector3d& point) const {
  return hit.primitive >= 0 ? materialOf(hit.primitive).albedo : albedoAt(point);
}

Eigen::Vector3d TriangleMesh::colorAtHit(const Hit& hit, const Eigen::Vector3d& point) const {
  return hit.primitive >= 0 ? materialOf(hit.primitive).color : colorAt(point);
}

}  // namespace body_scan_driver::sim
