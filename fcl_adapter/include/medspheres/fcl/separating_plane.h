#pragma once
/// \file
/// A proof that two posed meshes are farther apart than a margin, by a plane between their
/// vertices: cheaper than FCL's mesh distance for the pairs it settles, and exact.
///
/// Why it holds: a mesh's triangles (and the solid they bound, closed or not) lie in the
/// convex hull of its vertices. If, along a unit direction u, every vertex of A lies at
/// most h_A and every vertex of B at least m_B, with m_B - h_A > margin, then every point
/// of A's hull is at least m_B - h_A from every point of B's (the distance between two
/// points is at least the difference of their projections on u), so the two meshes and
/// their solids are farther apart than the margin. Only "free" is ever concluded; when no
/// such plane is found the caller asks the meshes.
///
/// The direction: GJK on the two vertex sets (the Minkowski difference of their hulls),
/// each support point the exact extreme vertex found by a walk of a ball tree over the
/// mesh's vertices, from a starting direction the caller gives (any nonzero vector: the
/// direction only decides how soon a plane is found, never whether the proof holds). GJK
/// stops when a plane clears the margin, when its point of the difference is within the
/// margin of the origin (the hulls are then within the margin: no plane exists), when it
/// no longer progresses, or after 24 steps.
///
/// A first, cheaper phase runs the same GJK on a few of each set's vertices (its extremes
/// along 128 fixed directions, in cache; VertexSupport::coarse_max_along): the hulls of
/// those subsets lie in the whole sets' hulls, so where their GJK finds the subsets within
/// the margin (or overlapping), no plane clears the margin for the whole sets either, and
/// the search stops without a walk of the trees. Where a direction clears the margin for
/// the subsets, the trees' exact walks decide along it (the proof above, unchanged); when
/// they do not clear it, or the first phase runs out of steps, the exact GJK goes on from
/// that direction. The first phase decides only how soon a plane is found, or that none
/// exists; every "free" rests on the exact extremes. Along the first phase's direction the
/// trees are asked only whether every vertex stays within half the subsets' slack of their
/// extremes (VertexSupport::at_most, a walk that prunes at that limit): the limits, bounds
/// of the computed extremes, give a gap no larger than the exact walks' one, which must
/// clear the margin by the same allowance.
///
/// Rounding: every projection is computed in the link's frame, u's image R^T u against the
/// vertex x and u against the frame's origin p, so each computed value differs from the
/// exact u . (R x + p) (R, p, x the doubles given; u the computed unit direction) by at
/// most 8 eps (|x|_1 + |p|_1) |u|_1 (eps = 2^-53); a ball of the tree is skipped when its
/// centre's projection plus its radius (rounded up by a relative 1e-14) cannot exceed the
/// best vertex found, so the computed extremes are within 16 eps of the magnitudes of the
/// exact ones (a ball's value is c . n + r |n|, |n| grown by a relative 1e-15); |u| is within 4 eps
/// of 1. The proof asks m_B - h_A to exceed the margin by gap_allowance (1e-12 of the magnitudes:
/// the two frames' origins, the meshes' largest coordinates and the margin), more than 10^3 times
/// these errors. So a pair proved free has an exact distance (and FCL's, within its own few ulps)
/// above margin + 1e-12 of the magnitudes: the verdict the meshes would give.
///
/// Frames and units: vertices in the link frame, poses X_W* in the world frame W, metres.
/// Degenerate input: a mesh without vertices has no VertexSupport (the constructor
/// throws std::invalid_argument); coincident vertices are kept once; a pose or margin that
/// is not finite proves nothing (false). Threads: immutable after construction; any number
/// of threads may query at once.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <fcl/math/geometry.h>
#include <fcl/narrowphase/collision_object.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/sphere_set.h"

namespace medspheres::fcl {

/// A mesh's vertices (or a union of balls: a link made of sphere primitives) in a ball
/// tree, for exact support queries. The solid it stands for lies in the convex hull of
/// the vertices (of the balls).
class VertexSupport {
 public:
  /// \throws std::invalid_argument for no vertices or a non-finite vertex.
  explicit VertexSupport(const std::vector<Eigen::Vector3d>& vertices);
  /// The vertices of a finished FCL mesh (make_mesh_model).
  explicit VertexSupport(const MeshModel& mesh);
  /// The balls (radius finite and >= 0); their union is the solid.
  /// \throws std::invalid_argument for no balls, a non-finite centre or a bad radius.
  explicit VertexSupport(const std::vector<Sphere>& balls);

  /// The greatest n . x over the vertices x (over the balls' points: n . c + r |n|), as
  /// computed (see the file comment for its rounding), and a point of the set that
  /// reaches it. \p hint, when given, is the index of a point to start from (a former
  /// extreme for a nearby direction prunes most of the tree at once; any value is
  /// accepted) and receives the extreme's.
  struct Extreme {
    double value;
    Eigen::Vector3d point;
  };
  Extreme max_along(const Eigen::Vector3d& n, std::uint32_t* hint = nullptr) const;

  /// Whether no vertex (no ball's point) exceeds \p limit along n: max_along's value is
  /// at most \p limit, decided by the same walk pruning at \p limit instead of at the best
  /// vertex found (so fewer nodes are read), starting from the point \p hint.
  bool at_most(const Eigen::Vector3d& n, double limit, std::uint32_t hint) const;

  /// The greatest n . x over a fixed subset of the points (the extremes along 128
  /// directions spread over the sphere, or every point of a small set), as computed, and
  /// the point's index for max_along's hint. At most max_along's value: a lower bound of
  /// the set's support, for directions only, never for a proof.
  struct CoarseExtreme {
    double value;
    Eigen::Vector3d point;
    std::uint32_t index;
  };
  CoarseExtreme coarse_max_along(const Eigen::Vector3d& n) const;

  std::size_t size() const noexcept { return points_.size(); }
  std::size_t coarse_size() const noexcept { return coarse_.size(); }
  /// The largest |x|_1 + r of a vertex or ball (the magnitude of the rounding rule).
  double extent() const noexcept { return extent_; }

 private:
  struct Node {
    Eigen::Vector3d centre;
    double radius;        // rounded up: every vertex (ball) of the node lies within it
    std::uint32_t begin;  // points_[begin, end) for a leaf
    std::uint32_t end;
    std::uint32_t left = 0;  // children (0: a leaf; the root is node 0)
    std::uint32_t right = 0;
  };
  void prepare();
  std::uint32_t build(std::uint32_t begin, std::uint32_t end);
  void choose_coarse();

  std::vector<Eigen::Vector4d> points_;  // centre and radius (0 for a vertex)
  std::vector<Node> nodes_;
  std::vector<Eigen::Vector4d> coarse_;      // the subset's points, as points_
  std::vector<std::uint32_t> coarse_index_;  // their indices in points_
  double extent_ = 0.0;
};

/// The support of an FCL scene geometry in its own frame, or null: a BVHModel of
/// triangles (its vertices), a Box (its corners), a Sphere (its ball), a Capsule (the
/// balls at its two ends, whose hull it is). Other geometries get none.
std::unique_ptr<const VertexSupport> support_of(const ::fcl::CollisionGeometryd& g);

/// What separated() found, for reports and tests.
struct PlaneResult {
  bool free = false;  ///< a plane clears the margin: the meshes are farther apart than it
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  ///< unit, from A towards B, in W
  double gap = 0.0;      ///< m_B - h_A along direction (computed), when free
  int steps = 0;         ///< GJK steps on the exact supports (the trees' walks, two a step)
  int coarse_steps = 0;  ///< GJK steps of the first phase, on the subsets
  /// The first phase found the subsets within the margin of each other (or overlapping):
  /// no plane exists, and no exact step was taken.
  bool no_plane = false;
};

/// Whether a plane between A's vertices (at X_WA) and B's (at X_WB) clears \p margin
/// (finite, >= 0), starting GJK along \p guess (in W, from A towards B; a zero or
/// non-finite guess starts from the two frames' origins).
PlaneResult separated(const VertexSupport& a, const ::fcl::Transform3d& X_WA,
                      const VertexSupport& b, const ::fcl::Transform3d& X_WB, double margin,
                      const Eigen::Vector3d& guess);

}  // namespace medspheres::fcl
