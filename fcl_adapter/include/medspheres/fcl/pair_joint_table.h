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
/// d(c) + D <= margin. The links' sphere trees try that first (decide() of
/// bounded_geometry.h at margin + D and at margin - D).
///
/// Levers: D holds for B's farthest point, but a point b of B moves by at most
/// w(b) = sum_j h_j (rho(b) + R_j - R_k), rho(b) = |b - o_k| (o_k the lowest joint's origin,
/// fixed in B, so rho is too; |b - o_j| <= rho(b) + R_j - R_k at every pose by the triangle
/// inequality along the origins). B's triangles are held in shells by their vertices'
/// largest rho (w is convex in b, so its largest value on a triangle is at a vertex): a
/// shell of largest rho_s moves by at most W_s = H rho_s + sum_j h_j (R_j - R_k) <= D, H =
/// sum_j h_j (with the same rounding allowance). Where the trees leave the cell open, each
/// shell's distance d_s(c) to A is FCL's mesh distance (exact when it is <= margin + W_s,
/// the search pruned there): the cell is free when every d_s(c) > margin + W_s, colliding
/// when some d_s(c) + W_s <= margin (that shell's closest point moves by at most W_s). Near
/// a joint, where two links a joint or two apart come close, rho is a fraction of R_k, so
/// cells there are decided at a fraction of the width that D allows.
///
/// A cell neither free nor colliding is split in two along the joint with the largest
/// R_j h_j, breadth first, until the table holds max_cells leaves (the largest cells first:
/// configurations drawn uniformly fall in a cell as often as its volume). Distances are
/// those of the meshes as surfaces, with bounded_geometry.h's assumption (no solid wholly inside
/// another without surface contact): the same contract as the mesh fallback.
///
/// Eligible pairs: both links have a mesh; on the path between them in the kinematic tree,
/// one or two actuated revolute joints with limits (not continuous, not mimic), all on the
/// same side of the links' common ancestor, and otherwise fixed joints only. Outside the
/// limits, and for other pairs, the table answers undecided.
/// Threads: immutable after build(); verdict() may run from many threads at once, and
/// build() for several pairs at once, with one store or without.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/robot_model.h"

namespace medspheres::fcl {

class PairTableStore;

class PairJointTable {
 public:
  /// The table of the pair (a, b) of links (indices in tree.link_names(), with their
  /// geometries ga, gb, posed as RobotBounds poses them) at \p margin (finite, >= 0), at
  /// most \p max_cells leaves (>= 1); null when the pair is not eligible. \p model gives the
  /// joints' types and limits (the tree's model).
  /// With a \p store (pair_table_store.h), the table is read from it when it holds this
  /// pair's table, else baked and written to it (InputError naming the folder and the pair
  /// before the bake when the folder cannot be written).
  static std::unique_ptr<const PairJointTable> build(const RobotModel& model,
                                                     const KinematicTree& tree, std::size_t a,
                                                     const BoundedGeometry& ga, std::size_t b,
                                                     const BoundedGeometry& gb, double margin,
                                                     std::size_t max_cells,
                                                     const PairTableStore* store = nullptr);

  /// The pair's verdict at positions \p q (KinematicTree::joint_names() order).
  BoundsVerdict verdict(const double* q) const;
  /// Leaves, and how many of them are free and colliding.
  std::size_t cells() const noexcept { return (nodes_.size() + 1) / 2; }
  std::size_t free_cells() const noexcept;
  std::size_t colliding_cells() const noexcept;
  /// Whether the table was read from a store rather than baked.
  bool stored() const noexcept { return stored_; }

 private:
  friend class PairTableStore;
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
  BoundsVerdict cell(const KinematicTree& tree, const Pair& p, double margin,
                     const std::vector<double>& R, const std::vector<double>& lo,
                     const std::vector<double>& hi) const;
  void bake(const KinematicTree& tree, const Pair& p, double margin, const std::vector<double>& R,
            std::size_t max_cells);
  std::string store_key(const KinematicTree& tree, const Pair& p, double margin,
                        std::size_t max_cells) const;

  struct Shell {
    std::shared_ptr<const MeshModel> mesh;  ///< triangles of B, in B's frame
    double rho = 0.0;                       ///< their vertices' largest |v - o_k|
  };
  BoundsVerdict shells_verdict(const std::vector<Eigen::Isometry3d>& X, const Pair& p,
                               double margin, double H, double E, double pad) const;
  void make_shells(const MeshModel& far, const Eigen::Vector3d& o_k, double R_k);

  std::vector<long> source_;   ///< per joint of the table: its index in q
  std::size_t far_ = 0;        ///< B, the link below the joints
  std::vector<Shell> shells_;  ///< during the bake
  std::vector<double> lower_, upper_;
  std::vector<Node> nodes_;
  bool stored_ = false;
};

}  // namespace medspheres::fcl
