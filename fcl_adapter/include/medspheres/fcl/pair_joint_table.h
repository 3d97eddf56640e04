#pragma once
/// \file
/// PairJointTable: certified verdicts of one self-collision pair over a box of joint space,
/// baked once, for the pairs whose relative pose hangs on one or two revolute joints (two
/// links two joints apart: a hip and the pelvis, a wrist's two links). A k-d tree over the
/// joints' limits; each leaf cell holds free, colliding or undecided for every
/// configuration inside it.
///
/// Proof of a cell: let c be its centre and h_j its half-widths. Moving joint j by at most
/// h_j moves every point of the far link (B, the one below the joints) relative to the
/// other (A) by at most R_j h_j, where R_j bounds the distance of B's points from a point
/// of joint j's axis (the joint origin): R_k = max |v - o_k| over B's mesh vertices v (a
/// solid's farthest point from a point is a vertex of its hull), R_j = R_{j+1} +
/// |o_{j+1} - o_j| (both origins fixed in the link between the joints), and a rotation by
/// d moves a point at distance r from the axis by 2 r sin(d / 2) <= r d. So the distance d
/// of the two meshes anywhere in the cell lies within D = sum_j R_j h_j (plus a rounding
/// allowance of 1e-9 (1 + R_1)) of d(c): free when d(c) > margin + D, colliding when
/// d(c) + D <= margin. d(c) is bounded first by the links' sphere trees (decide() of
/// bounded_geometry.h at margin + D and at margin - D), then given by FCL's mesh distance
/// (exact when it is <= margin + D, the search pruned there, as settle()). A cell neither
/// free nor colliding whose centre is free (a finer cell near the centre may be proven
/// free; the colliding side is left to the other levels) is split in two along the joint
/// with the largest R_j h_j, breadth first, until the table holds max_cells leaves. Distances are
/// those of the meshes as surfaces, with bounded_geometry.h's assumption (no solid wholly inside
/// another without surface contact): the same contract as the mesh fallback.
///
/// Eligible pairs: both links have a mesh; on the path between them in the kinematic tree,
/// one or two actuated revolute joints with limits (not continuous, not mimic), all on the
/// same side of the links' common ancestor, and otherwise fixed joints only. Outside the
/// limits, and for other pairs, the table answers undecided.
/// Threads: immutable after build(); verdict() may run from many threads at once.

#include <cstddef>
#include <memory>
#include <vector>

#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/robot_model.h"

namespace medspheres::fcl {

class PairJointTable {
 public:
  /// The table of the pair (a, b) of links (indices in tree.link_names(), with their
  /// geometries ga, gb, posed as RobotBounds poses them) at \p margin (finite, >= 0), at
  /// most \p max_cells leaves (>= 1); null when the pair is not eligible. \p model gives the
  /// joints' types and limits (the tree's model).
  static std::unique_ptr<const PairJointTable> build(const RobotModel& model,
                                                     const KinematicTree& tree, std::size_t a,
                                                     const BoundedGeometry& ga, std::size_t b,
                                                     const BoundedGeometry& gb, double margin,
                                                     std::size_t max_cells);

  /// The pair's verdict at positions \p q (KinematicTree::joint_names() order).
  BoundsVerdict verdict(const double* q) const;
  /// Leaves, and how many of them are free and colliding.
  std::size_t cells() const noexcept { return (nodes_.size() + 1) / 2; }
  std::size_t free_cells() const noexcept;
  std::size_t colliding_cells() const noexcept;

 private:
  struct Node {
    int child = -1;  ///< the two children are nodes child, child + 1; -1: a leaf
    int dim = 0;     ///< the joint split at mid
    double mid = 0.0;
    BoundsVerdict verdict = BoundsVerdict::undecided;  ///< of a leaf
  };
  struct Pair {
    std::size_t a;
    const BoundedGeometry* ga;
    std::size_t b;
    const BoundedGeometry* gb;
  };
  BoundsVerdict cell(bool& split, const KinematicTree& tree, const Pair& p, double margin,
                     const std::vector<double>& R, const std::vector<double>& lo,
                     const std::vector<double>& hi) const;
  void bake(const KinematicTree& tree, const Pair& p, double margin, const std::vector<double>& R,
            std::size_t max_cells);

  std::vector<long> source_;  ///< per joint of the table: its index in q
  std::vector<double> lower_, upper_;
  std::vector<Node> nodes_;
};

}  // namespace medspheres::fcl
