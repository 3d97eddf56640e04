#pragma once
// A SphereTree's nodes and spheres as the traversal adapters read them: one interface
// over the two node kinds, the pose of the other object in the tree's frame A, and the
// value of a pair of balls. Private to the runtime target.

#include <cmath>
#include <type_traits>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "proximity_bounds.h"
#include "sphere_tree_layout.h"

namespace medspheres::detail {

inline Eigen::Vector3d load(const double* v) {
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

/// The pose of frame B in frame A, and W's x axis expressed in A (the normal used when
/// two centres coincide).
struct Frame {
  Eigen::Matrix3d R;    // R_AB
  Eigen::Vector3d p;    // p_AoBo_A
  Eigen::Vector3d x_W;  // x axis of W, expressed in A

  Frame(const Eigen::Isometry3d& X_WA, const Eigen::Isometry3d& X_WB) {
    const Eigen::Matrix3d R_AW = X_WA.linear().transpose();
    R = R_AW * X_WB.linear();
    p = R_AW * (X_WB.translation() - X_WA.translation());
    x_W = R_AW.col(0);
  }
};

inline bool is_leaf(const RssNode& n) {
  return n.count > 0;
}
inline bool is_leaf(const BallNode& n) {
  return n.count > 0;
}
/// Radius of the node's bounding ball (centred at the node's c).
inline double bound_radius(const RssNode& n) {
  return n.ball_r;
}
inline double bound_radius(const BallNode& n) {
  return n.r;
}

/// The node's RSS in centre form, in A: \p c is the node's reference centre (its ball's)
/// already moved to A, R rotates the node's frame into A. A ball node is an RSS with an
/// empty rectangle.
inline RssView rss_view(const RssNode& n, const Eigen::Matrix3d& R, const Eigen::Vector3d& c) {
  RssView v;
  v.c = c + R * load(n.o);
  v.u = R * load(n.u);
  v.v = R * load(n.v);
  v.h0 = n.half[0];
  v.h1 = n.half[1];
  v.r = n.r;
  return v;
}

inline RssView rss_view(const BallNode& n, const Eigen::Matrix3d&, const Eigen::Vector3d& c) {
  RssView v;
  v.c = c;
  v.r = n.r;
  return v;
}

template <class N>
const N* nodes_of(const SphereTree::Layout& l) {
  if constexpr (std::is_same_v<N, RssNode>)
    return l.rss_nodes;
  else
    return l.ball_nodes;
}

/// Extent of a tree's geometry about the origin of its frame: the root's bounding ball.
template <class N>
double tree_extent(const SphereTree::Layout& l) {
  const N& root = nodes_of<N>(l)[0];
  return load(root.c).norm() + bound_radius(root);
}

/// Calls f(N{}) with the node type of the tree (RssNode or BallNode).
template <class F>
decltype(auto) with_node_type(const SphereTree::Layout& l, F&& f) {
  if (l.kind == BoundingVolumeKind::rss) return f(RssNode{});
  return f(BallNode{});
}

/// Two balls (ca, ra) and (cb, rb) in one frame: the signed distance |cb - ca| - (ra + rb),
/// the unit normal n from a to b (\p fallback_normal when the centres coincide) and the
/// witness points pa = ca + ra n, pb = cb - rb n.
struct BallPair {
  double sd;
  Eigen::Vector3d n;
  Eigen::Vector3d pa;
  Eigen::Vector3d pb;

  BallPair(const Eigen::Vector3d& ca, double ra, const Eigen::Vector3d& cb, double rb,
           const Eigen::Vector3d& fallback_normal) {
    const Eigen::Vector3d diff = cb - ca;
    const double len = diff.norm();
    sd = len - (ra + rb);
    n = len > 0.0 ? Eigen::Vector3d(diff / len) : fallback_normal;
    pa = ca + n * ra;
    pb = cb - n * rb;
  }
};

}  // namespace medspheres::detail
