// A triangle mesh surface ray-cast with Embree (one BVH per mesh, built once): the skin of a
// posed mesh human (sim/mesh_human.h). Per-triangle materials; smooth (interpolated vertex)
// normals.
#pragma once

#include <body_scan_driver/sim/scene.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace body_scan_driver::sim {

class TriangleMesh : public Surface {
 public:
  // triangles: counter-clockwise seen from outside; triangle_material[i] indexes materials.
  // Throws std::invalid_argument on an index out of range or a mismatched material list.
  TriangleMesh(std::vector<Eigen::Vector3f> vertices, std::vector<std::array<int, 3>> triangles,
               std::vector<Material> materials, std::vector<uint8_t> triangle_material);
  ~TriangleMesh() override;
  TriangleMesh(const TriangleMesh&) = delete;
  TriangleMesh& operator=(const TriangleMesh&) = delete;

  bool intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const override;
  bool occludes(const Ray& ray, double t_min, double t_max) const override;
  // Embree's 16-wide packets; the same hits as intersect() ray by ray.
  void intersectMany(const Ray* rays, int count, double t_min, Hit* hits) const override;
  double albedoAtHit(const Hit& hit, const Eigen::Vector3d& point) const override;
  Eigen::Vector3d colorAtHit(const Hit& hit, const Eigen::Vector3d& point) const override;
  double boundingRadius() const override { return bounding_radius_; }
  Eigen::Vector3d boundingCenter() const override { return bounding_center_; }

  const std::vector<Eigen::Vector3f>& vertices() const { return vertices_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }
  const std::vector<Eigen::Vector3f>& vertexNormals() const { return normals_; }
  const Material& materialOf(int triangle) const {
    return materials_[triangle_material_[triangle]];
  }
  int materialIndexOf(int triangle) const { return triangle_material_[triangle]; }
  // Named parts (a mesh human's body segments, for evaluation reports): part_names[
  // triangle_part[i]] is triangle i's. Empty unless set.
  void setParts(std::vector<std::string> part_names, std::vector<uint8_t> triangle_part);
  const std::vector<std::string>& partNames() const { return part_names_; }
  const std::vector<uint8_t>& trianglePart() const { return triangle_part_; }

 private:
  Eigen::Vector3d normalAt(int triangle, float u, float v) const;

  std::vector<Eigen::Vector3f> vertices_, normals_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<Material> materials_;
  std::vector<uint8_t> triangle_material_;
  std::vector<std::string> part_names_;
  std::vector<uint8_t> triangle_part_;
  Eigen::Vector3d bounding_center_;
  double bounding_radius_ = 0;
  struct Embree;
  Embree* embree_ = nullptr;
};

}  // namespace body_scan_driver::sim
