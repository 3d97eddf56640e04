#pragma once
// Node-pair adapter and accumulator of the traversal (traversal.h) for certified distance
// bounds: object A has an inner and an outer sphere tree; B has an inner and an outer tree,
// or is one ProximityTarget seen by both. One walk visits pairs of both kinds, so that each
// kind prunes the other. Private to the runtime target.
//
// A Pair is the virtual root, an outer pair (outer A, outer B) or an inner pair (inner A,
// inner B). The virtual root opens into the two root pairs. The accumulator gathers
//   L: the smallest outer pair distance seen (a lower bound, when every outer pair that
//      could be smaller is seen or pruned with its level recorded), and
//   U: the smallest inner pair distance seen (an upper bound: any inner pair is a pair of
//      points of the two solids).
// Order: the inner root pair first (its bound is taken as -infinity), so that U is known
// when the outer pairs are walked. A decision (sphere_tree_query.cpp) walks the outer pairs
// first instead, from outer_root(), and the inner pairs from inner_root() only when the
// outer sets leave "free" open: against a margin, U prunes the outer pairs only once it
// is below the margin, when the inner sets have already decided; so the order changes no
// verdict, and most pairs a robot checks are free, decided by the outer sets alone.
// Pruning. Inner pairs are pruned at U (as a distance query), and in a decision against a
// margin also at the margin. Outer pairs are pruned at min(U, L): a pair whose bound
// reaches U cannot lower L below what the bounds report (see lower()), and one whose bound
// reaches L does not lower L. Every pruned outer pair leaves a lower bound on its pair
// distances in `floor`, so that lower() = min(L, floor) is a lower bound on the outer sets'
// distance in every mode.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "traversal_accumulators.h"

namespace medspheres::detail {

class BoundsGather {
 public:
  /// With \p decide, the walk only needs to tell lower() > hi from lower() <= hi, and
  /// upper() <= lo from upper() > lo (lo <= hi: a margin with the rounding allowance).
  BoundsGather(bool decide, double lo, double hi)
      : outer(DistanceOptions{}, true),
        inner(DistanceOptions{}, true),
        decide_(decide),
        lo_(lo),
        hi_(std::nextafter(hi, std::numeric_limits<double>::infinity())) {}

  ClosestPair outer;  // L; stops at the first overlap (then lower() <= 0)
  ClosestPair inner;  // U; stops at the first overlap (then upper() <= 0)
  QueryStats stats;

  double prune_at() const { return decide_ ? std::min(inner.prune_at(), hi_) : inner.prune_at(); }

  bool keeps(double lb) {
    const double level = prune_at();
    if (lb < level) return true;
    floor_ = std::min(floor_, level);  // every pair below holds no pair closer than level
    return false;
  }

  bool done() const { return inner.done() || (decide_ && inner.value() <= lo_); }

  /// Whether outer pairs still matter, and the level at which they stop mattering.
  bool outer_wanted() const { return !outer.done() && !(decide_ && outer.value() < hi_); }
  double outer_level() const { return outer.prune_at(); }

  /// Records a lower bound on the pair distances of an outer pair left unvisited.
  void floor(double lb) { floor_ = std::min(floor_, lb); }

  /// A lower bound on the outer sets' distance once the walk has ended without done().
  double lower() const { return std::min(outer.value(), floor_); }
  double upper() const { return inner.value(); }

  QueryStats total() const {
    QueryStats s = stats;
    s.leaf_tests += outer.stats.leaf_tests + inner.stats.leaf_tests;
    return s;
  }

 private:
  bool decide_;
  double lo_, hi_;
  double floor_ = std::numeric_limits<double>::infinity();
};

/// The pairs of both kinds: \p O the outer adapter, \p I the inner one (SpherePairNodes or
/// TargetNodes), each with a leaf test for ClosestPair.
template <class O, class I>
class BoundsNodes {
 public:
  enum Side : std::int8_t { kRoot, kOuter, kInner };
  struct Pair {
    Side side = kRoot;
    bool inner_root = false;  // the inner sets' root pair
    typename O::Pair o;       // an outer pair's nodes
    typename I::Pair i;       // an inner pair's nodes
  };
  static constexpr int kMaxChildren =
      O::kMaxChildren > I::kMaxChildren ? O::kMaxChildren : I::kMaxChildren;

  BoundsNodes(const O& outer, const I& inner, BoundsGather& gather)
      : outer_(outer), inner_(inner), gather_(gather) {}

  Pair root() const { return Pair{}; }
  /// The outer sets' and the inner sets' root pairs, as the virtual root opens into them.
  Pair outer_root() const {
    Pair p;
    p.side = kOuter;
    p.o = outer_.root();
    return p;
  }
  Pair inner_root() const {
    Pair p;
    p.side = kInner;
    p.i = inner_.root();
    p.inner_root = true;
    return p;
  }

  double bound(const Pair& p, double prune_at) const {
    // The virtual root and the inner root pair get the trivial bound -infinity: the inner
    // sets are walked first, so that their distance prunes the outer walk.
    if (p.side == kRoot || p.inner_root) return -std::numeric_limits<double>::infinity();
    if (p.side == kInner) return inner_.bound(p.i, prune_at);
    // Outer pair: node_pair_bound returns infinity once it knows the bound reaches the
    // level it is given, so record that level as the pair's floor.
    if (!gather_.outer_wanted()) {
      const double b = outer_.bound(p.o, prune_at);
      gather_.floor(std::min(b, prune_at));
      return std::numeric_limits<double>::infinity();
    }
    const double level = gather_.outer_level();
    if (level <= prune_at) {
      const double b = outer_.bound(p.o, level);
      return b >= level ? std::numeric_limits<double>::infinity() : b;  // L covers it
    }
    return outer_.bound(p.o, prune_at);  // keeps() records prune_at when it is pruned
  }

  bool is_leaf(const Pair& p) const {
    if (p.side == kRoot) return false;
    return p.side == kOuter ? outer_.is_leaf(p.o) : inner_.is_leaf(p.i);
  }

  bool open_first(const Pair& p) const {
    if (p.side == kRoot) return true;
    return p.side == kOuter ? outer_.open_first(p.o) : inner_.open_first(p.i);
  }

  // Only the member of the pair's side is written (the other one is never read).
  int children(const Pair& p, bool first, Pair* out) const {
    if (p.side == kRoot) {
      out[0] = outer_root();
      out[1] = inner_root();
      return 2;
    }
    int n = 0;
    if (p.side == kOuter) {
      typename O::Pair po[O::kMaxChildren];
      n = outer_.children(p.o, first, po);
      for (int k = 0; k < n; ++k) {
        out[k].side = kOuter;
        out[k].o = po[k];
      }
    } else {
      typename I::Pair pi[I::kMaxChildren];
      n = inner_.children(p.i, first, pi);
      for (int k = 0; k < n; ++k) {
        out[k].side = kInner;
        out[k].i = pi[k];
      }
    }
    return n;
  }

  void leaf(const Pair& p, BoundsGather& acc) const {
    if (p.side == kOuter)
      outer_.leaf(p.o, acc.outer);
    else
      inner_.leaf(p.i, acc.inner);
  }

 private:
  const O& outer_;
  const I& inner_;
  BoundsGather& gather_;
};

}  // namespace medspheres::detail
