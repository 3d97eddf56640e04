// The entry points of SphereTree's queries: tree and tree, tree and point, tree and
// ProximityTarget. Each checks its arguments, picks the node-pair adapter for the two
// node types (traversal_sphere_pair.h, traversal_point.h, traversal_target.h) and an
// accumulator (traversal_accumulators.h), and runs the one traversal (traversal.h).
// Everything is computed in the first tree's frame A and converted to W at the end.
//
// The walk is depth first, the nearer child pair first; of two internal nodes the one
// with the larger ball is opened. A node pair's lower bound is the gap between the two
// balls, raised for RSS nodes to the gap between the two RSS along the line through the
// ball centres (proximity_bounds.h), and for signed queries to at least minus the sum of
// the two largest radii below: no two spheres below can overlap deeper.
//
// Tolerances. A pair whose lower bound c satisfies c >= best - abs_err and
// c (1 + rel_err) >= best is pruned (Threshold). A pruned pair holds no pair closer than
// c, so when the objects are apart the reported d and the minimum d* satisfy
// d* <= d <= min(d* + abs_err, (1 + rel_err) d*); with either tolerance zero the rule
// is c >= best and the answer is exact. When best < 0, best / (1 + rel_err) >= best, so
// the rule prunes no pair with c < best, none that could hold a deeper pair: a negative
// signed distance is always exact.
//
// Contacts are placed at the midpoint of the two witness points, FCL's convention for
// sphere-box; FCL's own sphere-sphere uses a radius-weighted point instead, which agrees
// with the midpoint when the radii are equal.

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "medspheres/sphere_tree.h"
#include "sphere_tree_layout.h"
#include "traversal.h"
#include "traversal_accumulators.h"
#include "traversal_bounds.h"
#include "traversal_point.h"
#include "traversal_sphere_pair.h"
#include "traversal_target.h"
#include "traversal_tree_nodes.h"

namespace medspheres {
namespace {

using detail::ClosestPair;
using detail::ContactList;
using detail::Frame;
using Layout = SphereTree::Layout;

void check_pose(const Eigen::Isometry3d& X, const char* name) {
  if (!X.matrix().allFinite())
    throw std::invalid_argument(std::string(name) + " has a non-finite entry");
}

void check_options(const DistanceOptions& o) {
  if (!(o.abs_err >= 0.0) || !std::isfinite(o.abs_err))
    throw std::invalid_argument("DistanceOptions::abs_err must be finite and >= 0");
  if (!(o.rel_err >= 0.0) || !std::isfinite(o.rel_err))
    throw std::invalid_argument("DistanceOptions::rel_err must be finite and >= 0");
  if (std::isnan(o.upper_bound)) throw std::invalid_argument("DistanceOptions::upper_bound is NaN");
}

bool has_nodes(const Layout* l) {
  return l != nullptr && l->num_nodes > 0;
}

// Rounding allowance of the collision traversals' node tests, so that touching pairs
// are never pruned: 64 ulps of the scene's extent.
double collision_slack(double extent_a, double extent_b, const Frame& frame) {
  return 64.0 * std::numeric_limits<double>::epsilon() * (extent_a + extent_b + frame.p.norm());
}

// --- tree and tree ---------------------------------------------------------------------

// Calls f(nodes, extent_a, extent_b) with the node-pair adapter for the two trees' node
// types and the extents of the two trees.
template <class F>
void with_sphere_pairs(const Layout& la, const Layout& lb, const Frame& frame, bool is_signed,
                       F&& f) {
  detail::with_node_type(la, [&](auto na) {
    detail::with_node_type(lb, [&](auto nb) {
      using NA = decltype(na);
      using NB = decltype(nb);
      const detail::SpherePairNodes<NA, NB> nodes(la, lb, frame, is_signed);
      f(nodes, detail::tree_extent<NA>(la), detail::tree_extent<NB>(lb));
    });
  });
}

// stop_at_overlap: distance() (the first overlapping pair ends the walk); otherwise
// signed_distance(), whose bounds are signed.
TreeDistance tree_distance(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
                           const Eigen::Isometry3d& X_WB, const DistanceOptions& options,
                           bool stop_at_overlap) {
  check_pose(X_WA, "X_WA");
  check_pose(X_WB, "X_WB");
  check_options(options);
  const Layout* la = tree_layout(a);
  const Layout* lb = tree_layout(b);
  TreeDistance out;
  out.distance = options.upper_bound;
  if (!has_nodes(la) || !has_nodes(lb)) return out;
  const Frame frame(X_WA, X_WB);
  ClosestPair acc(options, stop_at_overlap);
  with_sphere_pairs(*la, *lb, frame, !stop_at_overlap,
                    [&](const auto& nodes, double, double) { detail::traverse(nodes, acc); });
  return acc.result(la->original_index, lb->original_index, X_WA);
}

std::size_t tree_contacts(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
                          const Eigen::Isometry3d& X_WB, std::size_t max_contacts,
                          std::vector<TreeContact>* out, QueryStats* stats) {
  check_pose(X_WA, "X_WA");
  check_pose(X_WB, "X_WB");
  const Layout* la = tree_layout(a);
  const Layout* lb = tree_layout(b);
  QueryStats local;
  std::size_t found = 0;
  if (max_contacts > 0 && has_nodes(la) && has_nodes(lb)) {
    const Frame frame(X_WA, X_WB);
    const std::size_t before = out != nullptr ? out->size() : 0;
    with_sphere_pairs(
        *la, *lb, frame, false, [&](const auto& nodes, double extent_a, double extent_b) {
          ContactList acc(max_contacts, out, collision_slack(extent_a, extent_b, frame), X_WA);
          detail::traverse(nodes, acc);
          local = acc.stats;
          found = acc.found();
        });
    if (out != nullptr) {
      for (std::size_t k = before; k < out->size(); ++k) {
        TreeContact& c = (*out)[k];
        c.sphere_a = la->original_index[c.sphere_a];
        c.primitive_b = lb->original_index[c.primitive_b];
      }
    }
  }
  if (stats != nullptr) *stats = local;
  return found;
}

// --- tree and target -------------------------------------------------------------------

// Calls f(nodes, extent_a) with the node-pair adapter for the tree's node type.
template <class F>
void with_target_pairs(const Layout& la, const ProximityTarget& target, const TargetNode& root,
                       const Frame& frame, bool is_signed, F&& f) {
  detail::with_node_type(la, [&](auto na) {
    using N = decltype(na);
    const detail::TargetNodes<N> nodes(la, target, root, frame, is_signed);
    f(nodes, detail::tree_extent<N>(la));
  });
}

TreeDistance target_distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                             const ProximityTarget& b, const Eigen::Isometry3d& X_WB,
                             const DistanceOptions& options, bool stop_at_overlap) {
  check_pose(X_WA, "X_WA");
  check_pose(X_WB, "X_WB");
  check_options(options);
  const Layout* la = tree_layout(a);
  TreeDistance out;
  out.distance = options.upper_bound;
  if (!has_nodes(la)) return out;
  const std::optional<TargetNode> root = b.root();
  if (!root) return out;
  const Frame frame(X_WA, X_WB);
  ClosestPair acc(options, stop_at_overlap);
  with_target_pairs(*la, b, *root, frame, !stop_at_overlap,
                    [&](const auto& nodes, double) { detail::traverse(nodes, acc); });
  return acc.result(la->original_index, nullptr, X_WA);
}

// Extent of a target about the origin of its frame: its root's RSS (0 for a lone
// primitive, which may be unbounded).
double target_extent(const TargetNode& root) {
  return root.is_leaf
             ? 0.0
             : (root.bounds.center().norm() + root.bounds.length.norm() * 0.5 + root.bounds.radius);
}

std::size_t target_contacts(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                            const ProximityTarget& b, const Eigen::Isometry3d& X_WB,
                            std::size_t max_contacts, std::vector<TreeContact>* out,
                            QueryStats* stats) {
  check_pose(X_WA, "X_WA");
  check_pose(X_WB, "X_WB");
  const Layout* la = tree_layout(a);
  QueryStats local;
  std::size_t found = 0;
  const std::optional<TargetNode> root =
      (max_contacts > 0 && has_nodes(la)) ? b.root() : std::nullopt;
  if (root) {
    const Frame frame(X_WA, X_WB);
    const double extent_b = target_extent(*root);
    const std::size_t before = out != nullptr ? out->size() : 0;
    with_target_pairs(*la, b, *root, frame, false, [&](const auto& nodes, double extent_a) {
      ContactList acc(max_contacts, out, collision_slack(extent_a, extent_b, frame), X_WA);
      detail::traverse(nodes, acc);
      local = acc.stats;
      found = acc.found();
    });
    if (out != nullptr) {
      for (std::size_t k = before; k < out->size(); ++k)
        (*out)[k].sphere_a = la->original_index[(*out)[k].sphere_a];
    }
  }
  if (stats != nullptr) *stats = local;
  return found;
}

}  // namespace

TreeDistance distance(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
                      const Eigen::Isometry3d& X_WB, const DistanceOptions& options) {
  return tree_distance(a, X_WA, b, X_WB, options, true);
}

TreeDistance signed_distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                             const SphereTree& b, const Eigen::Isometry3d& X_WB,
                             const DistanceOptions& options) {
  return tree_distance(a, X_WA, b, X_WB, options, false);
}

bool collide(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
             const Eigen::Isometry3d& X_WB, QueryStats* stats) {
  return tree_contacts(a, X_WA, b, X_WB, 1, nullptr, stats) > 0;
}

std::size_t contacts(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
                     const Eigen::Isometry3d& X_WB, std::size_t max_contacts,
                     std::vector<TreeContact>& out, QueryStats* stats) {
  return tree_contacts(a, X_WA, b, X_WB, max_contacts, &out, stats);
}

TreeDistance distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                      const Eigen::Vector3d& p_WQ, const DistanceOptions& options) {
  check_pose(X_WA, "X_WA");
  check_options(options);
  if (!p_WQ.allFinite()) throw std::invalid_argument("p_WQ has a non-finite coordinate");
  const Layout* la = tree_layout(a);
  TreeDistance out;
  out.distance = options.upper_bound;
  if (!has_nodes(la)) return out;
  const Eigen::Vector3d q = X_WA.inverse() * p_WQ;
  const Eigen::Vector3d x_W = X_WA.linear().transpose().col(0);
  ClosestPair acc(options, false);
  detail::with_node_type(
      *la, [&](auto n) { detail::traverse(detail::PointNodes<decltype(n)>(*la, q, x_W), acc); });
  out = acc.result(la->original_index, nullptr, X_WA);
  if (out.found()) out.p_WPb = p_WQ;
  return out;
}

TreeDistance distance(const SphereTree& a, const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
                      const Eigen::Isometry3d& X_WB, const DistanceOptions& options) {
  return target_distance(a, X_WA, b, X_WB, options, true);
}

TreeDistance signed_distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                             const ProximityTarget& b, const Eigen::Isometry3d& X_WB,
                             const DistanceOptions& options) {
  return target_distance(a, X_WA, b, X_WB, options, false);
}

bool collide(const SphereTree& a, const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
             const Eigen::Isometry3d& X_WB, QueryStats* stats) {
  return target_contacts(a, X_WA, b, X_WB, 1, nullptr, stats) > 0;
}

std::size_t contacts(const SphereTree& a, const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
                     const Eigen::Isometry3d& X_WB, std::size_t max_contacts,
                     std::vector<TreeContact>& out, QueryStats* stats) {
  return target_contacts(a, X_WA, b, X_WB, max_contacts, &out, stats);
}

// --- certified distance bounds ---------------------------------------------------------
// One walk over outer and inner pairs (traversal_bounds.h). The rounding allowance is the
// collision slack of the outer trees (the larger extents), applied to both bounds and to
// the margin of a decision: "colliding" needs U + slack <= m, "free" L - slack > m.

namespace {

void check_margin(double margin) {
  if (!std::isfinite(margin) || margin < 0.0)
    throw std::invalid_argument("decide_collision: margin must be finite and >= 0");
}

const Layout& bounds_layout(const SphereTree& t, const char* name) {
  const Layout* l = tree_layout(t);
  if (!has_nodes(l))
    throw std::invalid_argument(std::string("distance_bounds: the ") + name + " tree is empty");
  return *l;
}

// \p inner_a, \p inner_b: the inner trees' original indices (inner_b null for a target).
template <class O, class I>
BoundsDecision run_bounds(const O& outer, const I& inner, double slack, bool decide, double margin,
                          const std::int32_t* inner_a, const std::int32_t* inner_b) {
  detail::BoundsGather g(decide, margin - slack, margin + slack);
  const detail::BoundsNodes<O, I> nodes(outer, inner, g);
  if (decide) {  // the outer pairs first (traversal_bounds.h)
    detail::traverse_from(nodes, nodes.outer_root(), g);
    if (!(g.lower() - slack > margin)) detail::traverse_from(nodes, nodes.inner_root(), g);
  } else {
    detail::traverse(nodes, g);
  }
  BoundsDecision d;
  // A walk stopped early (the inner sets decided a collision) leaves outer pairs
  // unvisited and unaccounted: lower is then 0, which every distance is at least.
  d.bounds.lower = g.done() ? 0.0 : std::max(0.0, g.lower() - slack);
  d.bounds.upper = std::max(0.0, g.upper() + slack);
  d.bounds.stats = g.total();
  const TreeDistance witness = g.inner.result(inner_a, inner_b, Eigen::Isometry3d::Identity());
  if (witness.found()) {
    d.bounds.upper_a = witness.sphere_a;
    d.bounds.upper_b = witness.primitive_b;
  }
  if (d.bounds.upper <= margin)
    d.verdict = BoundsVerdict::colliding;
  else if (d.bounds.lower > margin)
    d.verdict = BoundsVerdict::free;
  return d;
}

BoundsDecision tree_bounds(const SphereTree& inner_a, const SphereTree& outer_a,
                           const Eigen::Isometry3d& X_WA, const SphereTree& inner_b,
                           const SphereTree& outer_b, const Eigen::Isometry3d& X_WB, bool decide,
                           double margin) {
  check_pose(X_WA, "X_WA");
  check_pose(X_WB, "X_WB");
  const Layout& ia = bounds_layout(inner_a, "inner A");
  const Layout& oa = bounds_layout(outer_a, "outer A");
  const Layout& ib = bounds_layout(inner_b, "inner B");
  const Layout& ob = bounds_layout(outer_b, "outer B");
  const Frame frame(X_WA, X_WB);
  BoundsDecision out;
  with_sphere_pairs(oa, ob, frame, false, [&](const auto& outer, double ea, double eb) {
    with_sphere_pairs(ia, ib, frame, false, [&](const auto& inner, double, double) {
      out = run_bounds(outer, inner, collision_slack(ea, eb, frame), decide, margin,
                       ia.original_index, ib.original_index);
    });
  });
  return out;
}

BoundsDecision target_bounds(const SphereTree& inner_a, const SphereTree& outer_a,
                             const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
                             const Eigen::Isometry3d& X_WB, bool decide, double margin) {
  check_pose(X_WA, "X_WA");
  check_pose(X_WB, "X_WB");
  const Layout& ia = bounds_layout(inner_a, "inner A");
  const Layout& oa = bounds_layout(outer_a, "outer A");
  const std::optional<TargetNode> root = b.root();
  if (!root) throw std::invalid_argument("distance_bounds: the target is empty");
  const Frame frame(X_WA, X_WB);
  const double eb = target_extent(*root);
  BoundsDecision out;
  with_target_pairs(oa, b, *root, frame, false, [&](const auto& outer, double ea) {
    with_target_pairs(ia, b, *root, frame, false, [&](const auto& inner, double) {
      out = run_bounds(outer, inner, collision_slack(ea, eb, frame), decide, margin,
                       ia.original_index, nullptr);
    });
  });
  return out;
}

}  // namespace

DistanceBounds distance_bounds(const SphereTree& inner_a, const SphereTree& outer_a,
                               const Eigen::Isometry3d& X_WA, const SphereTree& inner_b,
                               const SphereTree& outer_b, const Eigen::Isometry3d& X_WB) {
  return tree_bounds(inner_a, outer_a, X_WA, inner_b, outer_b, X_WB, false, 0.0).bounds;
}

DistanceBounds distance_bounds(const SphereTree& inner_a, const SphereTree& outer_a,
                               const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
                               const Eigen::Isometry3d& X_WB) {
  return target_bounds(inner_a, outer_a, X_WA, b, X_WB, false, 0.0).bounds;
}

BoundsDecision decide_collision(const SphereTree& inner_a, const SphereTree& outer_a,
                                const Eigen::Isometry3d& X_WA, const SphereTree& inner_b,
                                const SphereTree& outer_b, const Eigen::Isometry3d& X_WB,
                                double margin) {
  check_margin(margin);
  return tree_bounds(inner_a, outer_a, X_WA, inner_b, outer_b, X_WB, true, margin);
}

BoundsDecision decide_collision(const SphereTree& inner_a, const SphereTree& outer_a,
                                const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
                                const Eigen::Isometry3d& X_WB, double margin) {
  check_margin(margin);
  return target_bounds(inner_a, outer_a, X_WA, b, X_WB, true, margin);
}

}  // namespace medspheres
