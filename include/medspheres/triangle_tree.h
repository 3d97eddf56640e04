#pragma once
/// \file
/// TriangleTree: an RSS hierarchy over the triangles of a TriangleMesh (built like
/// SphereTree's: each triangle fitted as its three corners, split by centroid, one per
/// leaf), so that a SphereTree can be queried against a mesh. Frame and units: the mesh's
/// own, called B in queries (sphere_tree.h). Primitive ids are triangle indices.
///
/// The mesh is a surface, not a solid: a triangle answers a ball as
/// ball_triangle_proximity does (never below minus the radius), so spheres inside a
/// closed mesh touching no triangle neither collide with it nor have a negative distance
/// (as FCL treats a BVHModel). Every closest point comes from point_triangle.h, the
/// kernel MeshQuery uses too. Immutable once built; const members are thread-safe.

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "medspheres/point_triangle.h"
#include "medspheres/proximity_target.h"
#include "medspheres/rss.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// The answer of triangle (a, b, c), as a surface, to the ball (centre, radius):
/// distance |q - centre| - radius, q = closest_point_on_triangle(centre, a, b, c), normal
/// (q - centre) / |q - centre|; for a centre on the triangle, -(b - a) x (c - a)
/// normalized (into an outward-wound solid), or the x axis if that is zero.
BallProximity ball_triangle_proximity(const Eigen::Vector3d& center, double radius,
                                      const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                      const Eigen::Vector3d& c);

class TriangleTree final : public ProximityTarget {
 public:
  /// Builds the hierarchy over \p mesh, which is copied.
  /// \throws std::invalid_argument when a vertex has a non-finite coordinate or a
  ///   triangle has an index out of range. A mesh without triangles gives an empty tree.
  explicit TriangleTree(const TriangleMesh& mesh);

  std::size_t num_triangles() const noexcept { return triangles_.size(); }
  std::size_t num_nodes() const noexcept { return nodes_.size(); }
  /// Bounds of node \p node (0 is the root), in frame B: every corner of every triangle
  /// below it lies inside (to the rounding margin described at SphereTree::rss).
  /// \throws std::out_of_range when \p node is not a node.
  Rss node_bounds(std::size_t node) const;
  /// The triangles below \p node. \throws std::out_of_range when \p node is not a node.
  std::vector<std::size_t> triangles_below(std::size_t node) const;

  std::optional<TargetNode> root() const override;
  int children(const TargetNode& node, TargetNode* out) const override;
  BallProximity ball_proximity(const TargetNode& leaf, const Eigen::Vector3d& p_BC,
                               double radius) const override;

 private:
  struct Node {
    Rss bounds;
    int begin = 0;  ///< the triangles below are order_[begin, end)
    int end = 0;
    int first_child = -1;  ///< -1 for a leaf; otherwise children first_child and + 1
  };
  TargetNode target_node(std::size_t node) const;

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<int> order_;                       ///< triangle indices in tree order
  std::vector<detail::QueryTriangle> prepared_;  ///< per triangle (point_triangle.h)
  std::vector<Eigen::Vector3d> normals_;         ///< per triangle: its TrianglePlane's
  std::vector<Node> nodes_;
};

}  // namespace medspheres
