#pragma once
// Node-pair adapter of the traversal (traversal.h) for a sphere tree A and a
// ProximityTarget B, with every position in A. Private to the runtime target.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "medspheres/proximity_target.h"
#include "traversal_accumulators.h"
#include "traversal_tree_nodes.h"

namespace medspheres::detail {

/// A target node's bounds as the walk uses them, and the end of its sibling list in the
/// walk's node stack.
struct TargetPlaced {
  RssView view;  // RSS nodes: the RSS in A
  double bound_r = 0.0;
  Eigen::Vector3d box_c = Eigen::Vector3d::Zero();  // box nodes: the box's centre, in B
  std::int32_t list_end = 0;
};

/// The node stack of one walk against a target.
struct TargetStack {
  std::vector<TargetNode> nodes;
  std::vector<TargetPlaced> placed;
};

/// Lends one of the calling thread's TargetStacks for its lifetime (a new one when all are
/// lent), so that the walks of a thread reuse one stack's memory instead of allocating
/// their own. A walk inside a walk (a target whose answers query) gets a stack of its own.
class TargetStackLease {
 public:
  TargetStackLease() {
    std::vector<std::unique_ptr<TargetStack>>& pool = free_stacks();
    if (pool.empty()) {
      stack_ = std::make_unique<TargetStack>();
    } else {
      stack_ = std::move(pool.back());
      pool.pop_back();
    }
  }
  ~TargetStackLease() {
    try {
      free_stacks().push_back(std::move(stack_));
    } catch (...) {  // no room to keep it: it is freed
    }
  }
  TargetStackLease(const TargetStackLease&) = delete;
  TargetStackLease& operator=(const TargetStackLease&) = delete;

  TargetStack& operator*() const { return *stack_; }

 private:
  static std::vector<std::unique_ptr<TargetStack>>& free_stacks() {
    thread_local std::vector<std::unique_ptr<TargetStack>> pool;
    return pool;
  }
  std::unique_ptr<TargetStack> stack_;
};

/// Pairs of a node of A (node type N) and a node of the target. Of two internal nodes
/// the one with the larger bounding ball is opened (a target node's ball: the centre of
/// its RSS, radius half the rectangle's diagonal plus the RSS radius; for a node with a
/// box, half the box's diagonal). The bound of a pair with a target leaf is the leaf's
/// answer to A's node ball, valid because a primitive's signed distance function is
/// 1-Lipschitz. A target node with a box (TargetNode::box_half) is bounded by the signed
/// distance from A's node ball centre to the box, less the ball's radius: a primitive P in
/// the box has s_P >= s_box, and a sphere (C, r) in the ball (q, R) has s_P(C) - r >=
/// s_box(q) - |C - q| - r >= s_box(q) - R. \p is_signed raises the bound of internal pairs
/// to minus the largest radius below A's node and the target's RSS radius (a box's
/// smallest half extent), the deepest a sphere below can reach into a primitive below.
///
/// Target nodes live in a stack (TargetStack) that the adapter holds for its walk, so that
/// a Pair is two indices, cheap to sort and to keep per opening: a node's children are
/// written right after the end of its own sibling list, where everything above belongs to
/// subtrees the depth-first walk has finished. The stack only grows (to the walk's depth
/// times kMaxChildren); its nodes are assigned, never rebuilt.
template <class N>
class TargetNodes {
 public:
  struct Pair {
    std::int32_t i;     // node of A
    std::int32_t slot;  // the target node's place in the stack
  };
  static constexpr int kMaxChildren = ProximityTarget::kMaxChildren;

  TargetNodes(const SphereTree::Layout& la, const ProximityTarget& target, const TargetNode& root,
              const Frame& frame, bool is_signed)
      : na_(nodes_of<N>(la)),
        sa_(la.spheres),
        target_(target),
        root_(root),
        frame_(frame),
        R_BA_(frame.R.transpose()),
        p_BA_(-(R_BA_ * frame.p)),
        is_signed_(is_signed) {}

  Pair root() const {
    reserve(1);
    nodes_[0] = root_;
    place(0, 1);
    return Pair{0, 0};
  }

  double bound(const Pair& p, double prune_at) const {
    const N& a = na_[p.i];
    const Eigen::Vector3d ca = load(a.c);
    const TargetNode& t = nodes_[p.slot];
    if (t.is_leaf) return leaf_answer(t, ca, bound_radius(a)).distance;
    const TargetPlaced& b = placed_[p.slot];
    if (t.box_half) return box_bound(a, ca, b.box_c, *t.box_half);
    double lb = (b.view.c - ca).norm() - bound_radius(a) - b.bound_r;
    if (lb >= prune_at) return lb;
    lb = std::max(lb, rss_gap(rss_view(a, Eigen::Matrix3d::Identity(), ca), b.view,
                              -std::numeric_limits<double>::infinity()));
    if (is_signed_) lb = std::max(lb, -(a.max_r + b.view.r));
    return lb;
  }

  bool is_leaf(const Pair& p) const { return detail::is_leaf(na_[p.i]) && nodes_[p.slot].is_leaf; }

  bool open_first(const Pair& p) const {
    if (detail::is_leaf(na_[p.i])) return false;
    if (nodes_[p.slot].is_leaf) return true;
    return bound_radius(na_[p.i]) >= placed_[p.slot].bound_r;
  }

  int children(const Pair& p, bool first, Pair* out) const {
    if (first) {
      out[0] = Pair{na_[p.i].first, p.slot};
      out[1] = Pair{na_[p.i].first + 1, p.slot};
      return 2;
    }
    const std::int32_t top = placed_[p.slot].list_end;
    reserve(static_cast<std::size_t>(top) + kMaxChildren);
    const int count = target_.children(nodes_[p.slot], nodes_.data() + top);
    for (int k = 0; k < count; ++k) {
      place(top + k, top + count);
      out[k] = Pair{p.i, top + k};
    }
    return count;
  }

  // Distance: every sphere of A's leaf against the target's primitive.
  void leaf(const Pair& p, ClosestPair& acc) const {
    const std::intptr_t id = nodes_[p.slot].primitive;
    each_answer(p, acc, [&](std::int32_t k, const Eigen::Vector3d& pa, const BallProximity& ans) {
      if (ans.distance < acc.value())
        acc.offer(ans.distance, k, id, pa, pa + ans.normal * ans.distance);
    });
  }

  // Collision: every sphere of A's leaf that the primitive's answer puts at <= 0.
  void leaf(const Pair& p, ContactList& acc) const {
    const std::intptr_t id = nodes_[p.slot].primitive;
    each_answer(p, acc, [&](std::int32_t k, const Eigen::Vector3d& pa, const BallProximity& ans) {
      if (!(ans.distance > 0.0))
        acc.offer(ans.distance, k, id, pa, pa + ans.normal * ans.distance, ans.normal);
    });
  }

 private:
  void reserve(std::size_t size) const {
    if (nodes_.size() >= size) return;
    const std::size_t grown = std::max(size, 2 * nodes_.size());
    nodes_.resize(grown);
    placed_.resize(grown);
  }

  // Computes the bounds of stacked node `slot`, whose sibling list ends at list_end.
  void place(std::int32_t slot, std::int32_t list_end) const {
    const TargetNode& node = nodes_[slot];
    TargetPlaced& item = placed_[slot];
    item.list_end = list_end;
    if (node.is_leaf) return;
    if (node.box_half) {
      item.box_c = node.bounds.center();
      item.bound_r = node.box_half->norm();
      return;
    }
    const Rss& b = node.bounds;
    item.view.c = frame_.R * b.center() + frame_.p;
    item.view.u = frame_.R * b.axis.col(0);
    item.view.v = frame_.R * b.axis.col(1);
    item.view.h0 = 0.5 * b.length[0];
    item.view.h1 = 0.5 * b.length[1];
    item.view.r = b.radius;
    item.bound_r =
        std::sqrt(item.view.h0 * item.view.h0 + item.view.h1 * item.view.h1) + item.view.r;
  }

  // A's node a (ball centre ca, in A) against a box of B (centre c, half extents h).
  double box_bound(const N& a, const Eigen::Vector3d& ca, const Eigen::Vector3d& c,
                   const Eigen::Vector3d& h) const {
    const Eigen::Vector3d d = (R_BA_ * ca + p_BA_ - c).cwiseAbs() - h;
    const double s_box = d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
    const double lb = s_box - bound_radius(a);
    return is_signed_ ? std::max(lb, -(a.max_r + h.minCoeff())) : lb;
  }

  // Calls f(k, p_a, answer) for each sphere k of A's leaf, in order, with the target
  // leaf's answer and the witness point p_a on the sphere, until acc is done.
  template <class Acc, class F>
  void each_answer(const Pair& p, Acc& acc, F&& f) const {
    const N& a = na_[p.i];
    const TargetNode& leaf = nodes_[p.slot];
    for (std::int32_t k = a.first; k < a.first + a.count; ++k) {
      const PackedSphere& s = sa_[k];
      ++acc.stats.leaf_tests;
      const Eigen::Vector3d c = load(s.c);
      const BallProximity ans = leaf_answer(leaf, c, s.r);
      f(k, Eigen::Vector3d(c + ans.normal * s.r), ans);
      if (acc.done()) return;
    }
  }

  // A ball of A (centre in A) against a target leaf, answered in A.
  BallProximity leaf_answer(const TargetNode& leaf, const Eigen::Vector3d& c_A, double r) const {
    BallProximity ans = target_.ball_proximity(leaf, R_BA_ * c_A + p_BA_, r);
    ans.normal = frame_.R * ans.normal;
    return ans;
  }

  const N* na_;
  const PackedSphere* sa_;
  const ProximityTarget& target_;
  TargetNode root_;
  Frame frame_;
  Eigen::Matrix3d R_BA_;
  Eigen::Vector3d p_BA_;
  bool is_signed_;
  // The walk's node stack (written by const members: the adapter belongs to one walk).
  TargetStackLease stack_;
  std::vector<TargetNode>& nodes_ = (*stack_).nodes;
  std::vector<TargetPlaced>& placed_ = (*stack_).placed;
};

}  // namespace medspheres::detail
