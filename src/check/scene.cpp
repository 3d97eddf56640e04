#include "medspheres/check/scene.h"

#include <cmath>
#include <stdexcept>

namespace medspheres::check {
namespace {

void require(bool ok, const std::string& name, const std::string& problem) {
  if (!ok) throw std::invalid_argument("scene object \"" + name + "\": " + problem);
}

bool finite(const Eigen::Isometry3d& X) {
  return X.matrix().allFinite();
}

void require_positive(double v, const std::string& name, const char* what) {
  require(std::isfinite(v) && v > 0.0, name, std::string(what) + " must be finite and > 0");
}

}  // namespace

std::size_t Scene::add(SceneObject o) {
  require(finite(o.X_WO), o.name, "its pose is not finite");
  objects_.push_back(std::move(o));
  return objects_.size() - 1;
}

std::size_t Scene::add_sphere(const Eigen::Vector3d& p_WC, double radius, std::string name) {
  require(p_WC.allFinite(), name, "its centre is not finite");
  require_positive(radius, name, "the radius");
  SceneObject o;
  o.kind = ShapeKind::sphere;
  o.name = std::move(name);
  o.X_WO.translation() = p_WC;
  o.radius = radius;
  return add(std::move(o));
}

std::size_t Scene::add_box(const Eigen::Vector3d& size, const Eigen::Isometry3d& X_WB,
                           std::string name) {
  for (int k = 0; k < 3; ++k) require_positive(size[k], name, "every side length");
  SceneObject o;
  o.kind = ShapeKind::box;
  o.name = std::move(name);
  o.X_WO = X_WB;
  o.size = size;
  return add(std::move(o));
}

// A capsule or a cylinder: a radius about a length of the frame's z axis (a capsule may
// have length 0, a ball).
std::size_t Scene::add_axial(ShapeKind kind, double radius, double length,
                             const Eigen::Isometry3d& X_WC, std::string name) {
  require_positive(radius, name, "the radius");
  require(std::isfinite(length) && (length > 0.0 || (length == 0.0 && kind == ShapeKind::capsule)),
          name, "the length must be finite and > 0 (>= 0 for a capsule)");
  SceneObject o;
  o.kind = kind;
  o.name = std::move(name);
  o.X_WO = X_WC;
  o.radius = radius;
  o.length = length;
  return add(std::move(o));
}

std::size_t Scene::add_capsule(double radius, double length, const Eigen::Isometry3d& X_WC,
                               std::string name) {
  return add_axial(ShapeKind::capsule, radius, length, X_WC, std::move(name));
}

std::size_t Scene::add_cylinder(double radius, double length, const Eigen::Isometry3d& X_WC,
                                std::string name) {
  return add_axial(ShapeKind::cylinder, radius, length, X_WC, std::move(name));
}

std::size_t Scene::add_mesh(const TriangleMesh& mesh, const Eigen::Isometry3d& X_WM,
                            std::string name) {
  const int nv = static_cast<int>(mesh.vertices.size());
  for (const Eigen::Vector3d& v : mesh.vertices)
    require(v.allFinite(), name, "a vertex is not finite");
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      require(t[k] >= 0 && t[k] < nv, name,
              "a triangle's vertex index " + std::to_string(t[k]) + " is out of range");
  SceneObject o;
  o.kind = ShapeKind::mesh;
  o.name = std::move(name);
  o.X_WO = X_WM;
  o.mesh = mesh;
  return add(std::move(o));
}

std::size_t Scene::add_points(std::vector<Eigen::Vector3d> p_W, std::string name) {
  for (const Eigen::Vector3d& p : p_W) require(p.allFinite(), name, "a point is not finite");
  SceneObject o;
  o.kind = ShapeKind::points;
  o.name = std::move(name);
  o.points = std::move(p_W);
  return add(std::move(o));
}

std::size_t Scene::add_cells(std::vector<Eigen::Vector3d> centres_W, double side,
                             std::string name) {
  require_positive(side, name, "the cell side");
  for (const Eigen::Vector3d& p : centres_W)
    require(p.allFinite(), name, "a cell centre is not finite");
  SceneObject o;
  o.kind = ShapeKind::cells;
  o.name = std::move(name);
  o.points = std::move(centres_W);
  o.cell_side = side;
  return add(std::move(o));
}

}  // namespace medspheres::check
