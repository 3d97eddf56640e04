#pragma once
// Small ProximityTarget implementations for the traversal tests, one for each shape of
// hierarchy the interface allows beside TriangleTree's binary RSS tree: a lone solid box
// (the root is a leaf, primitive -1, as FCL reports a lone shape), a half-space (an
// unbounded leaf), and a grid of solid cubes in an octree (up to eight children per
// node, empty cells left out). Header-only.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "medspheres/proximity_target.h"

namespace medspheres::test {

/// The answer of the solid axis-aligned box [lo, hi] to the ball (c, r), in the box's
/// frame: the signed distance of c to the box minus r, and the unit normal from the ball
/// towards the box (outside: from c to the nearest point; inside: out through the
/// nearest face, ties to the lowest axis, then to the lower face).
inline BallProximity ball_box_proximity(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                        const Eigen::Vector3d& c, double r) {
  BallProximity out;
  const Eigen::Vector3d q = c.cwiseMax(lo).cwiseMin(hi);
  const Eigen::Vector3d w = q - c;
  const double len = w.norm();
  if (len > 0.0) {
    out.distance = len - r;
    out.normal = w / len;
    return out;
  }
  double depth = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    for (int side = 0; side < 2; ++side) {
      const double d = side == 0 ? c[k] - lo[k] : hi[k] - c[k];
      if (d < depth) {
        depth = d;
        out.normal = Eigen::Vector3d::Zero();
        out.normal[k] = side == 0 ? 1.0 : -1.0;  // the box moves this way to separate
      }
    }
  }
  out.distance = -depth - r;
  return out;
}

/// An Rss, in the box's frame, that contains the axis-aligned box [lo, hi]: its mid
/// rectangle normal to the shortest side, swept by half that side.
inline Rss box_bounds(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d side = hi - lo;
  int k0 = 0, k1 = 1, k2 = 2;  // sides sorted longest first
  if (side[k0] < side[k1]) std::swap(k0, k1);
  if (side[k1] < side[k2]) std::swap(k1, k2);
  if (side[k0] < side[k1]) std::swap(k0, k1);
  Rss b;
  b.axis.col(0) = Eigen::Vector3d::Unit(k0);
  b.axis.col(1) = Eigen::Vector3d::Unit(k1);
  b.axis.col(2) = b.axis.col(0).cross(b.axis.col(1));
  b.corner = lo + 0.5 * side[k2] * Eigen::Vector3d::Unit(k2);
  b.length = Eigen::Vector2d(side[k0], side[k1]);
  b.radius = 0.5 * side[k2];
  return b;
}

/// A target of one primitive: the root is a leaf.
class LonePrimitiveTarget : public ProximityTarget {
 public:
  std::optional<TargetNode> root() const override {
    TargetNode n;
    n.is_leaf = true;
    return n;
  }
  int children(const TargetNode&, TargetNode*) const override { return 0; }
};

/// One solid box [lo, hi].
class BoxTarget final : public LonePrimitiveTarget {
 public:
  BoxTarget(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) : lo_(lo), hi_(hi) {}
  BallProximity ball_proximity(const TargetNode&, const Eigen::Vector3d& c,
                               double r) const override {
    return ball_box_proximity(lo_, hi_, c, r);
  }

 private:
  Eigen::Vector3d lo_, hi_;
};

/// The solid half-space {x : n . x <= offset}, n a unit vector.
class HalfspaceTarget final : public LonePrimitiveTarget {
 public:
  HalfspaceTarget(const Eigen::Vector3d& n, double offset) : n_(n.normalized()), offset_(offset) {}
  BallProximity ball_proximity(const TargetNode&, const Eigen::Vector3d& c,
                               double r) const override {
    BallProximity out;
    out.distance = n_.dot(c) - offset_ - r;
    out.normal = -n_;
    return out;
  }

 private:
  Eigen::Vector3d n_;
  double offset_;
};

/// Occupied cells of a 2^depth grid over the cube [-half, half]^3, in an octree: a node
/// is a cell (level, i, j, k) whose children are its occupied sub-cells, in z-order; a
/// leaf is an occupied cell of the last level, a solid cube whose primitive id is its
/// linear index i + n (j + n k), n = 2^depth. With \p boxes, internal nodes also carry
/// their cube as TargetNode::box_half.
class CubeGridTarget : public ProximityTarget {
 public:
  CubeGridTarget(int depth, double half, std::vector<bool> occupied, bool boxes = false)
      : depth_(depth), half_(half), occupied_(std::move(occupied)), boxes_(boxes) {}

  std::optional<TargetNode> root() const override {
    if (!any_below(0, 0, 0, 0)) return std::nullopt;
    return node(0, 0, 0, 0);
  }

  int children(const TargetNode& parent, TargetNode* out) const override {
    const auto [level, i, j, k] = decode(parent.handle);
    int n = 0;
    for (int c = 0; c < 8; ++c) {
      const int ci = 2 * i + (c & 1), cj = 2 * j + ((c >> 1) & 1), ck = 2 * k + ((c >> 2) & 1);
      if (any_below(level + 1, ci, cj, ck)) out[n++] = node(level + 1, ci, cj, ck);
    }
    return n;
  }

  BallProximity ball_proximity(const TargetNode& leaf, const Eigen::Vector3d& c,
                               double r) const override {
    const auto [level, i, j, k] = decode(leaf.handle);
    Eigen::Vector3d lo, hi;
    cell_box(level, i, j, k, lo, hi);
    return ball_box_proximity(lo, hi, c, r);
  }

 private:
  struct Cell {
    int level, i, j, k;
  };
  static std::intptr_t encode(int level, int i, int j, int k) {
    return ((static_cast<std::intptr_t>(level) * 64 + i) * 64 + j) * 64 + k;
  }
  static Cell decode(std::intptr_t h) {
    return Cell{static_cast<int>(h / (64 * 64 * 64)), static_cast<int>((h / (64 * 64)) % 64),
                static_cast<int>((h / 64) % 64), static_cast<int>(h % 64)};
  }
  void cell_box(int level, int i, int j, int k, Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
    const double s = 2.0 * half_ / (1 << level);
    lo = Eigen::Vector3d(-half_ + s * i, -half_ + s * j, -half_ + s * k);
    hi = lo + Eigen::Vector3d::Constant(s);
  }
  bool any_below(int level, int i, int j, int k) const {
    const int span = 1 << (depth_ - level), n = 1 << depth_;
    for (int z = k * span; z < (k + 1) * span; ++z)
      for (int y = j * span; y < (j + 1) * span; ++y)
        for (int x = i * span; x < (i + 1) * span; ++x)
          if (occupied_[static_cast<std::size_t>(x + n * (y + n * z))]) return true;
    return false;
  }
  TargetNode node(int level, int i, int j, int k) const {
    TargetNode t;
    t.handle = encode(level, i, j, k);
    t.is_leaf = level == depth_;
    Eigen::Vector3d lo, hi;
    cell_box(level, i, j, k, lo, hi);
    if (t.is_leaf) {
      const int n = 1 << depth_;
      t.primitive = i + n * (j + n * k);
    } else {
      t.bounds = box_bounds(lo, hi);
      if (boxes_) t.box_half = 0.5 * (hi - lo);
    }
    return t;
  }

  int depth_;
  double half_;
  std::vector<bool> occupied_;
  bool boxes_;
};

}  // namespace medspheres::test
