#pragma once
/// \file
/// ProximityTarget: the interface through which a SphereTree is queried against an
/// object that is not a sphere set: a TriangleTree, or, in the FCL adapter, an
/// fcl::BVHModel, an FCL primitive or an octree. A target is a hierarchy of nodes in its
/// own frame B whose leaves are primitives; each primitive is a closed convex set (a
/// triangle, a box, a half-space, ...). A primitive may be solid (a box) or a surface (a
/// triangle): its answer to a ball says which.
///
/// Implementations must be safe to call from many threads at once through const
/// member functions, as SphereTree's queries are.

#include <cstdint>
#include <optional>

#include <Eigen/Core>

#include "medspheres/rss.h"

namespace medspheres {

/// The answer of one primitive P to a ball (centre C, radius r), in frame B.
///
/// `distance` is the signed distance sd = s(C) - r, where s is P's signed distance
/// function (distance to P outside P; minus the distance to P's boundary inside a solid
/// P; a surface has no inside). sd > 0: separated by sd; sd <= 0: touching or
/// overlapping, with penetration depth -sd.
///
/// `normal` is the unit vector n_B from the ball towards P: the direction in which P
/// must move to separate. The witness points are then
///   on the ball:  p_BPa = C + r n,
///   on P:         p_BPb = p_BPa + sd n,
/// so that p_BPb - p_BPa = sd n in every case. When C lies on P's surface the direction is
/// the implementation's choice, and it must still be a unit vector.
struct BallProximity {
  double distance = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
};

/// A node of a target's hierarchy, as handed to SphereTree's traversal.
struct TargetNode {
  /// The target's own reference to the node (an index, or a pointer cast to an integer).
  std::intptr_t handle = 0;
  bool is_leaf = false;
  /// Internal nodes only: an RSS, in frame B, that contains every primitive below the
  /// node. Leaves leave it unset (half-spaces and planes are unbounded).
  Rss bounds;
  /// Internal nodes only, optional: when set, every primitive below the node also lies in
  /// the axis-aligned box of B centred at bounds.center() with these half extents (>= 0),
  /// and the traversal bounds the node by that box instead of the RSS. For a cube (an
  /// octree's cell) the box is exact, where the smallest RSS reaches twice as far along
  /// two of its axes.
  std::optional<Eigen::Vector3d> box_half;
  /// Leaves only: the id reported for the primitive in results (a triangle index, an
  /// octree cell id, or -1 for a lone primitive, as FCL does).
  std::intptr_t primitive = -1;
};

class ProximityTarget {
 public:
  /// Most children a node may have (an octree cell has eight).
  static constexpr int kMaxChildren = 8;

  virtual ~ProximityTarget() = default;

  /// The root, or nothing for a target without primitives.
  virtual std::optional<TargetNode> root() const = 0;

  /// Writes the children of an internal node to out[0 .. n) and returns n, at most
  /// kMaxChildren. Children that hold no primitive may be left out. Each out[k] must be
  /// assigned whole (out[k] = node): its previous content is unspecified (the traversal
  /// reuses the array).
  virtual int children(const TargetNode& node, TargetNode* out) const = 0;

  /// The answer of the primitive at \p leaf to the ball of centre p_BC (in frame B)
  /// and \p radius >= 0. The traversal uses it both for single spheres and, as a lower
  /// bound, for balls that enclose many spheres, which is valid because s is
  /// 1-Lipschitz.
  virtual BallProximity ball_proximity(const TargetNode& leaf, const Eigen::Vector3d& p_BC,
                                       double radius) const = 0;

 protected:
  ProximityTarget() = default;
  ProximityTarget(const ProximityTarget&) = default;
  ProximityTarget& operator=(const ProximityTarget&) = default;
};

}  // namespace medspheres
