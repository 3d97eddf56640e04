// The counting argument of the cover lower bound; contract in cover_count_bound.h.
#include "cover_count_bound.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <queue>

#include "medspheres/threads.h"

// Derivation.
//
// D is the signed distance to the surface S (positive inside), as in cover_lower_bound.cpp;
// a ball (c, r) protrudes by r - D(c).
//
// 1. Counting. Let W be points of S (the witnesses) with integer weights y_w >= 1, of total
//    Y, and K balls whose union contains S, each of protrusion at most P. Each witness lies
//    in some ball, so the balls hold weight >= Y in all and some ball (c, r) holds weight
//    >= q = ceil(Y / K): r >= d_y(c), the least radius at which the witnesses within it
//    weigh >= q. So P >= r - D(c) >= phi(c) = d_y(c) - D(c), and P >= inf over all c of
//    phi. With K + 1 witnesses of weight 1 (q = 2) this is the pair argument (min over c of
//    max(|c - x|, |c - y|) - D(c), least over pairs); with many witnesses it bounds how
//    much of the surface (as the weights measure it) one ball of protrusion P can hold: a
//    K-th. Integer weights keep the sums exact.
// 2. phi >= 0: D(c) <= the distance from c to S <= the distance to the nearest witness <=
//    d_y(c).
// 3. Centres in the mesh's box suffice. For c outside the box (so outside the solid, D(c)
//    = -d(c), d the unsigned distance to S) let c' be its projection on the box. The box
//    is convex and holds W and S, so |c' - w| <= |c - w| for every w (d_y(c') <= d_y(c))
//    and d(c') <= d(c), hence D(c') >= -d(c') >= -d(c) = D(c): phi(c') <= phi(c).
// 4. A box of centres, centre g, half extents e, half diagonal rho. Every c in it has
//    |c - w| >= the distance from w to the box, so d_y(c) >= the weighted order statistic
//    of those distances (each >= |g - w| - rho); and D(c) <= U, where on a closed mesh U =
//    D(g) + rho (D is 1-Lipschitz), and on an open mesh's winding solid U = d(g) + rho (D
//    <= d everywhere, d 1-Lipschitz) unless g is outside with d(g) > rho: then the box
//    lies outside (the assumption of cover_lower_bound.cpp, step 9) and U = rho - d(g). So
//    phi >= max(0, that order statistic - U) on the box. The inside test is step 6's (the
//    settled winding number); a box whose parent had d > rho (no surface in it, so one
//    side) takes the parent's side.
// 5. Branch and bound. The root is the mesh's box; the box of least value is split in 8
//    until `queries` boxes are evaluated or it is below 1e-4 L across. The boxes partition
//    the root, so the least value of a box bounds inf phi from below at every stopping
//    point. Witness lists: d_y is 1-Lipschitz, so on a box d_y(c) <= d_y(g) + rho, and
//    only the witnesses within d_y(g) + 2 rho of g (rounded up) can be among those that set
//    d_y(c); its children look at those alone (d_y is unchanged by dropping the others).
// 6. Rounding. Distances and the witnesses (interpolated samples) are exact up to a few
//    ulps of the coordinates; the bound is lowered by the caller's slack (4 times
//    cover_radius_slack), far above those errors. Sums of weights are exact (integers).
// 7. The weights (no part of the proof: any weights give a valid bound). Equal weights
//    prove little where one ball holds much surface cheaply (a thin flange, a concave
//    corner): the weights should sit where balls are dear, as in the fractional cover's
//    dual. For a threshold t, the balls of protrusion t centred on the depth grid's inside
//    centres (at most kCheapBalls of them, every k-th) hold sets of the witnesses;
//    multiplicative weights (kRounds rounds, each lowering by kStep the weights of the
//    heaviest ball's witnesses) look for weights under which every such ball holds less
//    than a K-th of the total, and t is bisected to the largest at which they find them
//    (kBisections steps; a t at which no ball holds any witness is feasible with any
//    weights). Those weights, scaled to integers 0 .. kScale, go to the branch
//    and bound (step 5). Then the kFound boxes of least value (the cheapest balls the
//    grid missed) join the centres and the weights are chosen again (`passes` passes in
//    all); the largest bound is kept. A last pass blends in the pair argument's K + 1
//    witnesses, each of weight Y / (kBlend K) beside the best pass's weights (total Y):
//    then a ball must hold several pair witnesses, or some of them and a share of the
//    surface, or a larger share of the surface alone. On more than kCoarse witnesses the weights
//    are chosen on the first kCoarse (spread: farthest-point order) and each witness takes its
//    nearest one's.
// 8. Equal weights on many witnesses (a last pass, when asked for). On a smooth thick solid
//    (a torus, K = 32) the balls that hold a K-th of the surface most cheaply are slices
//    whose width is a few witness spacings, and the chosen weights, fitted to the cheap
//    centres, leave cheaper ones between them. Even, dense witnesses of weight 1 measure
//    the surface itself: with 1024 a ball of the torus can hold a K-th of the count with a
//    slice narrower than a K-th of the area.
// Every step runs in a fixed order, so the result does not depend on the thread count.

namespace medspheres::detail {

double settled_winding(const MeshQuery& query, const Eigen::Vector3d& p, double w) {
  return std::abs(w - std::round(w)) > 0.1 ? query.winding_number_exact(p) : w;
}

namespace {

// Witnesses of positive integer weight, and the weighted order statistic of step 1: the
// least r such that the witnesses within r weigh >= ceil(Y / K).
class WeightedWitnesses {
 public:
  using Item = std::pair<double, long>;  // a squared distance, a weight

  WeightedWitnesses(const std::vector<Eigen::Vector3d>& pool, const std::vector<long>& weight,
                    std::size_t budget) {
    for (std::size_t i = 0; i < pool.size(); ++i)
      if (weight[i] > 0) {
        point_.push_back(pool[i]);
        weight_.push_back(weight[i]);
        total_ += weight[i];
      }
    need_ = (total_ + static_cast<long>(budget) - 1) / static_cast<long>(budget);
  }

  std::size_t size() const { return weight_.size(); }
  long total() const { return total_; }
  const Eigen::Vector3d& point(int i) const { return point_[static_cast<std::size_t>(i)]; }
  long weight(int i) const { return weight_[static_cast<std::size_t>(i)]; }

  // The square root of the least squared distance of \p items at which their weight, in
  // increasing order, reaches ceil(Y / K) (weighted quickselect; reorders items); infinity
  // when the items weigh less.
  double order(std::vector<Item>& items) const {
    auto lo = items.begin(), hi = items.end();
    long need = need_;
    while (lo != hi) {
      const double pivot = (lo + (hi - lo) / 2)->first;
      const auto less = std::partition(lo, hi, [&](const Item& a) { return a.first < pivot; });
      const auto equal = std::partition(less, hi, [&](const Item& a) { return a.first == pivot; });
      long below = 0, at = 0;
      for (auto it = lo; it != less; ++it) below += it->second;
      for (auto it = less; it != equal; ++it) at += it->second;
      if (below >= need) {
        hi = less;
      } else if (below + at >= need) {
        return std::sqrt(pivot);
      } else {
        need -= below + at;
        lo = equal;
      }
    }
    return std::numeric_limits<double>::infinity();
  }

 private:
  std::vector<Eigen::Vector3d> point_;
  std::vector<long> weight_;
  long total_ = 0, need_ = 0;
};

// Step 5: best-first branch and bound on inf phi over the mesh's box.
class CountRefinement {
 public:
  CountRefinement(const MeshQuery& query, bool closed, const WeightedWitnesses& witnesses)
      : query_(query), closed_(closed), witnesses_(witnesses) {
    auto all = std::make_shared<std::vector<int>>(witnesses.size());
    for (std::size_t i = 0; i < all->size(); ++i) (*all)[i] = static_cast<int>(i);
    const Eigen::AlignedBox3d box = query.mesh().bounds();
    add(box.center(), 0.5 * box.sizes(), all, 0);
  }

  // The least value of a box: a lower bound on inf phi.
  double bound() const { return boxes_.empty() ? 0.0 : boxes_.top().value; }

  // Splits the box of least value into 8; false when it is below \p finest across.
  bool split(double finest) {
    if (boxes_.empty() || 2.0 * boxes_.top().half.norm() < finest) return false;
    const Box b = boxes_.top();
    boxes_.pop();
    // Step 5's witness lists: d_y(c) <= d_y(g) + rho on the box, so only witnesses within
    // d_y(g) + 2 rho of g (rounded up) can set d_y anywhere in it.
    items_.clear();
    for (int i : *b.witnesses)
      items_.emplace_back((witnesses_.point(i) - b.centre).squaredNorm(), witnesses_.weight(i));
    const double reach = (witnesses_.order(items_) + 2.0 * b.half.norm()) * (1.0 + 1e-9);
    auto near = std::make_shared<std::vector<int>>();
    for (int i : *b.witnesses)
      if ((witnesses_.point(i) - b.centre).squaredNorm() <= reach * reach) near->push_back(i);
    const Eigen::Vector3d e = 0.5 * b.half;
    for (int k = 0; k < 8; ++k)
      add(b.centre + Eigen::Vector3d(k & 1 ? e.x() : -e.x(), k & 2 ? e.y() : -e.y(),
                                     k & 4 ? e.z() : -e.z()),
          e, near, b.one_side);
    return true;
  }

  std::size_t queries() const { return queries_; }

  // The centres of the (at most) \p count boxes of least value, taken off the heap.
  std::vector<Eigen::Vector3d> lowest(std::size_t count) {
    std::vector<Eigen::Vector3d> out;
    for (; out.size() < count && !boxes_.empty(); boxes_.pop()) out.push_back(boxes_.top().centre);
    return out;
  }

 private:
  struct Box {
    Eigen::Vector3d centre, half;
    double value;
    std::shared_ptr<const std::vector<int>> witnesses;
    int one_side;  // +1 / -1: the box is inside / outside the solid (no surface in it); 0: unknown
    bool operator<(const Box& o) const { return value > o.value; }  // least on top
  };

  // Step 4's value of the box, with d_m(c) >= the order statistic of the witnesses' least
  // distances to the box (each >= |w - g| - rho). \p side: the parent's one_side.
  void add(const Eigen::Vector3d& g, const Eigen::Vector3d& half,
           std::shared_ptr<const std::vector<int>> near, int side) {
    ++queries_;
    const double rho = half.norm(), d = query_.closest_point(g).distance();
    bool in = side > 0;
    if (side == 0) {
      double w = query_.winding_number(g);
      if (closed_) w = settled_winding(query_, g, w);
      in = w > 0.5;
    }
    double upper;  // U of step 4
    if (closed_)
      upper = (in ? d : -d) + rho;
    else
      upper = (in || d <= rho) ? d + rho : rho - d;
    items_.clear();
    for (int i : *near) {
      const Eigen::Vector3d gap = ((witnesses_.point(i) - g).cwiseAbs() - half).cwiseMax(0.0);
      items_.emplace_back(gap.squaredNorm(), witnesses_.weight(i));
    }
    const double least = witnesses_.order(items_);
    boxes_.push(
        {g, half, std::max(0.0, least - upper), std::move(near), d > rho ? (in ? 1 : -1) : 0});
  }

  const MeshQuery& query_;
  bool closed_;
  const WeightedWitnesses& witnesses_;
  std::priority_queue<Box> boxes_;
  std::vector<WeightedWitnesses::Item> items_;
  std::size_t queries_ = 0;
};

constexpr std::size_t kCheapBalls = 4096;  // the most depth samples the weights start from
constexpr std::size_t kCoarse = 1024;      // the most witnesses the weights are chosen on
constexpr int kRounds = 300;               // multiplicative-weight rounds per threshold
constexpr double kStep = 0.1;              // their factor 1 - kStep
constexpr int kBisections = 14;
constexpr long kScale = 1000;        // integer weights 0 .. kScale
constexpr std::size_t kFound = 256;  // boxes found as cheap centres
constexpr double kBlend = 2.0;       // a pair witness weighs the total / (kBlend K)

// Weights (step 8) that make the balls of protrusion t on the cheap centres hold little:
// multiplicative weights against the heaviest ball, the best ratio total / heaviest kept.
// Returns that ratio; \p weight gets the weights.
double weights_at(const std::vector<std::vector<int>>& holds,
                  const std::vector<std::vector<int>>& held_by, std::size_t witnesses,
                  double enough, std::vector<double>& weight) {
  std::vector<double> y(witnesses, 1.0), sum(holds.size());
  for (std::size_t g = 0; g < holds.size(); ++g) sum[g] = static_cast<double>(holds[g].size());
  double total = static_cast<double>(witnesses), best = 0.0;
  for (int round = 0; round <= kRounds; ++round) {
    const std::size_t top =
        static_cast<std::size_t>(std::max_element(sum.begin(), sum.end()) - sum.begin());
    // No ball holds any witness: every ball holds less than a K-th, whatever the weights.
    if (sum[top] <= 0.0) {
      weight = y;
      return std::numeric_limits<double>::infinity();
    }
    const double ratio = total / sum[top];
    if (ratio > best) {
      best = ratio;
      weight = y;
    }
    // Stopped early when the ratio stays below half of enough (hopeless).
    if (round == kRounds || (round >= kRounds / 6 && best < 0.5 * enough)) break;
    for (int w : holds[top]) {
      const double dy = kStep * y[static_cast<std::size_t>(w)];
      y[static_cast<std::size_t>(w)] -= dy;
      total -= dy;
      for (int g : held_by[static_cast<std::size_t>(w)]) sum[static_cast<std::size_t>(g)] -= dy;
    }
  }
  return best;
}

// Centres of balls with their depth D: where the weights look for cheap balls.
struct Centres {
  std::vector<Eigen::Vector3d> point;
  std::vector<double> depth;
};

// Step 8: the weights of the largest threshold t (bisection) at which the balls of
// protrusion t at \p cheap hold at most a K-th of the total, as integers 0 .. kScale (all 1
// when none is found).
std::vector<long> chosen_weights(const std::vector<Eigen::Vector3d>& pool, const Centres& cheap,
                                 std::size_t budget, double L, int threads) {
  std::vector<long> out(pool.size(), 1);
  if (cheap.point.empty()) return out;
  std::vector<double> weight, found;
  double lo = 0.0, hi = L;
  for (int step = 0; step < kBisections; ++step) {
    const double t = 0.5 * (lo + hi);
    std::vector<std::vector<int>> holds(cheap.point.size()), held_by(pool.size());
    const long long n = static_cast<long long>(cheap.point.size());
#pragma omp parallel for schedule(dynamic, 64) num_threads(thread_count(threads))
    for (long long i = 0; i < n; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      const double r = t + cheap.depth[k];
      if (r < 0.0) continue;
      for (std::size_t w = 0; w < pool.size(); ++w)
        if ((pool[w] - cheap.point[k]).squaredNorm() <= r * r)
          holds[k].push_back(static_cast<int>(w));
    }
    for (std::size_t k = 0; k < holds.size(); ++k)
      for (int w : holds[k]) held_by[static_cast<std::size_t>(w)].push_back(static_cast<int>(k));
    const double K = static_cast<double>(budget);
    if (weights_at(holds, held_by, pool.size(), K, weight) > K) {
      lo = t;
      found = weight;
    } else {
      hi = t;
    }
  }
  if (found.empty()) return out;
  const double top = *std::max_element(found.begin(), found.end());
  for (std::size_t w = 0; w < pool.size(); ++w)
    out[w] = std::lround(static_cast<double>(kScale) * found[w] / top);
  return out;
}

// Each point of \p pool gets the weight of its nearest point of \p coarse (ties: the first).
std::vector<long> spread(const std::vector<Eigen::Vector3d>& pool,
                         const std::vector<Eigen::Vector3d>& coarse,
                         const std::vector<long>& weight) {
  std::vector<long> out(pool.size());
  for (std::size_t i = 0; i < pool.size(); ++i) {
    std::size_t best = 0;
    for (std::size_t k = 1; k < coarse.size(); ++k)
      if ((pool[i] - coarse[k]).squaredNorm() < (pool[i] - coarse[best]).squaredNorm()) best = k;
    out[i] = weight[best];
  }
  return out;
}

// Step 5 on \p points with \p weight: keeps the bound in \p out when it is the largest so
// far, and returns the centres of the kFound boxes of least value.
std::vector<Eigen::Vector3d> prove(const MeshQuery& query, bool closed, std::size_t budget,
                                   const std::vector<Eigen::Vector3d>& points,
                                   const std::vector<long>& weight, double slack,
                                   std::size_t queries, double finest, CountBound& out) {
  WeightedWitnesses w(points, weight, budget);
  if (w.size() == 0) return {};
  CountRefinement r(query, closed, w);
  while (r.queries() < queries && r.split(finest)) {
  }
  const double bound = std::max(0.0, r.bound() - slack);
  out.queries += r.queries();
  if (bound > out.bound) {
    out.bound = bound;
    out.points.clear();
    out.weights.clear();
    for (std::size_t i = 0; i < points.size(); ++i)
      if (weight[i] > 0) {
        out.points.push_back(points[i]);
        out.weights.push_back(weight[i]);
      }
  }
  return r.lowest(kFound);
}

}  // namespace

CountBound count_lower_bound(const MeshQuery& query, bool closed, std::size_t budget,
                             const std::vector<Eigen::Vector3d>& pool, const DepthSamples& samples,
                             const std::vector<Eigen::Vector3d>& pairs,
                             const std::vector<Eigen::Vector3d>& even, double slack,
                             std::size_t queries, int passes, int threads) {
  const double L = query.mesh().bounds().sizes().maxCoeff();
  const double finest = 1e-4 * L;
  Centres cheap;
  const std::size_t n = samples.points ? samples.points->size() : 0;
  const std::size_t stride = std::max<std::size_t>(1, (n + kCheapBalls - 1) / kCheapBalls);
  for (std::size_t i = 0; i < n; i += stride) {
    cheap.point.push_back((*samples.points)[i]);
    cheap.depth.push_back((*samples.depth)[i]);
  }
  const std::vector<Eigen::Vector3d> coarse(
      pool.begin(), pool.begin() + static_cast<long>(std::min(pool.size(), kCoarse)));
  CountBound out;
  std::vector<long> best;
  for (int pass = 0; pass < passes; ++pass) {
    const std::vector<long> weight =
        spread(pool, coarse, chosen_weights(coarse, cheap, budget, L, threads));
    const double before = out.bound;
    for (const Eigen::Vector3d& c :
         prove(query, closed, budget, pool, weight, slack, queries, finest, out)) {
      const double d = query.closest_point(c).distance();
      cheap.point.push_back(c);
      cheap.depth.push_back(query.inside(c) ? d : -d);
    }
    if (best.empty() || out.bound > before) best = weight;
  }
  // Step 7's blend: the pair argument's witnesses join the best weights, each weighing a
  // share of their total, so that a ball must hold pair witnesses and surface both.
  if (!pairs.empty() && !best.empty() && budget > 1) {
    long total = 0;
    for (long y : best) total += y;
    std::vector<Eigen::Vector3d> points = pool;
    points.insert(points.end(), pairs.begin(), pairs.end());
    std::vector<long> weight = best;
    weight.resize(points.size(), std::max<long>(1, total / static_cast<long>(kBlend * budget)));
    prove(query, closed, budget, points, weight, slack, queries, finest, out);
  }
  if (!even.empty())  // step 8
    prove(query, closed, budget, even, std::vector<long>(even.size(), 1), slack, queries, finest,
          out);
  return out;
}

}  // namespace medspheres::detail
