#pragma once
// The one traversal of the runtime's proximity queries: a depth-first walk over pairs of
// nodes of two hierarchies, in the manner of coal's distanceRecurse / collisionRecurse.
// Private to the runtime target.
//
// What is walked is given by a node-pair adapter (sphere tree and sphere tree, sphere
// tree and target, sphere tree and point; see traversal_*.h), which provides
//   using Pair = ...;                       a pair of nodes, one of each hierarchy
//   static constexpr int kMaxChildren;      most child pairs one opening yields
//   Pair root() const;
//   double bound(const Pair&, double prune_at) const;
//       a lower bound on the signed distance of any two primitives below the pair; once
//       it knows the bound is >= prune_at it may return any lower bound >= prune_at;
//   bool is_leaf(const Pair&) const;        both nodes are leaves
//   bool open_first(const Pair&) const;     which node to open, the first or the second
//   int children(const Pair&, bool first, Pair* out) const;
//       the pairs made by opening that node, in the hierarchy's child order;
//   void leaf(const Pair&, Accumulator&) const;
//       the leaf test: hands every primitive pair below to the accumulator.
// What is gathered is given by the accumulator (traversal_accumulators.h), which provides
//   QueryStats stats;                       the work done, counted by the walk and the
//                                           leaf tests;
//   double prune_at() const;                the level above which pairs are pruned: the
//                                           adapter's bound may stop refining there;
//   bool keeps(double lb) const;            whether a pair of bound lb is visited: for a
//                                           distance lb < prune_at(), for a collision
//                                           lb <= prune_at() (touching counts);
//   bool done() const;                      whether the walk may stop.
//
// Order. At each opening, the child pairs' bounds are computed in child order and the
// pairs are visited nearest first, ties in child order (a stable sort). A pruned pair is
// pruned for the rest of the walk, since prune_at only decreases. So the order, and
// with it every tie-break and QueryStats count, depends only on the two hierarchies,
// the poses and the query.
//
// A new query mode is a new adapter (and, when it gathers something else, a new
// accumulator). For instance, bounds certified by an inner and an outer sphere set of
// each object: a Pair holds a node pair of the outer sets and one of the inner sets, the
// bound is the outer pair's lower bound, and the leaf test feeds the inner sets' pair
// distances to an accumulator whose prune_at() is the smallest of them (an upper bound
// on the true distance), so that a pair is pruned when its outer lower bound exceeds it.

#include <utility>

#include "medspheres/sphere_tree.h"

namespace medspheres::detail {

/// The child pairs of \p p, opened on the side the adapter chooses, with their bounds
/// (each counted in stats.bv_tests), and in \p order their indices nearest first, ties in
/// child order (the pairs themselves stay put: a bounds walk's pairs hold two pairs each).
template <class Nodes>
int open_pair(const Nodes& nodes, const typename Nodes::Pair& p, double prune_at, QueryStats& stats,
              typename Nodes::Pair* next, double* lb, int* order) {
  const int n = nodes.children(p, nodes.open_first(p), next);
  for (int k = 0; k < n; ++k) {
    ++stats.bv_tests;
    lb[k] = nodes.bound(next[k], prune_at);
    order[k] = k;
  }
  for (int k = 1; k < n; ++k) {  // insertion sort: stable, and n is small
    for (int m = k; m > 0 && lb[order[m]] < lb[order[m - 1]]; --m)
      std::swap(order[m], order[m - 1]);
  }
  return n;
}

template <class Nodes, class Acc>
void recurse(const Nodes& nodes, const typename Nodes::Pair& p, Acc& acc) {
  if (nodes.is_leaf(p)) {
    nodes.leaf(p, acc);
    return;
  }
  typename Nodes::Pair next[Nodes::kMaxChildren];
  double lb[Nodes::kMaxChildren];
  int order[Nodes::kMaxChildren];
  const int n = open_pair(nodes, p, acc.prune_at(), acc.stats, next, lb, order);
  for (int k = 0; k < n; ++k) {
    if (acc.keeps(lb[order[k]])) recurse(nodes, next[order[k]], acc);
    if (acc.done()) return;
  }
}

/// Walks, nearest first, every pair below \p top (itself included) whose bound the
/// accumulator keeps, until it is done.
template <class Nodes, class Acc>
void traverse_from(const Nodes& nodes, const typename Nodes::Pair& top, Acc& acc) {
  ++acc.stats.bv_tests;
  if (acc.keeps(nodes.bound(top, acc.prune_at()))) recurse(nodes, top, acc);
}

/// Walks, nearest first, every pair whose bound the accumulator keeps, until it is done.
template <class Nodes, class Acc>
void traverse(const Nodes& nodes, Acc& acc) {
  traverse_from(nodes, nodes.root(), acc);
}

}  // namespace medspheres::detail
