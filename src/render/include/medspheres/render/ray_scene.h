#pragma once
/// \file
/// RayScene: ray casting against a mesh (through MeshQuery's hierarchy, which also
/// answers distances) and a sphere set's SphereTree (a flat copy of its nodes' bounds,
/// read once through the tree's public accessors). Frame and units: the mesh's and the set's, which
/// must share them. Immutable once built; trace() may be called from many threads at once.

#include <array>
#include <cstddef>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_set.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres::render {

/// What one ray meets. Distances are along the unit direction, from the ray's origin;
/// +infinity for nothing.
struct RayHit {
  double mesh_t = std::numeric_limits<double>::infinity();  ///< first mesh crossing
  int triangle = -1;
  Eigen::Vector3d mesh_normal = Eigen::Vector3d::UnitZ();  ///< unit, facing the ray
  /// First entry into the union of the balls: along the ray, every point before it lies
  /// outside every sphere, so a mesh crossing before it is surface no sphere covers.
  double sphere_t = std::numeric_limits<double>::infinity();
  int sphere = -1;
  Eigen::Vector3d sphere_normal = Eigen::Vector3d::UnitZ();  ///< unit, outward
  /// The winding number of the mesh at the sphere entry point: the ray's crossings of
  /// the mesh before it, +1 into the solid (against the triangle's outward normal), -1
  /// out of it. > 0: that point is inside the solid. 0 when no sphere is hit.
  int sphere_winding = 0;

  bool sphere_inside_solid() const { return sphere_winding > 0; }
};

class RayScene {
 public:
  /// Copies the mesh and the set; with \p threads allowing two or more (threads.h), the
  /// mesh's hierarchy is built on a thread of its own beside the rest.
  /// \throws std::invalid_argument as MeshQuery and SphereTree do
  ///   (non-finite vertices, bad indices, bad spheres) and for a bad thread count.
  RayScene(const TriangleMesh& mesh, const SphereSet& spheres, int threads = 0);

  /// Casts the ray origin + t direction, t >= 0; \p direction must be a unit vector and
  /// \p origin outside every sphere and outside the solid (a camera's rays are).
  RayHit trace(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const;

  /// Distance from \p p to the nearest point of the mesh (MeshQuery: exact); +infinity
  /// for a mesh without triangles.
  double distance_to_mesh(const Eigen::Vector3d& p) const;

  std::size_t num_triangles() const { return num_triangles_; }
  std::size_t num_spheres() const { return spheres_.size(); }

  /// Bounding boxes; lo > hi componentwise when the mesh or the set is empty.
  Eigen::Vector3d mesh_lo() const { return mesh_lo_; }
  Eigen::Vector3d mesh_hi() const { return mesh_hi_; }
  Eigen::Vector3d spheres_lo() const { return spheres_lo_; }
  Eigen::Vector3d spheres_hi() const { return spheres_hi_; }

 private:
  struct BallNode {  ///< a SphereTree node: its bounding ball
    Eigen::Vector3d center;
    double radius = 0.0;
    int left = -1, right = -1;  ///< children, or -1 for a leaf
    int begin = 0, end = 0;     ///< a leaf's spheres: leaf_spheres_[begin, end)
  };
  void flatten_spheres(const SphereSet& spheres);
  void trace_spheres(const Eigen::Vector3d& o, const Eigen::Vector3d& d, RayHit& hit) const;
  void trace_mesh(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double limit,
                  bool count_crossings, RayHit& hit) const;

  std::unique_ptr<const MeshQuery> query_;  ///< null for a mesh without triangles
  std::size_t num_triangles_ = 0;
  std::vector<Sphere> spheres_;
  std::vector<BallNode> balls_;
  std::vector<int> leaf_spheres_;
  Eigen::Vector3d mesh_lo_, mesh_hi_, spheres_lo_, spheres_hi_;
};

}  // namespace medspheres::render
