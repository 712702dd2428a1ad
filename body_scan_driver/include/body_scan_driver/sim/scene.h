// Scene of the virtual pair: surfaces that camera and projector rays hit (DESIGN.md section 4).
// All coordinates are in the world frame (metres, z up).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace body_scan_driver::sim {

struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;  // unit length
};

// How a surface returns light: albedo scales the projector and ambient light (grey, 0..1);
// color is the texture camera's view of the surface.
struct Material {
  double albedo = 0.6;
  Eigen::Vector3d color{0.85, 0.65, 0.55};
};

class Surface;

struct Hit {
  double distance = std::numeric_limits<double>::infinity();  // along the ray
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();           // unit, outward
  const Surface* surface = nullptr;
  int surface_index = -1;  // into Scene::surfaces(); set by Scene::intersect
  int primitive = -1;      // the triangle of a TriangleMesh; -1 for analytic surfaces
};

// One primitive. Implementations: Plane, CheckerboardPlane, Sphere, Cylinder, Ellipsoid,
// TriangleMesh (triangle_mesh.h).
class Surface {
 public:
  explicit Surface(Material material) : material_(material) {}
  virtual ~Surface() = default;

  // Nearest intersection with distance in (t_min, t_max); fills hit and returns true if any.
  virtual bool intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const = 0;
  // Nearest hits of many rays: hits[i] is replaced where the surface has a hit in
  // (t_min, hits[i].distance). TriangleMesh casts them as packets.
  virtual void intersectMany(const Ray* rays, int count, double t_min, Hit* hits) const {
    for (int i = 0; i < count; ++i) {
      Hit hit;
      if (intersect(rays[i], t_min, hits[i].distance, hit)) hits[i] = hit;
    }
  }
  // Whether anything of the surface lies on the ray in (t_min, t_max) (shadow test).
  virtual bool occludes(const Ray& ray, double t_min, double t_max) const {
    Hit hit;
    return intersect(ray, t_min, t_max, hit);
  }
  // Albedo at a point on the surface; patterned surfaces (checkerboards) override it.
  virtual double albedoAt(const Eigen::Vector3d& /*point*/) const { return material_.albedo; }
  virtual Eigen::Vector3d colorAt(const Eigen::Vector3d& /*point*/) const {
    return material_.color;
  }
  // The same at a hit of this surface (meshes have a material per triangle).
  virtual double albedoAtHit(const Hit& /*hit*/, const Eigen::Vector3d& point) const {
    return albedoAt(point);
  }
  virtual Eigen::Vector3d colorAtHit(const Hit& /*hit*/, const Eigen::Vector3d& point) const {
    return colorAt(point);
  }
  // True for printed patterns (checker grids, markers): the renderer averages their albedo over
  // 4x4 samples of the pixel's area so pattern edges keep their subpixel position; plain
  // surfaces take one sample and keep their speed.
  virtual bool patterned() const { return false; }
  // Sphere enclosing the surface, for culling rays; radius infinity for unbounded surfaces.
  virtual double boundingRadius() const = 0;
  virtual Eigen::Vector3d boundingCenter() const = 0;

  const Material& material() const { return material_; }
  // Name of the object the surface belongs to (e.g. "person/left_forearm"), for reports.
  std::string name;

 private:
  Material material_;
};

// Bounded or unbounded plane through point with the given normal. A positive half_extent
// bounds it to the square |(p - point) . axis_u| <= half_extent, likewise along axis_v.
class Plane : public Surface {
 public:
  Plane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, Material material,
        double half_extent = 0.0);
  bool intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const override;
  double boundingRadius() const override;
  Eigen::Vector3d boundingCenter() const override { return point_; }

 protected:
  Eigen::Vector3d point_, normal_, axis_u_, axis_v_;
  double half_extent_;
};

// A printed checkerboard: squares of square_size alternating light/dark albedo, cols x rows
// squares, centred on point, rows along axis_v. axis_u must be perpendicular to normal.
class CheckerboardPlane : public Plane {
 public:
  CheckerboardPlane(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                    const Eigen::Vector3d& axis_u, int cols, int rows, double square_size,
                    double light_albedo, double dark_albedo);
  bool intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const override;
  double albedoAt(const Eigen::Vector3d& point) const override;
  Eigen::Vector3d colorAt(const Eigen::Vector3d& point) const override;
  double boundingRadius() const override;

 private:
  int cols_, rows_;
  double square_size_, light_albedo_, dark_albedo_;
};

class Sphere : public Surface {
 public:
  Sphere(const Eigen::Vector3d& center, double radius, Material material);
  bool intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const override;
  double boundingRadius() const override { return radius_; }
  Eigen::Vector3d boundingCenter() const override { return center_; }

 private:
  Eigen::Vector3d center_;
  double radius_;
};

// Closed cylinder (side and both caps) from base along axis for height.
class Cylinder : public Surface {
 public:
  Cylinder(const Eigen::Vector3d& base, const Eigen::Vector3d& axis, double radius, double height,
           Material material);
  bool intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const override;
  double boundingRadius() const override;
  Eigen::Vector3d boundingCenter() const override;

 private:
  Eigen::Vector3d base_, axis_;
  double radius_, height_;
};

// Ellipsoid with semi-axes radii along the columns of orientation, centred on center.
// The human body is built from these (smooth, cheap to intersect).
class Ellipsoid : public Surface {
 public:
  Ellipsoid(const Eigen::Vector3d& center, const Eigen::Matrix3d& orientation,
            const Eigen::Vector3d& radii, Material material);
  bool intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const override;
  double boundingRadius() const override { return radii_.maxCoeff(); }
  Eigen::Vector3d boundingCenter() const override { return center_; }
  // For evaluation tools that sample the true surface.
  const Eigen::Vector3d& center() const { return center_; }
  const Eigen::Vector3d& radii() const { return radii_; }
  const Eigen::Matrix3d& orientation() const { return orientation_; }
  bool contains(const Eigen::Vector3d& point) const {
    return (to_unit_ * (point - center_)).squaredNorm() < 1.0;
  }

 private:
  Eigen::Vector3d center_, radii_;
  Eigen::Matrix3d orientation_;
  Eigen::Matrix3d to_unit_;  // world offset -> unit-sphere coordinates
};

// A named 3D point of the true skeleton (world frame), e.g. "left_knee".
struct SkeletonJoint {
  std::string name;
  Eigen::Vector3d position;
};

class Scene {
 public:
  void add(std::unique_ptr<Surface> surface);
  void addJoints(const std::vector<SkeletonJoint>& joints);

  // Nearest hit along the ray in (t_min, t_max).
  bool intersect(const Ray& ray, Hit& hit, double t_min = 1e-6,
                 double t_max = std::numeric_limits<double>::infinity()) const;
  // intersect() for many rays at once (a camera row): hits[i].surface == nullptr = no hit.
  void intersectMany(const Ray* rays, int count, Hit* hits, double t_min = 1e-6) const;
  // True if anything lies strictly between from and to (shadow test).
  bool occluded(const Eigen::Vector3d& from, const Eigen::Vector3d& to) const;

  const std::vector<std::unique_ptr<Surface>>& surfaces() const { return surfaces_; }
  // The true skeleton of every human in the scene (ground truth: evaluation only).
  const std::vector<SkeletonJoint>& skeleton() const { return skeleton_; }

 private:
  std::vector<std::unique_ptr<Surface>> surfaces_;
  std::vector<SkeletonJoint> skeleton_;
};

// Loads a scene from YAML (see config/scenes/*.yaml for the format). Throws
// std::runtime_error naming the file, the object and the fix on bad input.
Scene loadScene(const std::string& path);
// The same from the text of a scene file (e.g. received by the driver's ~set_scene service).
Scene parseScene(const std::string& yaml_text);

}  // namespace body_scan_driver::sim
