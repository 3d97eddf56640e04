// Which balls may come within a margin of an FCL object (balls_near.h).
//
// First each ball against the object's bounding ball (its local AABB's, about the object's
// transform), then against what the object is known to lie in, in its own frame B: the
// root node's RSS of its target view (fcl_dispatch.h) when that root is an internal node
// (a mesh's root BV, an octree's smallest cell holding all its occupied cells), else its
// local AABB (set by computeLocalAABB, which fcl::CollisionObject's constructor calls; a
// box's is the box). Either contains the geometry at the object's current transform,
// whether or not its world AABB is up to date. An octree's local AABB is its whole root
// cube (about 2 km across for 3 cm cells), no bound at all, and even its smallest cell
// holding every occupied cell is that cube when cells lie on both sides of a coordinate
// plane; so a target with an internal root is searched below it, once for all the balls:
// a node keeps the balls within reach of its RSS (which contains its primitives), and a
// leaf marks near the balls within reach of its primitive (the primitive's answer to the
// ball's centre is its distance). A ball no node keeps is beyond. The search is cut at
// kNodeBudget nodes; every ball still open is then near.
//
// Rounding: a ball is beyond only when its gap exceeds the margin by 1e-12 of the
// magnitudes involved, far above the few ulps of error of these distances.

#include "medspheres/fcl/balls_near.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>

#include <stdexcept>
#include <utility>

#include "fcl_bv_rss.h"
#include "fcl_dispatch.h"
#include "gap_allowance.h"

namespace medspheres::fcl {
namespace {

using detail::rectangle_distance2;

constexpr int kNodeBudget = 4096;

// Whether the RSS b comes within reach (>= 0) of p: its rectangle within reach + radius.
bool rss_within(const Rss& b, const Eigen::Vector3d& p, double reach) {
  const double r = reach + b.radius;
  return rectangle_distance2(b, p) <= r * r;
}

// Whether every point of the RSS b lies within reach of p: its rectangle's farthest
// corner within reach - radius.
bool rss_inside(const Rss& b, const Eigen::Vector3d& p, double reach) {
  const double r = reach - b.radius;
  if (r < 0.0) return false;
  const Eigen::Vector3d u = b.axis.col(0) * b.length[0], v = b.axis.col(1) * b.length[1];
  const Eigen::Vector3d q = b.corner - p;
  const double far2 = std::max(std::max(q.squaredNorm(), (q + u).squaredNorm()),
                               std::max((q + v).squaredNorm(), (q + u + v).squaredNorm()));
  return far2 <= r * r;
}

// The search below a target's root, for the balls' centres p (frame B) and reaches.
class NearSearch {
 public:
  NearSearch(const ProximityTarget& t, const std::vector<Eigen::Vector3d>& p,
             const std::vector<double>& reach, std::vector<char>& near)
      : t_(t), p_(p), reach_(reach), near_(near) {}

  // Visits node n with the balls open_[begin, end).
  void visit(const TargetNode& n, std::size_t begin, std::size_t end) {
    if (--budget_ < 0) {
      for (std::size_t k = begin; k < end; ++k) near_[open_[k]] = 1;
      return;
    }
    if (n.is_leaf) {
      for (std::size_t k = begin; k < end; ++k) {
        const int i = open_[k];
        if (!near_[i] && t_.ball_proximity(n, p_[i], 0.0).distance <= reach_[i]) near_[i] = 1;
      }
      return;
    }
    // A node lying entirely within reach of a ball holds a primitive within reach of it,
    // or none: the ball may be called near either way (near is always a safe answer),
    // with no descent.
    const std::size_t kept = open_.size();
    for (std::size_t k = begin; k < end; ++k) {
      const int i = open_[k];
      if (near_[i] || !rss_within(n.bounds, p_[i], reach_[i])) continue;
      if (rss_inside(n.bounds, p_[i], reach_[i]))
        near_[i] = 1;
      else
        open_.push_back(i);
    }
    const std::size_t last = open_.size();
    if (last > kept) {
      TargetNode kids[ProximityTarget::kMaxChildren];
      const int count = t_.children(n, kids);
      for (int c = 0; c < count; ++c) visit(kids[c], kept, last);
    }
    open_.resize(kept);
  }

  std::vector<int> open_;

 private:
  const ProximityTarget& t_;
  const std::vector<Eigen::Vector3d>& p_;
  const std::vector<double>& reach_;
  std::vector<char>& near_;
  int budget_ = kNodeBudget;
};

// The gap between the balls, computed in doubles, and the magnitudes it is computed from.
std::pair<double, double> gap_and_scale(const Sphere& a, const Sphere& b) {
  const double gap = (a.center - b.center).norm() - a.radius - b.radius;
  return {gap, a.center.norm() + b.center.norm() + a.radius + b.radius};
}

}  // namespace

bool balls_apart(const Sphere& a, const Sphere& b, double margin) {
  const auto [gap, scale] = gap_and_scale(a, b);
  return detail::gap_beyond(gap, scale, margin);
}

bool balls_within(const Sphere& a, const Sphere& b, double margin) {
  const auto [gap, scale] = gap_and_scale(a, b);
  return gap + detail::gap_allowance(scale, margin) <= margin;
}

std::vector<char> balls_near(const ::fcl::CollisionObjectd& object,
                             const std::vector<Sphere>& balls, double margin) {
  if (object.collisionGeometry() == nullptr)
    throw std::invalid_argument("balls_near: the object has no geometry");
  const ::fcl::CollisionGeometryd& g = *object.collisionGeometry();
  const ::fcl::Transform3d X_BW = object.getTransform().inverse();
  std::vector<char> near(balls.size(), 1);
  // First the object's bounding ball in W, which needs no target view.
  const Sphere bound_W{object.getTransform() * g.aabb_center, g.aabb_radius};
  bool open = false;
  for (std::size_t i = 0; i < balls.size(); ++i) {
    if (balls_apart(balls[i], bound_W, margin))
      near[i] = 0;
    else
      open = true;
  }
  if (!open) return near;
  detail::with_target_view(g, [&](const ProximityTarget& t) {
    const std::optional<TargetNode> root = t.root();
    const bool rss = root && !root->is_leaf;
    const Eigen::Vector3d lo = g.aabb_local.min_, hi = g.aabb_local.max_;
    const double scale =
        object.getTransform().translation().norm() +
        (rss ? root->bounds.corner.norm() + root->bounds.length.sum() + root->bounds.radius
             : lo.cwiseAbs().maxCoeff() + hi.cwiseAbs().maxCoeff());
    std::vector<Eigen::Vector3d> p(balls.size());
    std::vector<double> reach(balls.size());
    NearSearch search(t, p, reach, near);
    for (std::size_t i = 0; i < balls.size(); ++i) {
      if (!near[i]) continue;  // beyond the bounding ball
      p[i] = X_BW * balls[i].center;
      reach[i] = balls[i].radius + margin +
                 detail::gap_allowance(balls[i].center.norm() + balls[i].radius + scale, margin);
      const double d2 = rss ? rectangle_distance2(root->bounds, p[i])
                            : (lo - p[i]).cwiseMax(p[i] - hi).cwiseMax(0.0).squaredNorm();
      const double r = reach[i] + (rss ? root->bounds.radius : 0.0);
      if (!std::isfinite(d2) || !std::isfinite(r)) continue;  // near
      near[i] = 0;
      if (d2 > r * r) continue;
      if (rss)
        search.open_.push_back(static_cast<int>(i));
      else
        near[i] = 1;
    }
    if (!search.open_.empty()) search.visit(*root, 0, search.open_.size());
  });
  return near;
}

}  // namespace medspheres::fcl
