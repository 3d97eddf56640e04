#pragma once
/// \file
/// SphereTree: a binary bounding-volume hierarchy over a SphereSet (paper §5.2), and the
/// proximity queries that run on it: distance, collision and signed distance between two
/// trees, between a tree and a point, and between a tree and a ProximityTarget (a
/// TriangleTree here; an fcl::BVHModel, FCL primitive or octree in the FCL adapter).
///
/// Construction. Top-down. At each node a linear least-squares (PCA) fit of the sphere
/// centres below it gives three axes, the major one first. Every node stores the
/// minimum enclosing ball of the spheres below it (computed as described at ball_slack),
/// and its bounding volume is
///   - BoundingVolumeKind::rss: an RSS (see rss.h) whose rectangle lies along the two
///     major axes, with radius and extents fitted as in Larsen et al. so that every
///     sphere below the node lies inside it; the ball serves as a cheaper first test;
///   - BoundingVolumeKind::ball: the ball alone.
/// The spheres are split by a plane normal to the major axis: sorted by the projection
/// of their centres on it (ties by the sphere's index), the first k go to the first
/// child, with k the smallest minimiser of k d_1 + (n - k) d_2, d_i the diagonal of the
/// box (in the node's PCA frame) of child i's spheres, among the k that leave each child
/// more than a tenth of the n spheres; this bounds the depth by log(n) / log(10/9).
/// (The paper cuts at the mean centre. On dilated sets, which mix large and small
/// spheres, the cost-chosen cut made near-contact distance queries visit up to a fifth
/// fewer node pairs; see bench_distance and bench_table2.) A node with at most
/// max_leaf_size spheres is a leaf.
///
/// Traversal. Depth first, the nearer child pair first; of two internal nodes the one
/// with the larger ball is opened. The lower bound of a node pair is the gap between
/// the two balls, raised for RSS nodes to the gap between the two RSS along the line
/// through the ball centres (a few dot products; on baked sphere sets the traversal then
/// visits under ten percent more node pairs than with a tight rectangle distance), and
/// for signed queries to at least minus the sum of the two largest radii below.
///
/// Frames and notation (monogram notation, as in FCL's sphere_box.h): A is the frame of
/// a tree (the frame of the SphereSet it was built from), B the frame of the other
/// object, W the world. X_WA is the pose of A in W, a rigid transform whose rotation
/// must be orthonormal. p_WQ is the position of point Q measured and expressed in W.
/// Every result is expressed in W. Units are those of the sphere set; nothing is
/// rescaled.
///
/// Queries.
///   - distance(): the smallest distance between a sphere of A and a sphere (or
///     primitive) of B, with the two witness points and the indices of the pair. When
///     the objects overlap it stops at the first overlapping pair found and reports that
///     pair's signed distance (<= 0, and >= the true signed distance); ask
///     signed_distance() for the deepest one.
///   - signed_distance(): the same when separated; when the objects overlap, the
///     negative of the maximum penetration depth over all overlapping pairs, with that
///     pair's witness points (the deepest point of each object inside the other).
///   - collide() and contacts(): whether any pair overlaps, or up to max_contacts
///     overlapping pairs as contacts.
/// Pair values. For balls (a, r_a) and (b, r_b) with centres in a common frame, the
/// signed distance is |b - a| - (r_a + r_b). The unit normal n points from a to b; when
/// the centres coincide it is the x axis of W. Witness points: p_Pa = a + r_a n and
/// p_Pb = b - r_b n, so that p_Pb - p_Pa = (signed distance) n. For a primitive of a
/// target see BallProximity.
/// Touching is collision: a pair collides unless |b - a| > r_a + r_b, the comparison of
/// FCL's sphere-sphere test (computed here with both centres in frame A).
/// Contacts: position = the midpoint of the two witness points, normal = n (from A to
/// B), depth = -(signed distance) >= 0. Midpoint is FCL's convention for sphere-box;
/// FCL's own sphere-sphere uses a radius-weighted point instead, which agrees with the
/// midpoint when the radii are equal.
///
/// Tolerances (DistanceOptions::abs_err and rel_err), as FCL's DistanceRequest: a pair of
/// nodes whose lower bound c satisfies both c >= best - abs_err and c (1 + rel_err) >=
/// best is pruned. So, for objects apart, the reported value d and the exact minimum d*
/// satisfy
///   d* <= d <= min(d* + abs_err, (1 + rel_err) d*),
/// which means that the answer is exact when either tolerance is zero (the defaults).
/// A negative signed_distance() is always exact: the rule never prunes a pair that could
/// be deeper. The witness points and indices are those of the reported pair. On top of
/// this, values carry the rounding of double arithmetic: a few units in the last place of
/// the coordinates' magnitude.
///
/// Ties. When several pairs share the minimum, the one found first is reported. The
/// traversal order depends only on the two trees and the poses, so answers are
/// deterministic, but swapping the two objects may report another pair of the tie.
/// Contacts are reported in traversal order, not by depth.
///
/// Degenerate input. A tree may be empty (built from an empty set): distance queries
/// then find nothing (TreeDistance::found() is false), collide() is false and contacts()
/// adds none. Coincident spheres, zero-extent nodes and identical centres are handled.
/// Non-finite poses or points and negative tolerances throw std::invalid_argument.
///
/// Thread safety. A tree is immutable once built; every query is a free function taking
/// const references, and any number of threads may query the same trees at once.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

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
  int max_leaf_size = 8;  ///< most spheres in a leaf, >= 1 (8 is fastest in bench_distance)
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
  /// Relative excess, over the exact minimum, allowed for a node's bounding ball
  /// (bounding_ball()). The ball is computed by a cutting-plane loop: the exact minimum ball
  /// of a finite set P of points on the spheres (Welzl's move-to-front algorithm, as in
  /// Gärtner 1999) is a lower bound R_P on the minimum R*; the farthest point of every
  /// sphere from its centre is added to P until the ball of that centre enclosing every
  /// sphere, R, satisfies R <= (1 + ball_slack) R_P. Hence R* <= R <= (1 + ball_slack) R*,
  /// to rounding. Enclosure is then made exact: R is recomputed from the final centre as
  /// max_i |c_i - C| + r_i, plus 16 eps (|C|_inf + R) for the rounding of that sum.
  static constexpr double ball_slack = 1e-9;

  /// An empty tree.
  SphereTree();

  /// Builds the tree over \p set, which is copied (the tree does not refer to it).
  /// \throws InputError (source "sphere set") if a sphere has a non-finite coordinate or
  ///   a radius that is not finite and > 0 (see validate_sphere_set).
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
  /// For BoundingVolumeKind::rss: the node's RSS, in frame A. Every sphere below the node
  /// lies inside it: the distance from its centre to the rectangle plus its radius is at
  /// most the RSS radius, which is the largest such value computed in double precision
  /// plus 16 eps (|corner|_inf + length[0] + length[1] + radius), the rounding of the
  /// computation.
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

TreeDistance distance(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
                      const Eigen::Isometry3d& X_WB, const DistanceOptions& options = {});

TreeDistance signed_distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                             const SphereTree& b, const Eigen::Isometry3d& X_WB,
                             const DistanceOptions& options = {});

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

}  // namespace medspheres
