#pragma once
// bench_robot's seeded scene around a robot whose root link is at the world origin (z up,
// x forward): a table in front, shelves of boxes to the left, a few meshes (shared ones
// when the folder exists, generated ones otherwise) and, to the right, an octomap
// (fcl::OcTree) of a seeded point cloud: a wall with a pile of clutter in front of it.

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fcl/narrowphase/collision_object.h>

#include "medspheres/mesh/mesh_query.h"

namespace medspheres::bench {

struct SceneObject {
  std::string name;
  std::shared_ptr<::fcl::CollisionObjectd> object;  ///< posed in W, AABB computed
};

struct BenchScene {
  std::vector<SceneObject> objects;
  std::size_t boxes = 0, meshes = 0, mesh_triangles = 0;
  std::size_t cloud_points = 0, octree_cells = 0;  ///< occupied leaves
  double octree_resolution = 0.0;
  /// The octomap's occupied cells as one mesh of boxes (BVHModel<OBBRSS>, 12 triangles a
  /// cell): the exact reference's view of the octomap, independent of FCL's octree code.
  std::shared_ptr<::fcl::CollisionObjectd> octree_cells_mesh;
  /// The solids of the meshes and of the cells mesh, for the reference's inside tests.
  std::map<const ::fcl::CollisionGeometryd*, std::shared_ptr<const MeshQuery>> solids;
  /// The objects as robot_bounds takes them; with \p cells_as_mesh the octomap is
  /// octree_cells_mesh.
  std::vector<const ::fcl::CollisionObjectd*> pointers(bool cells_as_mesh = false) const;
};

/// \p meshes_dir: a folder with MANIFEST.tsv (empty: generated meshes only). \p scale
/// stretches every position and size (1 for a robot the size of a human; the G1 is
/// about 1.3 m tall with its pelvis 0.8 m above the floor).
BenchScene make_scene(unsigned seed, const std::string& meshes_dir, double scale);

}  // namespace medspheres::bench
