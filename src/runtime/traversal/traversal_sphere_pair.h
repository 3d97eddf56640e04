#pragma once
// Node-pair adapter of the traversal (traversal.h) for two sphere trees, A and B, with
// every position in A. Private to the runtime target.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include <Eigen/Core>

#include "traversal_accumulators.h"
#include "traversal_tree_nodes.h"

namespace medspheres::detail {

/// Lower bound on the signed distance of any sphere below a and any sphere below b, with
/// the nodes' ball centres already in A, or infinity when the bounding balls alone show
/// that the bound exceeds prune_at: first the two balls' gap, then, for RSS nodes, the
/// gap of the RSS along the line through the ball centres (see proximity_bounds.h; an
/// RSS's extent about the ball centre adds the rectangle's offset o), and for signed
/// queries minus the two largest radii.
template <class NA, class NB>
double node_pair_bound(const NA& a, const Eigen::Vector3d& ca, const NB& b,
                       const Eigen::Vector3d& cb, const Eigen::Matrix3d& R_AB, double prune_at,
                       bool is_signed) {
  const Eigen::Vector3d w = cb - ca;
  // The balls alone prune most pairs: decide those without a square root.
  const double reach = prune_at + bound_radius(a) + bound_radius(b);
  const double len2 = w.squaredNorm();
  if (reach < 0.0 || len2 > reach * reach) return std::numeric_limits<double>::infinity();
  const double len = std::sqrt(len2);
  double lb = len - bound_radius(a) - bound_radius(b);
  if (lb >= prune_at) return lb;
  constexpr bool rss_a = std::is_same_v<NA, RssNode>;
  constexpr bool rss_b = std::is_same_v<NB, RssNode>;
  if constexpr (rss_a || rss_b) {
    if (len > 0.0) {
      const Eigen::Vector3d d = w / len;
      double gap = len;
      if constexpr (rss_a) {
        const Eigen::Vector3d u = load(a.u), v = load(a.v);
        gap -= d.dot(load(a.o)) + rectangle_extent(a.half[0], a.half[1], u, v, d) + a.r;
      } else {
        gap -= a.r;
      }
      if constexpr (rss_b) {
        const Eigen::Vector3d d_B = R_AB.transpose() * d;
        const Eigen::Vector3d u = load(b.u), v = load(b.v);
        gap += d_B.dot(load(b.o)) - rectangle_extent(b.half[0], b.half[1], u, v, d_B) - b.r;
      } else {
        gap -= b.r;
      }
      lb = std::max(lb, gap);
    }
  }
  if (is_signed) lb = std::max(lb, -(a.max_r + b.max_r));
  return lb;
}

/// Pairs of a node of A and a node of B (node types NA, NB). Of two internal nodes the
/// one with the larger ball is opened. \p is_signed raises the bound to minus the two
/// largest radii below (signed distance queries).
template <class NA, class NB>
class SpherePairNodes {
 public:
  struct Pair {
    std::int32_t i, j;       // node of A, node of B
    Eigen::Vector3d ca, cb;  // their ball centres, in A
  };
  static constexpr int kMaxChildren = 2;

  SpherePairNodes(const SphereTree::Layout& la, const SphereTree::Layout& lb, const Frame& frame,
                  bool is_signed)
      : na_(nodes_of<NA>(la)),
        nb_(nodes_of<NB>(lb)),
        sa_(la.spheres),
        sb_(lb.spheres),
        frame_(frame),
        is_signed_(is_signed) {}

  Pair root() const { return Pair{0, 0, center_a(0), center_b(0)}; }

  double bound(const Pair& p, double prune_at) const {
    return node_pair_bound(na_[p.i], p.ca, nb_[p.j], p.cb, frame_.R, prune_at, is_signed_);
  }

  bool is_leaf(const Pair& p) const {
    return detail::is_leaf(na_[p.i]) && detail::is_leaf(nb_[p.j]);
  }

  bool open_first(const Pair& p) const {
    if (detail::is_leaf(na_[p.i])) return false;
    if (detail::is_leaf(nb_[p.j])) return true;
    return bound_radius(na_[p.i]) >= bound_radius(nb_[p.j]);
  }

  int children(const Pair& p, bool first, Pair* out) const {
    for (int k = 0; k < 2; ++k) {
      if (first) {
        const std::int32_t c = na_[p.i].first + k;
        out[k] = Pair{c, p.j, center_a(c), p.cb};
      } else {
        const std::int32_t c = nb_[p.j].first + k;
        out[k] = Pair{p.i, c, p.ca, center_b(c)};
      }
    }
    return 2;
  }

  // Distance: every sphere pair that could beat the best so far, each rejected first on
  // its squared length; a sphere of B too far from A's leaf ball skips the whole leaf.
  void leaf(const Pair& p, ClosestPair& acc) const {
    const NA& a = na_[p.i];
    const NB& b = nb_[p.j];
    const Eigen::Vector3d ca = load(a.c);
    for (std::int32_t kb = b.first; kb < b.first + b.count; ++kb) {
      const PackedSphere& sb = sb_[kb];
      const Eigen::Vector3d cb = frame_.R * load(sb.c) + frame_.p;
      const double reach_a = acc.value() + sb.r + bound_radius(a);
      if (reach_a <= 0.0 || (cb - ca).squaredNorm() > reach_a * reach_a) continue;
      for (std::int32_t ka = a.first; ka < a.first + a.count; ++ka) {
        const PackedSphere& sa = sa_[ka];
        ++acc.stats.leaf_tests;
        const double reach = acc.value() + (sa.r + sb.r);
        const double len2 = (cb - load(sa.c)).squaredNorm();
        if (reach <= 0.0 || len2 > reach * reach) continue;
        const double sd = std::sqrt(len2) - (sa.r + sb.r);
        if (sd < acc.value()) {
          const BallPair v(load(sa.c), sa.r, cb, sb.r, frame_.x_W);
          acc.offer(v.sd, ka, kb, v.pa, v.pb);
          if (acc.done()) return;
        }
      }
    }
  }

  // Collision: every sphere pair whose centres are at most the sum of the radii apart.
  void leaf(const Pair& p, ContactList& acc) const {
    const NA& a = na_[p.i];
    const NB& b = nb_[p.j];
    for (std::int32_t kb = b.first; kb < b.first + b.count; ++kb) {
      const PackedSphere& sb = sb_[kb];
      const Eigen::Vector3d cb = frame_.R * load(sb.c) + frame_.p;
      for (std::int32_t ka = a.first; ka < a.first + a.count; ++ka) {
        const PackedSphere& sa = sa_[ka];
        ++acc.stats.leaf_tests;
        if ((cb - load(sa.c)).norm() > sa.r + sb.r) continue;
        const BallPair v(load(sa.c), sa.r, cb, sb.r, frame_.x_W);
        acc.offer(v.sd, ka, kb, v.pa, v.pb, v.n);
        if (acc.done()) return;
      }
    }
  }

 private:
  Eigen::Vector3d center_a(std::int32_t i) const { return load(na_[i].c); }
  Eigen::Vector3d center_b(std::int32_t j) const { return frame_.R * load(nb_[j].c) + frame_.p; }

  const NA* na_;
  const NB* nb_;
  const PackedSphere* sa_;
  const PackedSphere* sb_;
  Frame frame_;
  bool is_signed_;
};

}  // namespace medspheres::detail
