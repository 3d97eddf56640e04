#pragma once
/// \file
/// SphereTree: a binary bounding-volume hierarchy over a SphereSet (paper §5.2), and the
/// proximity queries on it: distance, signed distance and collision between two trees,
/// between a tree and a point, and between a tree and a ProximityTarget.
///
/// Frames (monogram notation, as FCL's sphere_box.h): A is a tree's frame (its
/// SphereSet's), B the other object's, W the world. X_WA is the pose of A in W, a rigid
/// transform with an orthonormal rotation; p_WQ is point Q measured and expressed in W.
/// Results are in W, in the sphere set's units.
///
/// Pair values. Balls (a, r_a), (b, r_b): signed distance |b - a| - (r_a + r_b), unit
/// normal n from a to b (W's x axis when a = b), witness points a + r_a n and b - r_b n.
/// A target's primitive answers as BallProximity says. Touching is collision: a pair
/// collides unless |b - a| > r_a + r_b (FCL's sphere-sphere comparison).
/// Contact: position the midpoint of the witness points (FCL's sphere-box convention),
/// normal n (from A to B), depth -(signed distance) >= 0.
///
/// Tolerances: as FCL's DistanceRequest; with abs_err or rel_err zero (the default) the
/// answer is exact, otherwise a separated answer d and the minimum d* satisfy
/// d* <= d <= min(d* + abs_err, (1 + rel_err) d*); a negative signed distance is exact.
/// Values carry double rounding: a few ulps of the coordinates' magnitude.
///
/// Ties: the pair found first is reported. The traversal order depends only on the two
/// trees, the poses and the query, so answers are deterministic; swapping the objects
/// may report another pair of a tie. Contacts come in traversal order, not by depth.
///
/// Errors and degenerate input: an empty tree finds nothing (TreeDistance::found() is
/// false, collide() false, no contacts). Non-finite poses or points and negative or NaN
/// tolerances throw std::invalid_argument. Coincident spheres and centres are handled.
///
/// Threads: a tree is immutable once built and the queries are free functions on const
/// references; any number of threads may query the same trees at once.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/min_enclosing_ball.h"
#include "medspheres/proximity_target.h"
#include "medspheres/rss.h"
#include "medspheres/sphere_set.h"

namespace medspheres {

/// The bounding volume of a SphereTree's nodes.
enum class BoundingVolumeKind {
  rss,   ///< rectangle-swept sphere (paper §5.2; the paper found these faster)
  ball,  ///< minimum enclosing ball of the spheres below the node
};

struct SphereTreeOptions {
  BoundingVolumeKind kind = BoundingVolumeKind::rss;  ///< node bounding volume
  int max_leaf_size = 8;  ///< most spheres in a leaf, >= 1 (see docs/benchmarks.md)
  /// Accept balls of radius 0 (points, e.g. surface points added to an inner set: a
  /// point's distance to anything is the distance of the point itself).
  bool allow_points = false;
};

/// Shape and size of a tree, reported next to timings.
struct SphereTreeStats {
  std::size_t spheres = 0;
  std::size_t nodes = 0;  ///< internal nodes plus leaves
  std::size_t leaves = 0;
  std::size_t depth = 0;  ///< edges on the longest root-to-leaf path (0 for one node)
  std::size_t min_leaf_size = 0;
  std::size_t max_leaf_size = 0;
  double mean_leaf_size = 0.0;
  std::size_t bytes = 0;  ///< memory held by the tree: its one allocation plus headers
};

class SphereTree {
 public:
  /// A node's bounding ball (bounding_ball()) has radius R with R* <= R <=
  /// (1 + ball_slack) R*, R* the minimum enclosing ball's, to rounding, and encloses every
  /// sphere below the node exactly (rounded up).
  static constexpr double ball_slack = kEnclosingBallSlack;

  /// An empty tree.
  SphereTree();

  /// Builds the tree over \p set, which is copied (the tree does not refer to it): top
  /// down, each node split across its spheres' principal axis; a node of at most
  /// max_leaf_size spheres is a leaf, and the depth is at most log(n) / log(10/9).
  /// \throws InputError (source "sphere set") if a sphere has a non-finite coordinate or
  ///   a radius that is not finite and > 0 (>= 0 with options.allow_points; see
  ///   validate_sphere_set).
  /// \throws std::invalid_argument if options.max_leaf_size < 1.
  explicit SphereTree(const SphereSet& set, const SphereTreeOptions& options = {});

  BoundingVolumeKind kind() const noexcept;
  std::size_t num_spheres() const noexcept;
  std::size_t num_nodes() const noexcept;
  bool empty() const noexcept { return num_spheres() == 0; }

  /// Sphere \p i of the set the tree was built from, in its original order.
  /// Precondition: i < num_spheres() (checked: std::out_of_range).
  Sphere sphere(std::size_t i) const;

  // Nodes are numbered 0 .. num_nodes() - 1; node 0 is the root. Every accessor below
  // checks its node index and throws std::out_of_range when it is not a node.

  /// True for a leaf.
  bool is_leaf(std::size_t node) const;
  /// The two children of an internal node (std::invalid_argument for a leaf).
  std::size_t left_child(std::size_t node) const;
  std::size_t right_child(std::size_t node) const;
  /// The spheres below \p node, as indices into the original set, in tree order.
  std::vector<std::size_t> spheres_below(std::size_t node) const;
  /// For BoundingVolumeKind::rss: the node's RSS, in frame A, which contains every sphere
  /// below the node (its radius rounded up).
  /// \throws std::invalid_argument for a BoundingVolumeKind::ball tree.
  Rss rss(std::size_t node) const;
  /// The minimum enclosing ball, in frame A, of the spheres below the node, within
  /// ball_slack and proven to contain them. Both kinds store it; for kind ball it is the
  /// node's bounding volume.
  Sphere bounding_ball(std::size_t node) const;
  /// The largest radius of a sphere below the node.
  double max_sphere_radius(std::size_t node) const;

  SphereTreeStats stats() const;

  struct Layout;  ///< the flat arrays; defined in the library's sources

 private:
  std::shared_ptr<const Layout> layout_;
  friend const Layout* tree_layout(const SphereTree& tree) noexcept;
};

/// Options of the distance queries. The defaults give the exact answer.
struct DistanceOptions {
  double abs_err = 0.0;  ///< absolute tolerance, >= 0 (FCL's DistanceRequest::abs_err)
  double rel_err = 0.0;  ///< relative tolerance, >= 0 (FCL's DistanceRequest::rel_err)
  /// Only pairs strictly closer than this are reported (FCL's preset
  /// DistanceResult::min_distance, which MoveIt uses as a threshold). It also prunes.
  double upper_bound = std::numeric_limits<double>::infinity();
};

/// Work done by one query: the BVH statistics of a run.
struct QueryStats {
  std::uint64_t bv_tests = 0;    ///< node-pair lower bounds evaluated
  std::uint64_t leaf_tests = 0;  ///< sphere-sphere or sphere-primitive tests
};

/// The pair reported by a distance query.
struct TreeDistance {
  /// The pair's (signed) distance; upper_bound when no pair is closer than it.
  double distance = std::numeric_limits<double>::infinity();
  Eigen::Vector3d p_WPa = Eigen::Vector3d::Zero();  ///< witness point on A, in W
  Eigen::Vector3d p_WPb = Eigen::Vector3d::Zero();  ///< witness point on B, in W
  std::intptr_t sphere_a = -1;  ///< index into A's SphereSet, or -1 when nothing found
  /// Index into B's SphereSet, the primitive id of a target's leaf, or -1.
  std::intptr_t primitive_b = -1;
  QueryStats stats;
  bool found() const noexcept { return sphere_a >= 0; }
};

/// One overlapping pair.
struct TreeContact {
  Eigen::Vector3d p_WC = Eigen::Vector3d::Zero();  ///< contact position, in W
  Eigen::Vector3d n_W = Eigen::Vector3d::UnitX();  ///< unit normal, from A towards B
  double depth = 0.0;                              ///< penetration depth, >= 0
  std::intptr_t sphere_a = -1;
  std::intptr_t primitive_b = -1;
};

// --- tree and tree ---------------------------------------------------------------------

/// The smallest pair signed distance below options.upper_bound, with the pair and its
/// witness points. When the trees overlap it stops at the first overlapping pair found:
/// the value is <= 0 and >= the true signed distance.
TreeDistance distance(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
                      const Eigen::Isometry3d& X_WB, const DistanceOptions& options = {});

/// As distance(), but when the trees overlap: minus the deepest pair's penetration depth,
/// with that pair's witness points (the deepest point of each object inside the other).
TreeDistance signed_distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                             const SphereTree& b, const Eigen::Isometry3d& X_WB,
                             const DistanceOptions& options = {});

/// Whether any pair of spheres touches or overlaps.
bool collide(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
             const Eigen::Isometry3d& X_WB, QueryStats* stats = nullptr);

/// Appends up to \p max_contacts overlapping pairs to \p out, in traversal order, and
/// returns how many it appended (none when max_contacts is 0).
std::size_t contacts(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
                     const Eigen::Isometry3d& X_WB, std::size_t max_contacts,
                     std::vector<TreeContact>& out, QueryStats* stats = nullptr);

// --- tree and point --------------------------------------------------------------------

/// The signed distance from point Q to the union of A's balls, min_i |Q - c_i| - r_i: the
/// distance to the union outside it, and inside it minus the depth of Q in the ball it
/// is deepest in (which can be less than the distance to the union's boundary). p_WPa is
/// the point of that ball nearest Q (c_i + r_i n, n the unit vector from c_i to Q, or the
/// x axis of W when Q is the centre); p_WPb is Q; primitive_b is -1.
TreeDistance distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                      const Eigen::Vector3d& p_WQ, const DistanceOptions& options = {});

// --- tree and target -------------------------------------------------------------------
// As the tree-and-tree queries, with B's primitives (primitive_b: the primitive id of the
// target's leaf) in place of B's spheres.

TreeDistance distance(const SphereTree& a, const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
                      const Eigen::Isometry3d& X_WB, const DistanceOptions& options = {});

TreeDistance signed_distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                             const ProximityTarget& b, const Eigen::Isometry3d& X_WB,
                             const DistanceOptions& options = {});

bool collide(const SphereTree& a, const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
             const Eigen::Isometry3d& X_WB, QueryStats* stats = nullptr);

std::size_t contacts(const SphereTree& a, const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
                     const Eigen::Isometry3d& X_WB, std::size_t max_contacts,
                     std::vector<TreeContact>& out, QueryStats* stats = nullptr);

// --- certified distance bounds ---------------------------------------------------------
// Each object is given by two sphere trees: an inner one, whose balls lie inside the
// solid, and an outer one, whose union contains the solid's surface. For two disjoint
// solids the closest points lie on their surfaces, which the outer unions contain, so
// d(outer A, outer B) <= d(A, B); every pair of inner points is a pair of points of the
// solids, so d(A, B) <= d(inner A, inner B). When the solids overlap their surfaces meet
// (the outer unions then overlap, lower = 0) unless one solid lies inside the other
// without surface contact: the bounds then need the outer union to contain the solid's
// interior too (the caller's assumption; a cover certificate certifies only the surface).
// Both bounds are computed in one walk that prunes each kind of pair with the other's
// values (traversal_bounds.h), exact up to double rounding, which they absorb (the
// allowance, 64 ulps of the scene's extent, is subtracted from lower and added to upper).
// A target answers as its ball_proximity does (exact for triangles; within the
// narrowphase tolerance for GJK shapes).

/// Distance bounds: lower <= d(A, B) <= upper, both >= 0. lower = 0: the outer sets
/// overlap (the solids may collide); upper = 0: the inner sets overlap (they collide; the
/// walk stops there, with lower = 0).
struct DistanceBounds {
  double lower = 0.0;
  double upper = std::numeric_limits<double>::infinity();
  QueryStats stats;
  /// The inner pair that gave upper: indices into A's and B's inner sets (a target's
  /// primitive id for B), or -1 when upper is infinity.
  std::intptr_t upper_a = -1, upper_b = -1;
};

/// Three-valued collision against a margin m >= 0 ("colliding" means d(A, B) <= m).
enum class BoundsVerdict {
  free,       ///< lower > m: certainly farther apart than m
  colliding,  ///< upper <= m: certainly within m (m = 0: certainly in collision)
  undecided,  ///< lower <= m < upper
};

/// A verdict with the bounds the walk needed for it: valid bounds, but only as tight as
/// the verdict required (upper may be infinity when the outer sets decided "free").
struct BoundsDecision {
  BoundsVerdict verdict = BoundsVerdict::undecided;
  DistanceBounds bounds;
};

/// The bounds for A (inner_a, outer_a at X_WA) and B (inner_b, outer_b at X_WB).
/// \throws std::invalid_argument for an empty tree or a non-finite pose.
DistanceBounds distance_bounds(const SphereTree& inner_a, const SphereTree& outer_a,
                               const Eigen::Isometry3d& X_WA, const SphereTree& inner_b,
                               const SphereTree& outer_b, const Eigen::Isometry3d& X_WB);

/// The bounds for A and a target B (exact geometry: its own set on both sides).
DistanceBounds distance_bounds(const SphereTree& inner_a, const SphereTree& outer_a,
                               const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
                               const Eigen::Isometry3d& X_WB);

/// The verdict against \p margin (finite, >= 0; std::invalid_argument otherwise); the walk
/// stops as soon as it is known.
BoundsDecision decide_collision(const SphereTree& inner_a, const SphereTree& outer_a,
                                const Eigen::Isometry3d& X_WA, const SphereTree& inner_b,
                                const SphereTree& outer_b, const Eigen::Isometry3d& X_WB,
                                double margin = 0.0);

BoundsDecision decide_collision(const SphereTree& inner_a, const SphereTree& outer_a,
                                const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
                                const Eigen::Isometry3d& X_WB, double margin = 0.0);

}  // namespace medspheres
