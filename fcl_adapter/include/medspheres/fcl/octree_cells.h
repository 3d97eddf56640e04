#pragma once
/// \file
/// OctreeCells: FCL's exact distance between a link's mesh and an fcl::OcTree, asked only
/// of the octree's cells near the link. FCL's own query (fcl::distance of a BVHModel and
/// an OcTree) walks the octree from its root, pruning with axis-aligned boxes around the
/// mesh's bounding volumes; here the cells are listed once, indexed by position, and for a
/// posed link only the cells near its mesh's box and its certified cover go to FCL's
/// mesh-to-box distance, whose leaf tests are the same: FCL's box-triangle distance
/// (shapeTriangleDistance) on the same box, at the same transform (fcl::constructBox of the
/// cell's cube), against the same triangles. So the answer is FCL's up to which pairs each
/// prunes: both visit every cell-triangle pair within the margin.
///
/// The cells are FCL's: from the root (fcl::OcTree::getRootBV), each child's cube by
/// fcl::computeChildBV; a cell with children is opened only when occupied
/// (fcl::OcTree::isNodeOccupied), and a cell without children counts when occupied.
/// Frames and units: the octree's cells in its frame O, placed in W at X_WO; the mesh in its
/// link frame A, placed at X_WA; metres (the octree's units).
/// Pruning: a cell is skipped when its cube is farther than margin + kGjkSlack from the
/// mesh's vertices' box, or, with a certified cover (Cover, built from a covering set whose
/// union holds the mesh's surface), from every ball of the cover. kGjkSlack exceeds FCL's
/// GJK tolerance (1e-6) tenfold, so a skipped cell is one whose GJK distance to every
/// triangle exceeds the margin too.
/// Threads: immutable after construction; distance() may run from many threads at once.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <fcl/math/bv/AABB.h>
#include <Eigen/Geometry>

#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/sphere_set.h"

namespace fcl {
template <typename S>
class OcTree;
}

namespace medspheres::fcl {

class OctreeCells {
 public:
  /// m: how much farther than the margin a pruned cell lies from the mesh (see the file
  /// comment).
  static constexpr double kGjkSlack = 1e-5;

  /// A link as distance() takes it: its mesh, the box of the mesh's vertices, and with a
  /// certified outer set its balls, in groups of a few under a bounding ball (frame A).
  class Link {
   public:
    /// \p g must have a mesh (std::invalid_argument otherwise). The cover is used only
    /// when g.certified().
    explicit Link(const BoundedGeometry& g);

   private:
    friend class OctreeCells;
    struct Group {
      Sphere bound;
      std::vector<Sphere> balls;
    };
    const MeshModel* mesh_ = nullptr;
    Eigen::AlignedBox3d box_;
    std::vector<Group> cover_;
  };

  /// The occupied cells of \p tree (FCL's rules, file comment) placed at X_WO.
  OctreeCells(const ::fcl::OcTree<double>& tree, const Eigen::Isometry3d& X_WO);

  std::size_t size() const noexcept { return cells_.size(); }
  /// Cell i's cube, in O (i < size()).
  const ::fcl::AABBd& cell(std::size_t i) const { return cells_.at(i); }

  /// FCL's distance between the link's mesh at X_WA and the cells: exact when <= margin
  /// (the smallest box-triangle distance, -1 for a box that a triangle enters, as FCL's
  /// GJK reports it), otherwise some value > margin. \p margin finite and >= 0, X_WA
  /// finite (std::invalid_argument otherwise).
  double distance(const Link& link, const Eigen::Isometry3d& X_WA, double margin) const;

 private:
  struct Key {
    std::int64_t x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  Key key_of(const Eigen::Vector3d& p) const;
  void candidates(const Link& link, const Eigen::Isometry3d& X_OA, double reach,
                  std::vector<std::uint32_t>& out) const;

  Eigen::Isometry3d X_WO_ = Eigen::Isometry3d::Identity();
  std::vector<::fcl::AABBd> cells_;  // cubes in O
  double bucket_ = 1.0;              // side of a bucket of the index, in O
  std::unordered_map<Key, std::vector<std::uint32_t>, KeyHash> buckets_;
};

/// The cells of \p g placed at X_WO when g is an fcl::OcTree, else null.
std::unique_ptr<const OctreeCells> octree_cells_of(const ::fcl::CollisionGeometryd& g,
                                                   const Eigen::Isometry3d& X_WO);

}  // namespace medspheres::fcl
