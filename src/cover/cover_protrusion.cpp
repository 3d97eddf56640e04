// The protrusion stage of the covering bake (cover_protrusion.h).
//
// With the protrusion of a ball at c holding a point p written as |p - c| - D(c) (D the
// signed distance to the surface, positive inside), the least largest protrusion of K
// balls is a k-center problem under an additively weighted distance.
// - The threshold start: candidate centres on a grid inside the solid, each with its depth;
//   a binary search finds the least threshold t at which a greedy set cover picks at most
//   K candidates holding every patch with protrusion <= t (a log-factor approximation of
//   the bottleneck, cover_threshold.h).
// - Minimax rounds, the local improvement: each element goes to the ball whose protrusion
//   grows least to hold it (for fixed centres the assignment of least largest protrusion,
//   as a Voronoi assignment gives the least largest radius), then each centre moves to
//   lower its own protrusion (deepen).
// - Split and exchange moves, for budgets up to kMoveBudget: the ball that protrudes most is
//   split in two, filling the budget while balls are missing, else in exchange for the ball
//   whose elements the others take at the least protrusion; then minimax rounds. (They ran
//   up to K = 16 only at first; at K = 32 they lower P by 14 to 16% on the quadric knot,
//   the trefoil and the fandisk: bench_budget --no-g1 --methods cover --only NAME --k 32.)
// - The fill, at every budget: while the cover has fewer balls than the budget (the threshold
//   start picks fewer when its candidates are too coarse for the solid, as on thin links:
//   the G1's right hip roll link kept 29 to 45 balls at K = 32 to 256, and its largest
//   protrusion at K = 256 was above that at K = 64), the balls that protrude most are split,
//   as many at once as are missing, then minimax rounds (above kMoveBudget with enough
//   tries to double the balls up to any budget, fill_tries). Above kMoveBudget the balls
//   still missing are then spent by splits in place: each part's ball starts where its parent
//   was, so it protrudes no more, and only deepen moves it. Minimax rounds may raise the
//   largest protrusion a little and be refused, and one ball pinned by the surface keeps
//   P where it is whatever the budget, so without them a large budget went mostly unspent
//   (the G1's left hip roll link at K = 4096: 1104 balls after the stage; with them all
//   4096, and the volume outside the solid 9% lower after the bake's last steps).
// - The spread start, for budgets up to kSpreadBudget: farthest-point centres on the
//   surface, then the same rounds and moves; the threshold start's greedy picks can hold
//   the minimax rounds in a worse local optimum, which at small K costs most (the lower
//   of the two results is kept).
// - Balancing rounds (CoverOptions::balance_rounds, none by default): after each run of
//   minimax rounds, rounds whose assignment adds an offset per ball that moves elements from
//   the balls that stick out most to their neighbours (Rounds).
// - Perturbed restarts (CoverOptions::protrusion_restarts, none by default): from the best
//   result so far, the centres jittered, a ball exchanged for a split of the worst, or the
//   spread start from a random patch; then the same rounds and moves, kept when P falls.
//   On the G1's links at cuRobo's counts 48 of them lower P by 0 to 28% (docs/covers.md),
//   at 0.007 to 0.21 CPU s each, beyond the bake's second per link on most links.
// Deepen: the minimum enclosing ball is the smallest ball holding a patch, not the one that
// sticks out least: under a flat patch a centre at depth t sticks out by sqrt(R^2 + t^2) -
// t < R. A pattern search moves each centre to lower its protrusion.
#include "cover_protrusion.h"

#include "cover_threshold.h"
#include "cover_weights.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <random>

#include "medspheres/measure/fit_metrics.h"

namespace medspheres::detail {

namespace {

constexpr double kCandidates = 2000.0;
constexpr double kCandidateGrid = 20000.0;
constexpr int kThresholdHalvings = 12;
constexpr std::size_t kMoveBudget = 64;
constexpr int kMoves = 6, kMovesAbove16 = 3;  // moves at most, up to K = 16 and above
constexpr std::size_t kSpreadBudget = 16;     // the spread start runs up to this budget
constexpr int kMoveRounds = 2;
constexpr int kFillRounds = 6;  // the fill's tries at most, up to kMoveBudget
// The splits in place's tries at most: an accepted one doubles the balls at most, so 32
// reach any budget and leave room for tries of half as many.
constexpr int kSplitInPlaceRounds = 32;
// Balancing rounds (Rounds; CoverOptions::balance_rounds of them at most): the offsets'
// gain; they stop after kBalancePatience rounds in a row that lower the largest protrusion
// by less than kBalanceLeastGain of itself.
constexpr double kBalanceGain = 0.5;
constexpr int kBalancePatience = 4;
constexpr double kBalanceLeastGain = 5e-3;

// The pattern search of deepen (file comment): the six axis steps, halved on failure, from
// \p first times the radius down to 1e-3 of it, each centre to lower the radius needed to
// hold its elements minus its depth; the radius is then the distance to the farthest point.
void deepen(const MeshQuery& query, const Elements& e, Clustering& c, int threads,
            double first = 0.25, const BallWeights& weights = {}) {
  c.settled.clear();
  const auto members = members_of(c.owner, c.balls.size());
  const long long k = static_cast<long long>(c.balls.size());
#pragma omp parallel num_threads(threads)
  {
    std::vector<char> mark(e.points.size(), 0);
    std::vector<Sphere> pts, near;  // each thread's, reused by its balls
#pragma omp for schedule(dynamic, 1)
    for (long long jj = 0; jj < k; ++jj) {
      const std::size_t j = static_cast<std::size_t>(jj);
      if (members[j].empty()) continue;
      atoms_into(e, members[j], mark, pts);
      FarthestAtoms reach(pts, near);
      Eigen::Vector3d x = c.balls[j].center;
      Probe px = probe(query, x, x, {});
      const auto cost = [&](double radius, const Eigen::Vector3d& y, double depth) {
        return weights.weight(Sphere{y, radius}) * (radius - depth);
      };
      const double rx = reach_from(pts, x);
      double fx = cost(rx, x, px.depth);
      const double r = std::max(c.balls[j].radius, rx - px.depth);
      for (double step = first * r; step > 1e-3 * r;) {
        bool moved = false;
        for (int axis = 0; axis < 6 && !moved; ++axis) {
          const Eigen::Vector3d y = x + (axis % 2 ? -step : step) * Eigen::Vector3d::Unit(axis / 2);
          const double ry = reach(y, 4.0 * step);
          // The cost falls as the depth grows: at the depth's upper bound it is a lower bound.
          if (!(cost(ry, y, depth_bound(query, y, px)) < fx)) continue;
          const Probe py = probe(query, y, x, px);
          const double fy = cost(ry, y, py.depth);
          if (fy < fx) x = y, fx = fy, px = py, moved = true;
        }
        if (!moved) step *= 0.5;
      }
      c.balls[j] = {x, holding_radius(pts, x)};
    }
  }
}

// Each ball's depth D(c) from its radius and its protrusion \p q (sphere_protrusions).
std::vector<double> depths_of(const std::vector<Sphere>& balls, const std::vector<double>& q) {
  std::vector<double> depth(q.size());
  for (std::size_t j = 0; j < q.size(); ++j) depth[j] = balls[j].radius - q[j];
  return depth;
}

// The minimax rounds of one local search. A round gives each element to the ball whose
// protrusion, less the ball's offset, is least to hold it, then deepens every centre.
// Without offsets (gain 0) that is the plain round of the file comment. Plain rounds stall
// where balls of unequal protrusion border each other: a ball keeps every element it holds
// more cheaply than its neighbours would, whatever its own protrusion, so the ball that
// sticks out most keeps its elements, and the balls along a tube stay unevenly spaced
// (tests/cover_flow_test.cpp: a torus at K = 16 stops at 1.45 times the P of a ring of balls
// on its axis). Balancing rounds carry an offset per ball that grows by \p gain times the
// mean protrusion less the ball's own, so a ball above the mean cedes its farthest elements
// to its neighbours, which move in turn (the torus: 1.06 times the ring's P).
struct Rounds {
  Rounds(const MeshQuery& query_, const Elements& e_, const BallWeights& weights_, int threads_,
         int& run_)
      : query(query_), e(e_), weights(weights_), threads(threads_), run(run_) {}
  const MeshQuery& query;
  const Elements& e;
  const BallWeights& weights;
  int threads;
  int& run;
  Clustering c, best;
  std::vector<double> depth, q;  // per ball of c: its depth and its weighted protrusion
  double best_p = 0.0;
  bool c_is_best = false;  // c equals best (depth and q describe both)

  double measure() {
    const std::vector<double> p = sphere_protrusions(query, c.balls, threads);
    depth = depths_of(c.balls, p);
    q = weighted(c.balls, weights, p);
    return *std::max_element(q.begin(), q.end());
  }
  void start(Clustering from) {
    c = std::move(from);
    best = c;
    best_p = measure();
    c_is_best = true;
  }
  // At most \p rounds rounds from the best so far, stopping after \p patience in a row that
  // lower the best by less than \p least_gain of itself.
  void descend(int rounds, double gain, int patience, double least_gain) {
    if (!c_is_best) c = best, measure(), c_is_best = true;
    std::vector<double> offset(c.balls.size(), 0.0);
    for (int round = 0, stale = 0; round < rounds && stale < patience; ++round) {
      ++run;
      const double mean = std::accumulate(q.begin(), q.end(), 0.0) / static_cast<double>(q.size());
      std::vector<double> cost_depth = depth;
      for (std::size_t j = 0; j < offset.size(); ++j)
        offset[j] += gain * (mean - q[j]), cost_depth[j] += offset[j];
      if (weights.active())
        assign_weighted(e, c.balls, cost_depth, weights, c.owner, threads);
      else
        assign(e, c.balls, c.owner, threads, cost_depth);
      c.settled.clear();
      const auto members = members_of(c.owner, c.balls.size());
      for (std::size_t j = 0; j < c.balls.size(); ++j)
        if (members[j].empty()) c.balls[j].radius = 0.0;
      deepen(query, e, c, threads, 0.1, weights);
      const std::size_t before = c.balls.size();
      drop_empty(c);
      if (c.balls.size() != before) offset.assign(c.balls.size(), 0.0);
      const double p = measure();
      stale = p < best_p - least_gain * std::abs(best_p) ? 0 : stale + 1;
      c_is_best = p < best_p;
      if (c_is_best) best = c, best_p = p;
    }
  }
};

// Minimax rounds (file comment), at most \p rounds, stopping when the largest protrusion
// drops by less than 1e-3 of itself; then at most \p balance balancing rounds from the best
// so far (Rounds). The best round is kept, then shrunk, which only lowers protrusions. \p run
// counts the rounds.
Clustering minimax(const MeshQuery& query, const Elements& e, Clustering c, int rounds, int threads,
                   int& run, const BallWeights& weights, int balance = 0) {
  drop_empty(c);
  Rounds r(query, e, weights, threads, run);
  r.start(std::move(c));
  r.descend(rounds, 0.0, 1, 1e-3);
  if (balance > 0) r.descend(balance, kBalanceGain, kBalancePatience, kBalanceLeastGain);
  shrink(e, r.best);
  return std::move(r.best);
}

// The candidate centres: the points of a grid inside the solid (about kCandidates of them,
// the grid at most kCandidateGrid points), each with its depth; \p volume: the solid's
// volume (solid_volume), which sizes the grid.
struct Candidates {
  std::vector<Eigen::Vector3d> centres;
  std::vector<double> depth;
};

Candidates candidates(const MeshQuery& query, const std::optional<double>& volume, int threads) {
  const Eigen::AlignedBox3d box = query.mesh().bounds();
  const double box_volume = box.sizes().prod();
  const double cell = std::max(std::cbrt(volume.value_or(box_volume) / kCandidates),
                               std::cbrt(box_volume / kCandidateGrid));
  std::vector<Eigen::Vector3d> points;
  for (double x = box.min().x() + 0.5 * cell; x < box.max().x(); x += cell)
    for (double y = box.min().y() + 0.5 * cell; y < box.max().y(); y += cell)
      for (double z = box.min().z() + 0.5 * cell; z < box.max().z(); z += cell)
        points.emplace_back(x, y, z);
  const std::vector<double> w = query.winding_numbers(points, threads);
  Candidates out;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (w[i] > 0.5) out.centres.push_back(points[i]);
  const std::vector<ClosestPoint> near = query.closest_points(out.centres, threads);
  for (const ClosestPoint& c : near) out.depth.push_back(c.distance());
  return out;
}

// The threshold start (file comment): the K candidate centres of the least threshold cover
// of the patches \p p, each patch's cost at a candidate the protrusion a ball there needs to
// hold it; the elements then go to them as in the minimax rounds, each ball as large as its
// elements need. Empty when no cover is found.
Clustering threshold_start(const MeshQuery& query, const Elements& e, const Elements& p,
                           std::size_t budget, const std::optional<double>& volume, int threads,
                           const BallWeights& weights) {
  const Candidates cand = candidates(query, volume, threads);
  const std::size_t m_count = cand.centres.size(), items = p.size();
  Clustering c;
  if (m_count == 0) return c;
  // Filled below, every entry: not zeroed first (tens of MB at the larger budgets).
  const std::unique_ptr<float[]> cost(new float[m_count * items]);
  const long long n = static_cast<long long>(m_count);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long long mm = 0; mm < n; ++mm) {
    const std::size_t m = static_cast<std::size_t>(mm);
    const double gap = weights.active() ? weights.gap(cand.centres[m]) : 0.0;
    for (std::size_t q = 0; q < items; ++q) {
      const double reach = farthest(p, q, cand.centres[m]);
      cost[m * items + q] =
          static_cast<float>((reach - cand.depth[m]) * weights.weight(reach, gap));
    }
  }
  const ThresholdCover tc =
      least_threshold_cover(cost.get(), m_count, items, budget,
                            std::numeric_limits<double>::infinity(), kThresholdHalvings, threads);
  if (tc.picks.empty()) return c;
  std::vector<double> depth;
  for (std::size_t m : tc.picks)
    c.balls.push_back({cand.centres[m], weights.active() ? 0.0 : 1.0}),
        depth.push_back(cand.depth[m]);
  if (weights.active())
    assign_weighted(e, c.balls, depth, weights, c.owner, threads);
  else
    assign(e, c.balls, c.owner, threads, depth);
  hold_members(e, c);
  return c;
}

// Ball j's elements divided about their two most distant centroids (the farthest from the
// ball's centre, then the farthest from that); the second part goes to a new ball, centred
// at its far centroid, whose radius (as j's) is left for the caller to set. False when j
// has fewer than two elements.
bool halve(const Elements& e, Clustering& c, std::size_t j) {
  std::vector<std::size_t> members;
  for (std::size_t i = 0; i < c.owner.size(); ++i)
    if (c.owner[i] == static_cast<int>(j)) members.push_back(i);
  if (members.size() < 2) return false;
  c.settled.clear();
  auto farthest_from = [&](const Eigen::Vector3d& x) {
    return *std::max_element(members.begin(), members.end(), [&](std::size_t a, std::size_t b) {
      return (e.centroids[a] - x).squaredNorm() < (e.centroids[b] - x).squaredNorm();
    });
  };
  const Eigen::Vector3d a = e.centroids[farthest_from(c.balls[j].center)];
  const Eigen::Vector3d b = e.centroids[farthest_from(a)];
  const int fresh = static_cast<int>(c.balls.size());
  c.balls.push_back({b, 0.0});
  for (std::size_t i : members)
    if ((e.centroids[i] - b).squaredNorm() < (e.centroids[i] - a).squaredNorm()) c.owner[i] = fresh;
  return true;
}

// Ball j halved, each part fitted with its minimum enclosing ball; the second part becomes
// a new ball. False when j has fewer than two elements.
bool split(const Elements& e, Clustering& c, std::size_t j) {
  if (!halve(e, c, j)) return false;
  const std::size_t fresh = c.balls.size() - 1;
  const auto parts = members_of(c.owner, c.balls.size());
  std::vector<char> mark(e.points.size(), 0);
  for (std::size_t part : {j, fresh})
    c.balls[part] =
        parts[part].empty() ? Sphere{c.balls[part].center, 0.0} : fit(e, parts[part], mark);
  return true;
}

// Ball j halved, both parts' balls centred where ball j was: each holds part of j's
// elements, so once its radius holds them (the caller's hold_members) it protrudes there no
// more than j did, and deepen only lowers that (the fill's splits in place).
bool split_in_place(const Elements& e, Clustering& c, std::size_t j) {
  const Eigen::Vector3d parent = c.balls[j].center;
  if (!halve(e, c, j)) return false;
  c.balls[j].center = parent;
  c.balls.back().center = parent;
  return true;
}

// The ball other than j (the one element i belongs to) that holds i at the least
// protrusion, given each ball's \p depth, and that protrusion. \p g: scratch.
std::pair<std::size_t, double> cheapest_other(const Elements& e, const Clustering& c, std::size_t i,
                                              const std::vector<double>& depth,
                                              std::vector<double>& g) {
  const std::size_t j = static_cast<std::size_t>(c.owner[i]);
  std::pair<std::size_t, double> best{j, std::numeric_limits<double>::infinity()};
  // The farthest point is within |centroid - c| +- reach: skip balls that cannot win, as
  // assign does.
  g.assign(c.balls.size(), std::numeric_limits<double>::infinity());
  double best_hi = std::numeric_limits<double>::infinity();
  for (std::size_t m = 0; m < c.balls.size(); ++m) {
    if (m == j || !(c.balls[m].radius > 0.0)) continue;
    g[m] = (e.centroids[i] - c.balls[m].center).norm() - depth[m];
    best_hi = std::min(best_hi, g[m] + e.reach[i]);
  }
  for (std::size_t m = 0; m < c.balls.size(); ++m) {
    const double lo = g[m] - e.reach[i];
    if (!(lo <= best_hi) || lo >= best.second) continue;
    const double v = farthest(e, i, c.balls[m].center) - depth[m];
    if (v < best.second) best = {m, v};
  }
  return best;
}

// The ball whose elements the other balls can take at the least largest protrusion.
std::size_t cheapest_removal(const Elements& e, const Clustering& c,
                             const std::vector<double>& depth, int threads) {
  constexpr double kLow = -std::numeric_limits<double>::infinity();
  std::vector<double> worst(c.balls.size(), kLow);
  const long long n = static_cast<long long>(e.size());
#pragma omp parallel num_threads(threads)
  {
    std::vector<double> mine(c.balls.size(), kLow), g;  // the maximum is order-free
#pragma omp for schedule(static)
    for (long long ii = 0; ii < n; ++ii) {
      const std::size_t i = static_cast<std::size_t>(ii);
      double& w = mine[static_cast<std::size_t>(c.owner[i])];
      w = std::max(w, cheapest_other(e, c, i, depth, g).second);
    }
#pragma omp critical
    for (std::size_t j = 0; j < worst.size(); ++j) worst[j] = std::max(worst[j], mine[j]);
  }
  return static_cast<std::size_t>(std::min_element(worst.begin(), worst.end()) - worst.begin());
}

// Ball \p gone's elements to their cheapest other balls; \p gone is left empty (radius 0).
void hand_over(const Elements& e, Clustering& c, std::size_t gone,
               const std::vector<double>& depth) {
  c.settled.clear();
  std::vector<double> g;
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (c.owner[i] != static_cast<int>(gone)) continue;
    const std::size_t m = cheapest_other(e, c, i, depth, g).first;
    c.owner[i] = static_cast<int>(m);
  }
  c.balls[gone].radius = 0.0;
}

// The split and exchange moves (file comment), at most kMoves (kMovesAbove16 for budgets
// above 16, where each costs more and gains less), each followed by kMoveRounds
// minimax rounds and kept when the largest protrusion \p p (that of \p c, updated) falls; the
// first move that does not help ends them.
Clustering moves(const MeshQuery& query, const Elements& e, Clustering c, std::size_t budget,
                 double& p, int threads, int& run, const BallWeights& weights, int balance) {
  const int most = budget <= 16 ? kMoves : kMovesAbove16;
  for (int move = 0; move < most; ++move) {
    Clustering d = c;
    drop_empty(d);
    if (d.balls.empty()) break;
    const std::vector<double> q = sphere_protrusions(query, d.balls, threads);
    const std::vector<double> depth = depths_of(d.balls, q);
    const std::vector<double> wq = weighted(d.balls, weights, q);
    const std::size_t worst =
        static_cast<std::size_t>(std::max_element(wq.begin(), wq.end()) - wq.begin());
    if (d.balls.size() >= budget) {
      const std::size_t gone = cheapest_removal(e, d, depth, threads);
      if (gone == worst) break;
      hand_over(e, d, gone, depth);
    }
    if (!split(e, d, worst)) break;
    hold_members(e, d);
    d = minimax(query, e, std::move(d), kMoveRounds, threads, run, weights, balance);
    const double v = largest_weighted_protrusion(query, d.balls, weights, threads);
    if (!(v < p)) break;
    c = std::move(d), p = v;
  }
  return c;
}

// The spread start: K centres by farthest-point sampling of the patches' centroids (from
// patch \p first, or by default the one farthest from their mean), each element to the
// nearest, each ball then as large as its elements need and moved inward (deepen). Unlike
// the threshold start it ignores depth, so it lands in a different local optimum of the
// minimax rounds; at small budgets either may be the better one.
Clustering spread_start(const MeshQuery& query, const Elements& e, const Elements& fine,
                        std::size_t budget, int threads,
                        std::optional<std::size_t> first = std::nullopt) {
  Clustering c;
  const std::size_t n = fine.surface;
  if (n == 0) return c;
  std::vector<double> gap(n, std::numeric_limits<double>::infinity());
  if (!first) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) mean += fine.centroids[i];
    mean /= static_cast<double>(n);
    for (std::size_t i = 0; i < n; ++i) gap[i] = (fine.centroids[i] - mean).squaredNorm();
    first = static_cast<std::size_t>(std::max_element(gap.begin(), gap.end()) - gap.begin());
    std::fill(gap.begin(), gap.end(), std::numeric_limits<double>::infinity());
  }
  std::size_t far = *first;
  for (std::size_t k = 0; k < std::min(budget, n); ++k) {
    if (k > 0 && !(gap[far] > 0.0)) break;
    c.balls.push_back({fine.centroids[far], 1.0});
    for (std::size_t i = 0; i < n; ++i)
      gap[i] = std::min(gap[i], (fine.centroids[i] - fine.centroids[far]).squaredNorm());
    far = static_cast<std::size_t>(std::max_element(gap.begin(), gap.end()) - gap.begin());
  }
  assign(e, c.balls, c.owner, threads, {});
  hold_members(e, c);
  deepen(query, e, c, threads);
  return c;
}

// The fill's tries above kMoveBudget: kFillRounds, and one more for each doubling that
// the budget takes from one ball (ceil(log2 K)). An accepted try at most doubles the balls;
// the threshold start leaves a thin link with few (the G1's right hip roll link: 38 at
// K = 4096), so six tries spent 1072 balls there, the splits in place the rest, and those
// never lower the ball that sticks out most: P 5.9 mm at K = 4096 against 4.7 at 1024.
int fill_tries(std::size_t budget) {
  int doublings = 0;
  while ((std::size_t{1} << doublings) < budget) ++doublings;
  return kFillRounds + doublings;
}

// Rounds of splits while c has fewer balls than \p budget (at most \p tries): in a copy of c,
// \p split_one (split or split_in_place) splits the balls that protrude most, as many as are
// missing, each ball then holds its elements and \p improve runs; the copy is kept while the
// largest protrusion \p p (updated) does not rise, else the next try splits half as many.
// With \p stop_stalled, the rounds also stop at a kept copy that neither lowers p nor holds
// more balls.
template <class Improve>
Clustering split_rounds(const MeshQuery& query, const Elements& e, Clustering c, std::size_t budget,
                        int tries, bool stop_stalled, double& p, int threads,
                        const BallWeights& weights,
                        bool (*split_one)(const Elements&, Clustering&, std::size_t),
                        Improve&& improve) {
  auto missing = [&] { return budget > c.balls.size() ? budget - c.balls.size() : 0; };
  // c's balls, the most protruding first (ranked again only when c changes).
  auto ranked = [&] {
    const std::vector<double> wq =
        weighted(c.balls, weights, sphere_protrusions(query, c.balls, threads));
    std::vector<std::size_t> order(c.balls.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return wq[a] > wq[b]; });
    return order;
  };
  drop_empty(c);
  std::vector<std::size_t> order;
  std::size_t batch = missing();
  for (int round = 0; round < tries && batch > 0 && !c.balls.empty(); ++round) {
    if (order.empty()) order = ranked();
    Clustering d = c;
    std::size_t made = 0;
    for (std::size_t j = 0; j < order.size() && made < batch; ++j)
      made += split_one(e, d, order[j]) ? 1 : 0;
    if (made == 0) break;
    hold_members(e, d);
    improve(d);
    const double v = largest_weighted_protrusion(query, d.balls, weights, threads);
    if (v <= p) {
      drop_empty(d);
      const bool stalled = v >= p && d.balls.size() <= c.balls.size();
      c = std::move(d), p = v;
      order.clear();
      batch = missing();
      if (stop_stalled && stalled) break;
    } else {
      batch /= 2;
    }
  }
  return c;
}

// The fill (file comment): the balls that protrude most, as many as are missing, are split at
// once, then minimax rounds (at most \p rounds: a split part's fitted ball sits near the
// surface, and two rounds do not take it deep enough); at most kFillRounds tries of
// split_rounds up to kMoveBudget. Above it, fill_tries, stopping at a stall; then the balls
// still missing are spent by splits in place.
Clustering fill(const MeshQuery& query, const Elements& e, Clustering c, std::size_t budget,
                int rounds, double& p, int threads, int& run, const BallWeights& weights,
                int balance) {
  const bool large = budget > kMoveBudget;
  c = split_rounds(query, e, std::move(c), budget, large ? fill_tries(budget) : kFillRounds, large,
                   p, threads, weights, split, [&](Clustering& d) {
                     d = minimax(query, e, std::move(d), rounds, threads, run, weights, balance);
                   });
  if (!large) return c;
  return split_rounds(query, e, std::move(c), budget, kSplitInPlaceRounds, false, p, threads,
                      weights, split_in_place,
                      [&](Clustering& d) { deepen(query, e, d, threads, 0.25, weights); });
}

// Minimax rounds (at most \p rounds), the split and exchange moves up to kMoveBudget, then the
// fill while balls are still missing; \p p is the result's largest protrusion. Each minimax
// call of them ends with at most \p balance balancing rounds.
Clustering local_search(const MeshQuery& query, const Elements& e, Clustering c, std::size_t budget,
                        int rounds, int balance, int threads, double& p, int& run,
                        const BallWeights& weights) {
  c = minimax(query, e, std::move(c), rounds, threads, run, weights, balance);
  p = largest_weighted_protrusion(query, c.balls, weights, threads);
  if (budget <= kMoveBudget)
    c = moves(query, e, std::move(c), budget, p, threads, run, weights, balance);
  c = fill(query, e, std::move(c), budget, rounds, p, threads, run, weights, balance);
  return c;
}

// A restart's perturbation of \p c (the restarts in protrusion_stage): \p kind 0, every
// centre moved by up to \p scale of its radius, each element then to the ball whose
// protrusion grows least; 1, a random ball other than the one that protrudes most hands
// its elements to the others and that one is split; 2, the spread start from a random
// first patch. Each ball then as large as its elements need.
Clustering perturbed(const MeshQuery& query, const Elements& e, const Elements& fine,
                     const Clustering& c, std::size_t budget, int kind, double scale,
                     std::mt19937_64& rng, int threads) {
  Clustering d = c;
  drop_empty(d);
  if (kind == 2 || d.balls.size() < 2) {
    std::uniform_int_distribution<std::size_t> pick(0, fine.surface - 1);
    return spread_start(query, e, fine, budget, threads, pick(rng));
  }
  const std::vector<double> depth = depths_of(d.balls, sphere_protrusions(query, d.balls, threads));
  if (kind == 0) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (Sphere& b : d.balls) {
      Eigen::Vector3d v;
      do v = Eigen::Vector3d(u(rng), u(rng), u(rng));
      while (v.squaredNorm() > 1.0);
      b.center += scale * b.radius * v;
    }
    assign(e, d.balls, d.owner, threads, depth);
  } else {
    std::size_t worst = 0;
    for (std::size_t j = 1; j < d.balls.size(); ++j)
      if (d.balls[j].radius - depth[j] > d.balls[worst].radius - depth[worst]) worst = j;
    std::uniform_int_distribution<std::size_t> pick(0, d.balls.size() - 2);
    std::size_t gone = pick(rng);
    if (gone >= worst) ++gone;
    if (d.balls.size() >= budget) hand_over(e, d, gone, depth);
    split(e, d, worst);
  }
  d.settled.clear();
  hold_members(e, d);
  return d;
}

}  // namespace

Clustering minimax_rounds(const MeshQuery& query, const Elements& e, Clustering c, int rounds,
                          int threads) {
  int run = 0;
  return minimax(query, e, std::move(c), rounds, threads, run, BallWeights{});
}

double largest_protrusion(const MeshQuery& query, const std::vector<Sphere>& balls, int threads) {
  return largest_weighted_protrusion(query, balls, BallWeights{}, threads);
}

Clustering one_ball(const MeshQuery& query, const Elements& e, int threads) {
  Clustering c;
  std::vector<std::size_t> surface(e.surface);
  for (std::size_t i = 0; i < e.surface; ++i) surface[i] = i;
  std::vector<char> mark(e.points.size(), 0);
  c.balls.push_back(fit(e, surface, mark));
  c.owner.assign(e.size(), 0);
  hold_members(e, c);
  deepen(query, e, c, threads);
  return c;
}

ProtrusionStage protrusion_stage(const MeshQuery& query, const Elements& e, const Elements& fine,
                                 std::size_t budget, int rounds,
                                 const std::optional<double>& volume, int threads,
                                 const BallWeights& weights, int restarts, int balance) {
  ProtrusionStage out;
  Clustering c = threshold_start(query, e, fine, budget, volume, threads, weights);
  if (c.balls.empty()) c = one_ball(query, e, threads);
  double p = 0.0;
  c = local_search(query, e, std::move(c), budget, rounds, balance, threads, p, out.rounds,
                   weights);
  if (budget <= kSpreadBudget) {
    double q = 0.0;
    Clustering d = local_search(query, e, spread_start(query, e, fine, budget, threads), budget,
                                rounds, balance, threads, q, out.rounds, weights);
    if (q < p) std::swap(c, d), std::swap(p, q);
    out.others.push_back(std::move(d));
  }
  std::mt19937_64 rng(0x5eed);
  for (int restart = 0; restart < restarts && fine.surface > 0; ++restart) {
    const int kind = restart % 3;
    const double scale = restart % 2 ? 0.3 : 0.1;
    double q = 0.0;
    Clustering d =
        local_search(query, e, perturbed(query, e, fine, c, budget, kind, scale, rng, threads),
                     budget, rounds, balance, threads, q, out.rounds, weights);
    if (q < p) c = std::move(d), p = q;
  }
  out.clustering = std::move(c);
  return out;
}

}  // namespace medspheres::detail
