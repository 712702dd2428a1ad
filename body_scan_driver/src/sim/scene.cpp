#include <body_scan_driver/sim/bvh_body.h>
#include <body_scan_driver/sim/calibration_cylinder.h>
#include <body_scan_driver/sim/human_body.h>
#include <body_scan_driver/sim/mesh_human.h>
#include <body_scan_driver/sim/scene.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include "../yaml_file.h"

namespace body_scan_driver::sim {
namespace {

Eigen::Vector3d anyPerpendicular(const Eigen::Vector3d& n) {
  const Eigen::Vector3d helper =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return n.cross(helper).normalized();
}

// Smallest root of a t^2 + 2 b t + c = 0 inside (t_min, t_max), if any.
bool nearestRoot(double a, double b, double c, double t_min, double t_max, double& t) {
  const double discriminant = b * b - a * c;
  if (discriminant < 0 || a == 0) return false;
  const double root = std::sqrt(discriminant);
  for (double candidate : {(-b - root) / a, (-b + root) / a}) {
    if (candidate > t_min && candidate < t_max) {
      t = candidate;
      return true;
    }
  }
  return false;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
Plane::Plane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, Material material,
             double half_extent)
    : Surface(material),
      point_(point),
      normal_(normal.normalized()),
      axis_u_(anyPerpendicular(normal_)),
      axis_v_(normal_.cross(axis_u_)),
      half_extent_(half_extent) {}

bool Plane::intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const {
  const double denominator = normal_.dot(ray.direction);
  if (std::abs(denominator) < 1e-12) return false;
  const double t = normal_.dot(point_ - ray.origin) / denominator;
  if (t <= t_min || t >= t_max) return false;
  if (half_extent_ > 0) {
    const Eigen::Vector3d offset = ray.origin + t * ray.direction - point_;
    if (std::abs(offset.dot(axis_u_)) > half_extent_ ||
        std::abs(offset.dot(axis_v_)) > half_extent_)
      return false;
  }
  hit.distance = t;
  hit.normal = denominator < 0 ? normal_ : Eigen::Vector3d(-normal_);
  hit.surface = this;
  return true;
}

double Plane::boundingRadius() const {
  return half_extent_ > 0 ? half_extent_ * std::sqrt(2.0) : std::numeric_limits<double>::infinity();
}

// ---------------------------------------------------------------------------------------------
CheckerboardPlane::CheckerboardPlane(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                                     const Eigen::Vector3d& axis_u, int cols, int rows,
                                     double square_size, double light_albedo, double dark_albedo)
    : Plane(center, normal, Material{light_albedo, {0.9, 0.9, 0.9}}),
      cols_(cols),
      rows_(rows),
      square_size_(square_size),
      light_albedo_(light_albedo),
      dark_albedo_(dark_albedo) {
  axis_u_ = (axis_u - axis_u.dot(normal_) * normal_).normalized();
  axis_v_ = normal_.cross(axis_u_);
}

bool CheckerboardPlane::intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const {
  Hit candidate;
  if (!Plane::intersect(ray, t_min, t_max, candidate)) return false;
  const Eigen::Vector3d offset = ray.origin + candidate.distance * ray.direction - point_;
  if (std::abs(offset.dot(axis_u_)) > 0.5 * cols_ * square_size_ ||
      std::abs(offset.dot(axis_v_)) > 0.5 * rows_ * square_size_)
    return false;
  hit = candidate;
  return true;
}

double CheckerboardPlane::albedoAt(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d offset = point - point_;
  const int col = static_cast<int>(std::floor(offset.dot(axis_u_) / square_size_ + 0.5 * cols_));
  const int row = static_cast<int>(std::floor(offset.dot(axis_v_) / square_size_ + 0.5 * rows_));
  return (col + row) % 2 == 0 ? dark_albedo_ : light_albedo_;
}

Eigen::Vector3d CheckerboardPlane::colorAt(const Eigen::Vector3d& point) const {
  return Eigen::Vector3d::Constant(albedoAt(point));
}

double CheckerboardPlane::boundingRadius() const {
  return 0.5 * square_size_ * std::hypot(cols_, rows_);
}

// ---------------------------------------------------------------------------------------------
Sphere::Sphere(const Eigen::Vector3d& center, double radius, Material material)
    : Surface(material), center_(center), radius_(radius) {}

bool Sphere::intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const {
  const Eigen::Vector3d offset = ray.origin - center_;
  double t;
  if (!nearestRoot(1.0, offset.dot(ray.direction), offset.squaredNorm() - radius_ * radius_, t_min,
                   t_max, t))
    return false;
  hit.distance = t;
  hit.normal = (offset + t * ray.direction) / radius_;
  hit.surface = this;
  return true;
}

// ---------------------------------------------------------------------------------------------
Cylinder::Cylinder(const Eigen::Vector3d& base, const Eigen::Vector3d& axis, double radius,
                   double height, Material material)
    : Surface(material), base_(base), axis_(axis.normalized()), radius_(radius), height_(height) {}

bool Cylinder::intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const {
  bool found = false;
  // Side: |(o + t d - base) x axis| = radius with 0 <= height coordinate <= height.
  const Eigen::Vector3d offset = ray.origin - base_;
  const Eigen::Vector3d d_perp = ray.direction - ray.direction.dot(axis_) * axis_;
  const Eigen::Vector3d o_perp = offset - offset.dot(axis_) * axis_;
  const double a = d_perp.squaredNorm(), b = o_perp.dot(d_perp);
  const double c = o_perp.squaredNorm() - radius_ * radius_;
  const double discriminant = b * b - a * c;
  if (a > 1e-15 && discriminant >= 0) {
    const double root = std::sqrt(discriminant);
    for (double t : {(-b - root) / a, (-b + root) / a}) {
      const double along = (offset + t * ray.direction).dot(axis_);
      if (t > t_min && t < t_max && along >= 0 && along <= height_) {
        t_max = t;
        hit.distance = t;
        hit.normal = (o_perp + t * d_perp) / radius_;
        hit.surface = this;
        found = true;
        break;
      }
    }
  }
  // Caps.
  const double d_axis = ray.direction.dot(axis_);
  if (std::abs(d_axis) > 1e-12) {
    for (double cap : {0.0, height_}) {
      const double t = (cap - offset.dot(axis_)) / d_axis;
      if (t <= t_min || t >= t_max) continue;
      const Eigen::Vector3d p = offset + t * ray.direction;
      if ((p - p.dot(axis_) * axis_).squaredNorm() > radius_ * radius_) continue;
      t_max = t;
      hit.distance = t;
      hit.normal = cap == 0.0 ? Eigen::Vector3d(-axis_) : axis_;
      hit.surface = this;
      found = true;
    }
  }
  return found;
}

double Cylinder::boundingRadius() const { return std::hypot(radius_, 0.5 * height_); }
Eigen::Vector3d Cylinder::boundingCenter() const { return base_ + 0.5 * height_ * axis_; }

// ---------------------------------------------------------------------------------------------
Ellipsoid::Ellipsoid(const Eigen::Vector3d& center, const Eigen::Matrix3d& orientation,
                     const Eigen::Vector3d& radii, Material material)
    : Surface(material), center_(center), radii_(radii), orientation_(orientation) {
  to_unit_ = radii_.cwiseInverse().asDiagonal() * orientation_.transpose();
}

bool Ellipsoid::intersect(const Ray& ray, double t_min, double t_max, Hit& hit) const {
  // In unit-sphere coordinates the ray is o' + t d' and the surface |x| = 1.
  const Eigen::Vector3d o = to_unit_ * (ray.origin - center_);
  const Eigen::Vector3d d = to_unit_ * ray.direction;
  double t;
  if (!nearestRoot(d.squaredNorm(), o.dot(d), o.squaredNorm() - 1.0, t_min, t_max, t)) return false;
  hit.distance = t;
  // The gradient of |M x|^2 is M^T M x: the normal is M^T times the unit-sphere point.
  hit.normal = (to_unit_.transpose() * (o + t * d)).normalized();
  hit.surface = this;
  return true;
}

// ---------------------------------------------------------------------------------------------
void Scene::add(std::unique_ptr<Surface> surface) { surfaces_.push_back(std::move(surface)); }

void Scene::addJoints(const std::vector<SkeletonJoint>& joints) {
  skeleton_.insert(skeleton_.end(), joints.begin(), joints.end());
}

namespace {

// Cull by the bounding sphere: true when the ray's line misses it or it lies outside
// [t_min, t_max] (surfaces without a finite bound are never culled).
bool missesBoundingSphere(const Surface& surface, const Ray& ray, double t_min, double t_max) {
  const double radius = surface.boundingRadius();
  if (!std::isfinite(radius)) return false;
  const Eigen::Vector3d to_center = surface.boundingCenter() - ray.origin;
  const double along = to_center.dot(ray.direction);
  if (along + radius < t_min || along - radius > t_max) return true;
  return to_center.squaredNorm() - along * along > radius * radius;
}

}  // namespace

bool Scene::intersect(const Ray& ray, Hit& hit, double t_min, double t_max) const {
  bool found = false;
  for (size_t index = 0; index < surfaces_.size(); ++index) {
    const Surface* surface = surfaces_[index].get();
    if (missesBoundingSphere(*surface, ray, t_min, t_max)) continue;
    if (surface->intersect(ray, t_min, t_max, hit)) {
      t_max = hit.distance;
      hit.surface_index = static_cast<int>(index);
      found = true;
    }
  }
  return found;
}

void Scene::intersectMany(const Ray* rays, int count, Hit* hits, double t_min) const {
  for (int i = 0; i < count; ++i) hits[i] = Hit{};
  for (size_t index = 0; index < surfaces_.size(); ++index) {
    const Surface* surface = surfaces_[index].get();
    const double radius = surface->boundingRadius();
    // Rays whose line meets the bounding sphere, in runs (a row's rays are contiguous).
    int start = 0;
    while (start < count) {
      auto meets = [&](int i) {
        if (!std::isfinite(radius)) return true;
        const Eigen::Vector3d to_center = surface->boundingCenter() - rays[i].origin;
        const double along = to_center.dot(rays[i].direction);
        return along + radius >= t_min && along - radius <= hits[i].distance &&
               to_center.squaredNorm() - along * along <= radius * radius;
      };
      while (start < count && !meets(start)) ++start;
      int end = start;
      while (end < count && meets(end)) ++end;
      if (end > start) {
        std::vector<Hit> run(hits + start, hits + end);
        surface->intersectMany(rays + start, end - start, t_min, run.data());
        for (int i = start; i < end; ++i)
          if (run[i - start].surface == surface) {
            hits[i] = run[i - start];
            hits[i].surface_index = static_cast<int>(index);
          }
      }
      start = end;
    }
  }
}

bool Scene::occluded(const Eigen::Vector3d& from, const Eigen::Vector3d& to) const {
  const Eigen::Vector3d delta = to - from;
  const double length = delta.norm();
  const Ray ray{from, delta / length};
  // Tolerances keep a surface from shadowing itself at the start point.
  const double t_min = 1e-5, t_max = length - 1e-5;
  for (const auto& surface : surfaces_) {
    if (missesBoundingSphere(*surface, ray, t_min, t_max)) continue;
    if (surface->occludes(ray, t_min, t_max)) return true;
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
namespace {

Eigen::Vector3d readVector(const YAML::Node& node, const std::string& key,
                           const std::string& where) {
  const YAML::Node value = node[key];
  if (!value || !value.IsSequence() || value.size() != 3)
    throw std::runtime_error(where + ": '" + key + "' must be a list of 3 numbers [x, y, z]");
  return {value[0].as<double>(), value[1].as<double>(), value[2].as<double>()};
}

double readPositive(const YAML::Node& node, const std::string& key, const std::string& where,
                    std::optional<double> fallback = std::nullopt) {
  if (!node[key]) {
    if (fallback) return *fallback;
    throw std::runtime_error(where + ": missing '" + key + "' (a positive number, metres)");
  }
  const double value = node[key].as<double>();
  if (!(value > 0)) throw std::runtime_error(where + ": '" + key + "' must be > 0");
  return value;
}

Material readMaterial(const YAML::Node& node) {
  Material material;
  if (node["albedo"]) material.albedo = node["albedo"].as<double>();
  if (node["color"]) material.color = readVector(node, "color", "material");
  return material;
}

void addObject(const YAML::Node& object, const std::string& where, const std::string& base_dir,
               Scene& scene) {
  const std::string type = object["type"] ? object["type"].as<std::string>() : "";
  std::unique_ptr<Surface> surface;
  if (type == "plane") {
    surface = std::make_unique<Plane>(
        readVector(object, "point", where), readVector(object, "normal", where),
        readMaterial(object), object["half_extent"] ? object["half_extent"].as<double>() : 0);
  } else if (type == "checkerboard") {
    surface = std::make_unique<CheckerboardPlane>(
        readVector(object, "center", where), readVector(object, "normal", where),
        readVector(object, "axis_u", where), object["cols"].as<int>(9), object["rows"].as<int>(7),
        readPositive(object, "square_size", where), object["light_albedo"].as<double>(0.8),
        object["dark_albedo"].as<double>(0.1));
  } else if (type == "sphere") {
    surface = std::make_unique<Sphere>(readVector(object, "center", where),
                                       readPositive(object, "radius", where), readMaterial(object));
  } else if (type == "cylinder") {
    surface = std::make_unique<Cylinder>(
        readVector(object, "base", where), readVector(object, "axis", where),
        readPositive(object, "radius", where), readPositive(object, "height", where),
        readMaterial(object));
  } else if (type == "calibration_cylinder") {
    CalibrationCylinderLayout layout;
    layout.radius = readPositive(object, "radius", where, layout.radius);
    layout.height = readPositive(object, "height", where, layout.height);
    layout.grid_pitch = readPositive(object, "grid_pitch", where, layout.grid_pitch);
    layout.marker_fraction = readPositive(object, "marker_fraction", where, layout.marker_fraction);
    if (layout.marker_fraction >= 1)
      throw std::runtime_error(where +
                               ": 'marker_fraction' must be < 1 (marker inside its square)");
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() =
        object["base"] ? readVector(object, "base", where) : Eigen::Vector3d::Zero();
    pose.linear() =
        Eigen::AngleAxisd(object["yaw_deg"].as<double>(0.0) * M_PI / 180, Eigen::Vector3d::UnitZ())
            .toRotationMatrix();
    surface =
        std::make_unique<CalibrationCylinder>(pose, layout, object["light_albedo"].as<double>(0.9),
                                              object["dark_albedo"].as<double>(0.5));
  } else if (type == "human") {
    addHumanBody(humanBodyFromYaml(object), scene);
    return;
  } else if (type == "bvh_human") {
    addHumanBody(bvhHumanFromYaml(object, where, base_dir), scene);
    return;
  } else if (type == "mesh_human") {
    addMeshHumanFromYaml(object, where, base_dir, scene);
    return;
  } else {
    throw std::runtime_error(where + ": unknown type '" + type +
                             "'; use plane, checkerboard, sphere, cylinder, calibration_cylinder, "
                             "human, bvh_human or mesh_human");
  }
  surface->name = object["name"] ? object["name"].as<std::string>() : type;
  scene.add(std::move(surface));
}

}  // namespace

namespace {

// `source` names the text in errors ("scene file 'x.yaml'"), `prefix` starts each object's.
// Relative file names in objects (bvh_human) are relative to base_dir.
Scene sceneFromYaml(const YAML::Node& root, const std::string& source, const std::string& prefix,
                    const std::string& base_dir) {
  if (!root["objects"] || !root["objects"].IsSequence())
    throw std::runtime_error(source + " needs a list 'objects:'");
  Scene scene;
  int index = 0;
  for (const YAML::Node& object : root["objects"]) {
    const std::string where = prefix + ": objects[" + std::to_string(index++) + "]";
    try {
      addObject(object, where, base_dir, scene);
    } catch (const YAML::Exception& e) {
      throw std::runtime_error(where + ": " + e.what());
    }
  }
  return scene;
}

}  // namespace

Scene loadScene(const std::string& path) {
  return sceneFromYaml(loadYamlFile(path, "scene"), "scene file '" + path + "'", path,
                       std::filesystem::path(path).parent_path().string());
}

Scene parseScene(const std::string& yaml_text) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(std::string("cannot parse the scene text: ") + e.what() +
                             " (check the YAML syntax)");
  }
  return sceneFromYaml(root, "the scene text", "scene text", "");
}

}  // namespace body_scan_driver::sim
