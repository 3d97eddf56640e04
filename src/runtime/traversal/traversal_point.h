#pragma once
// Node-pair adapter of the traversal (traversal.h) for a sphere tree A and a point Q:
// the second side is the point alone, a leaf that is never opened. Positions in A.
// Private to the runtime target.

#include <algorithm>
#include <cstdint>
#include <limits>

#include <Eigen/Core>

#include "traversal_accumulators.h"
#include "traversal_tree_nodes.h"

namespace medspheres::detail {

/// Nodes of A (node type N) paired with the point q. The bound is signed: the gap from
/// q to the node's ball and RSS, raised to minus the largest radius below.
template <class N>
class PointNodes {
 public:
  using Pair = std::int32_t;  // node of A
  static constexpr int kMaxChildren = 2;

  PointNodes(const SphereTree::Layout& l, const Eigen::Vector3d& q, const Eigen::Vector3d& x_W)
      : nodes_(nodes_of<N>(l)), spheres_(l.spheres), q_(q), x_W_(x_W) {}

  Pair root() const { return 0; }

  double bound(Pair i, double prune_at) const {
    const N& n = nodes_[i];
    const Eigen::Vector3d c = load(n.c);
    double lb = std::max((q_ - c).norm() - bound_radius(n), -n.max_r);
    if (lb < prune_at) {
      RssView point;
      point.c = q_;
      lb = std::max(lb, rss_gap(rss_view(n, Eigen::Matrix3d::Identity(), c), point,
                                -std::numeric_limits<double>::infinity()));
    }
    return lb;
  }

  bool is_leaf(Pair i) const { return detail::is_leaf(nodes_[i]); }
  bool open_first(Pair) const { return true; }

  int children(Pair i, bool, Pair* out) const {
    out[0] = nodes_[i].first;
    out[1] = nodes_[i].first + 1;
    return 2;
  }

  void leaf(Pair i, ClosestPair& acc) const {
    const N& n = nodes_[i];
    for (std::int32_t k = n.first; k < n.first + n.count; ++k) {
      const PackedSphere& s = spheres_[k];
      ++acc.stats.leaf_tests;
      const BallPair v(load(s.c), s.r, q_, 0.0, x_W_);
      if (v.sd < acc.value()) acc.offer(v.sd, k, -1, v.pa, q_);
    }
  }

 private:
  const N* nodes_;
  const PackedSphere* spheres_;
  Eigen::Vector3d q_;
  Eigen::Vector3d x_W_;
};

}  // namespace medspheres::detail
