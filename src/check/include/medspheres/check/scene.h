#pragma once
/// \file
/// check::Scene: the obstacles a RobotChecker tests a robot against, as plain geometry in
/// the world frame W (metres): spheres, boxes, capsules, cylinders, triangle meshes, point
/// clouds and the occupied cells of an octomap. The checker builds its own structure for
/// sphere queries from them (robot_checker.h); a Scene itself is only the list.
///
/// Solids and surfaces: spheres, boxes, capsules, cylinders and cells are solids (a ball
/// inside one touches it); a mesh is a surface, as FCL treats a BVHModel (a ball wholly
/// inside a closed mesh touches no triangle); a point is a point.
/// Conventions of FCL's primitives: a box is centred on its frame's origin with the given
/// side lengths along its axes; a capsule and a cylinder are centred on their frame's
/// origin along its z axis, `length` the length of the axis segment (a capsule's caps
/// stick out by its radius beyond it).
/// Errors: std::invalid_argument for a non-finite number, a negative or zero size, or a
/// triangle whose index is out of range, naming the object and the problem.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/triangle_mesh.h"

namespace medspheres::check {

enum class ShapeKind { sphere, box, capsule, cylinder, mesh, points, cells };

/// One obstacle. Which fields count depends on the kind (the add_* functions say).
struct SceneObject {
  ShapeKind kind = ShapeKind::sphere;
  std::string name;
  Eigen::Isometry3d X_WO = Eigen::Isometry3d::Identity();  ///< the object's frame O in W
  Eigen::Vector3d size = Eigen::Vector3d::Zero();          ///< box: side lengths along O's axes
  double radius = 0.0;                                     ///< sphere, capsule, cylinder
  double length = 0.0;                                     ///< capsule, cylinder: along O's z axis
  TriangleMesh mesh;                                       ///< mesh: in O
  /// points: the points, in W; cells: the cells' centres, in W.
  std::vector<Eigen::Vector3d> points;
  double cell_side = 0.0;  ///< cells: side of every cell
};

class Scene {
 public:
  /// Each add_* returns the object's index (the order of addition).
  std::size_t add_sphere(const Eigen::Vector3d& p_WC, double radius, std::string name = "sphere");
  std::size_t add_box(const Eigen::Vector3d& size, const Eigen::Isometry3d& X_WB,
                      std::string name = "box");
  std::size_t add_capsule(double radius, double length, const Eigen::Isometry3d& X_WC,
                          std::string name = "capsule");
  std::size_t add_cylinder(double radius, double length, const Eigen::Isometry3d& X_WC,
                           std::string name = "cylinder");
  /// A triangle mesh, a surface, its vertices in frame M placed by X_WM.
  std::size_t add_mesh(const TriangleMesh& mesh, const Eigen::Isometry3d& X_WM,
                       std::string name = "mesh");
  /// A point cloud in W (points of no extent).
  std::size_t add_points(std::vector<Eigen::Vector3d> p_W, std::string name = "points");
  /// Axis-aligned cubes of side \p side centred at \p centres_W: an octomap's occupied
  /// leaves (one side for all; give each depth its own call).
  std::size_t add_cells(std::vector<Eigen::Vector3d> centres_W, double side,
                        std::string name = "cells");

  const std::vector<SceneObject>& objects() const noexcept { return objects_; }
  std::size_t size() const noexcept { return objects_.size(); }

 private:
  std::size_t add(SceneObject o);
  std::size_t add_axial(ShapeKind kind, double radius, double length, const Eigen::Isometry3d& X_WC,
                        std::string name);
  std::vector<SceneObject> objects_;
};

}  // namespace medspheres::check
