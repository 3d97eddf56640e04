#pragma once
// Node-pair adapter of the traversal (traversal.h) for a sphere tree A and a
// ProximityTarget B, with every position in A. Private to the runtime target.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Core>

#include "medspheres/proximity_target.h"
#include "traversal_accumulators.h"
#include "traversal_tree_nodes.h"

namespace medspheres::detail {

/// Pairs of a node of A (node type N) and a node of the target. Of two internal nodes
/// the one with the larger bounding ball is opened (a target node's ball: the centre of
/// its RSS, radius half the rectangle's diagonal plus the RSS radius). The bound of a
/// pair with a target leaf is the leaf's answer to A's node ball, valid because a
/// primitive's signed distance function is 1-Lipschitz. \p is_signed raises the bound of
/// internal pairs to minus the largest radius below A's node and the target's RSS radius.
template <class N>
class TargetNodes {
 public:
  /// A target node with its bounds in A.
  struct Item {
    TargetNode node;
    RssView view;
    double bound_r = 0.0;
  };
  struct Pair {
    std::int32_t i;  // node of A
    Item t;
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

  Pair root() const { return Pair{0, make_item(root_)}; }

  double bound(const Pair& p, double prune_at) const {
    const N& a = na_[p.i];
    const Eigen::Vector3d ca = load(a.c);
    if (p.t.node.is_leaf) return leaf_answer(p.t.node, ca, bound_radius(a)).distance;
    double lb = (p.t.view.c - ca).norm() - bound_radius(a) - p.t.bound_r;
    if (lb >= prune_at) return lb;
    lb = std::max(lb, rss_gap(rss_view(a, Eigen::Matrix3d::Identity(), ca), p.t.view,
                              -std::numeric_limits<double>::infinity()));
    if (is_signed_) lb = std::max(lb, -(a.max_r + p.t.view.r));
    return lb;
  }

  bool is_leaf(const Pair& p) const { return detail::is_leaf(na_[p.i]) && p.t.node.is_leaf; }

  bool open_first(const Pair& p) const {
    if (detail::is_leaf(na_[p.i])) return false;
    if (p.t.node.is_leaf) return true;
    return bound_radius(na_[p.i]) >= p.t.bound_r;
  }

  int children(const Pair& p, bool first, Pair* out) const {
    if (first) {
      out[0] = Pair{na_[p.i].first, p.t};
      out[1] = Pair{na_[p.i].first + 1, p.t};
      return 2;
    }
    TargetNode kids[ProximityTarget::kMaxChildren];
    const int count = target_.children(p.t.node, kids);
    for (int k = 0; k < count; ++k) out[k] = Pair{p.i, make_item(kids[k])};
    return count;
  }

  // Distance: every sphere of A's leaf against the target's primitive.
  void leaf(const Pair& p, ClosestPair& acc) const {
    each_answer(p, acc, [&](std::int32_t k, const Eigen::Vector3d& pa, const BallProximity& ans) {
      if (ans.distance < acc.value())
        acc.offer(ans.distance, k, p.t.node.primitive, pa, pa + ans.normal * ans.distance);
    });
  }

  // Collision: every sphere of A's leaf that the primitive's answer puts at <= 0.
  void leaf(const Pair& p, ContactList& acc) const {
    each_answer(p, acc, [&](std::int32_t k, const Eigen::Vector3d& pa, const BallProximity& ans) {
      if (!(ans.distance > 0.0))
        acc.offer(ans.distance, k, p.t.node.primitive, pa, pa + ans.normal * ans.distance,
                  ans.normal);
    });
  }

 private:
  Item make_item(const TargetNode& node) const {
    Item item;
    item.node = node;
    if (!node.is_leaf) {
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
    return item;
  }

  // Calls f(k, p_a, answer) for each sphere k of A's leaf, in order, with the target
  // leaf's answer and the witness point p_a on the sphere, until acc is done.
  template <class Acc, class F>
  void each_answer(const Pair& p, Acc& acc, F&& f) const {
    const N& a = na_[p.i];
    for (std::int32_t k = a.first; k < a.first + a.count; ++k) {
      const PackedSphere& s = sa_[k];
      ++acc.stats.leaf_tests;
      const Eigen::Vector3d c = load(s.c);
      const BallProximity ans = leaf_answer(p.t.node, c, s.r);
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
};

}  // namespace medspheres::detail
