// A lower bound on the least max protrusion of any K-ball surface cover; contract in
// cover_lower_bound.h.
#include "medspheres/cover/cover_lower_bound.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <queue>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cover_count_bound.h"
#include "cover_elements.h"
#include "medspheres/cover/cover.h"
#include "medspheres/error.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/threads.h"

// Derivation.
//
// D is the signed distance to the surface S (positive inside), 1-Lipschitz. The protrusion
// of a ball (c, r) is r - D(c). For a point x and h >= 0 let rho(x, h) = max of D over the
// ball B(x, h).
//
// 1. One point. A ball (c, r) holding x has c in B(x, r), so D(c) <= rho(x, r) and its
//    protrusion is >= f_x(r) = r - rho(x, r). f_x is nondecreasing: for r >= r0, every c in
//    B(x, r) is within r - r0 of a point c' of B(x, r0) (its radial projection), so
//    D(c) <= D(c') + r - r0 and rho(x, r) <= rho(x, r0) + r - r0.
// 2. Two points. A ball holding x and y has r >= max(|c - x|, |c - y|) >= h = |x - y| / 2,
//    so by 1 its protrusion is >= m(x, y) = max(f_x(h), f_y(h)) = h - min(rho(x, h),
//    rho(y, h)).
// 3. Pigeonhole. K balls (or fewer) whose union contains S hold the K + 1 witnesses
//    w_0 .. w_K (points of S), so one ball holds two of them and protrudes by at least
//    min over pairs i < j of m(w_i, w_j). Any witnesses give a valid bound; they are chosen
//    to make it large (below).
// 4. rho from above. A grid of cell centres g over the mesh's box (cells c_x, c_y, c_z, at
//    most L / resolution each) leaves every point of the box within delta = |c| / 2 of a
//    centre. D(g) is computed at every centre inside the solid (exact closest-point
//    distance). For c in B(x, h): if c is not inside, D(c) <= 0; if it is, c lies in the
//    box, its nearest centre g has |g - x| <= h + delta and D(c) <= D(g) + delta, where
//    D(g) <= 0 unless g is inside. Hence
//      rho(x, h) <= max(0, max{D(g) : g inside, |g - x| <= h + delta}) + delta,
//    and, since D(x) = 0 on the surface, also rho(x, h) <= h. The maximum over centres is
//    read from a per-witness profile: the centres binned by floor(|g - x| / w), w = delta /
//    2, and the running maximum over bins; the bin of h + delta (rounded up by a relative
//    1e-12, above the rounding of |g - x|) holds every centre within h + delta, and some a
//    little farther, which only raises the bound on rho. Bins beyond the last are read as
//    the last, the maximum over all centres.
// 5. Rounding. Closest-point distances, the centres and the witnesses (area samples are
//    interpolated) are exact up to a few ulps of the coordinates; every m is lowered by
//    sigma = 4 cover_radius_slack(L, X) (1e-9 L plus 64 eps of the largest coordinate X,
//    four times), far above those errors. The bound is clamped at 0, which holds anyway:
//    a ball holding a point of S protrudes by >= 0 (|c - x| >= D(c) for x on S).
// 6. Inside. As for protrusions (fit_metrics.h), inside is the winding number > 1/2. The
//    hierarchical winding number is exact up to its expansion error, far below 1/2 on a
//    closed mesh away from the surface; centres whose value is more than 0.1 from an
//    integer are recomputed by the direct sum (winding_number_exact).
// 7. Open meshes (only with winding_solid). The solid is the winding solid and D(c) = d(c)
//    inside, -d(c) outside, d the distance to the mesh with its holes capped when the query
//    caps them (fit_metrics.h); D is no longer 1-Lipschitz where the winding number crosses
//    1/2 off the surface (across a hole). The argument runs on the least 1-Lipschitz
//    majorant D~(c) = sup_y (D(y) - |c - y|) >= D(c) instead, so protrusions are >=
//    r - D~(c) and steps 1 to 3 hold for D~. On the surface D~(x) <= 0 (D(y) <= d(y) <=
//    |y - x|), so max of D~ over B(x, h) is <= h, and it equals
//      sup_y (D(y) - max(0, |y - x| - h)) <= max(0, sup_{y inside} (d(y) - max(0, |y - x| - h))).
//    Assumption (not checked): every inside y farther than delta from the surface lies
//    within delta of a counted centre: an inside centre or one of its 26 neighbours (the
//    band that catches the winding solid's boundary across holes). Then d(y) <= d(g) + delta
//    and |y - x| >= |g - x| - delta, so with R = h + delta the bound is
//      max(0, max over counted g of d(g) - max(0, |g - x| - R)) + delta;
//    points y within delta of the surface add at most delta, which the formula has. In the
//    profile, centres in bins b > floor(R / w) are lowered by (b - floor(R / w) - 1) w, less
//    than their true penalty; the rest are not lowered. Without holes this is looser than
//    step 4 (it has more terms), which is why closed meshes use step 4.
// 8. A sharper bound for a pair, m*. A ball (c, r) holding x and y protrudes by at least
//    phi(c) = max(|c - x|, |c - y|) - D(c), and, with m = (x + y) / 2, the parallelogram law
//    |c - x|^2 + |c - y|^2 = 2 |c - m|^2 + 2 h^2 gives max(|c - x|, |c - y|) >=
//    sqrt(h^2 + |c - m|^2), which loses little to the grid near m. So m(x, y) <= min_c phi(c)
//    and min_c phi(c) >= m*(x, y) = min(h - delta, min over counted g of v(g) - delta),
//      v(g) = max(max(|g - x|, |g - y|) - delta, sqrt(h^2 + max(0, |g - m| - delta)^2)) - d(g):
//    - c not inside: D(c) <= 0, phi(c) >= h;
//    - c inside with d(c) <= delta: phi(c) >= h - delta;
//    - c inside with d(c) > delta: it has a counted centre g within delta (closed mesh: the
//      nearest centre is inside, or the segment to it would cross the surface within delta
//      of c; open mesh: the assumption of step 7), so |c - x| >= |g - x| - delta, |c - m| >=
//      |g - m| - delta, and D(c) = d(c) <= d(g) + delta; hence phi(c) >= v(g) - delta.
//    m* needs no Lipschitz property of D, only of d, so it holds on an open mesh under the
//    assumption of step 7. The pair's bound is max(m, m*) - sigma. It is computed by
//    branch and bound over blocks of 4^3 cells (bounding ball, largest depth).
// 9. Refinement. For the chosen witnesses, min_c phi(c) of a pair is
//    bounded again by branch and bound over boxes: the root is the box of points within
//    R = h + Dmax of x and of y, inside the mesh's box (elsewhere phi >= h: outside the
//    box D <= 0, and beyond R max(|c - x|, |c - y|) - D(c) >= R - Dmax; Dmax = the deepest
//    counted centre plus delta bounds D, as in step 4). A box with centre g and half
//    diagonal r: if g is outside with d(g) > r, the box holds no inside point and phi >= h
//    on it; otherwise, for c in it, D(c) <= d(c) <= d(g) + r and
//      phi(c) >= max(max(|g - x|, |g - y|) - r, sqrt(h^2 + max(0, |g - m| - r)^2)) - d(g) - r.
//    The boxes partition the root, so min(h, least box value) bounds min_c phi. The box of
//    least value is split in 8, for the pair of least current bound (its step 8 value or,
//    once higher, its refined one, less sigma), until refine_queries queries are spent or
//    the box is below 1e-4 L across. Any stopping point gives a valid bound. On an open
//    mesh (winding_solid) "no inside point in the box" also assumes that the winding solid's
//    boundary lies on the capped surface (so that d(g) > r keeps the box on one side).
//
// Choosing the witnesses. Candidates: farthest-point sampling (first: the point farthest
// from the box centre) over area-weighted surface samples and the vertices, so they are
// spread and include the extremities. Then greedy max-min on the pair bound max(m, m*)
// from `starts` first points (the first candidates, the most spread): add the candidate
// whose least bound to the chosen points is largest (ties: lowest index), K times; a
// start's value is the least bound over its pairs. The best start (ties: lowest) is kept,
// improved by single swaps (a point of the worst pair is replaced by the candidate whose
// least bound to the others is largest, while that strictly raises the least bound over
// pairs), and its pairs are refined (step 9).
// Every step runs in a fixed order, so the result does not depend on the thread count.
//
// The bound returned is the larger of this pair bound and the counting argument's
// (cover_count_bound.cpp: many weighted witnesses, a K-th of the weight in one ball); each
// is a valid bound on its own.

namespace medspheres {

namespace {

using detail::settled_winding;
constexpr std::size_t kSamplesPerCandidate = 8;

void check_input(const MeshQuery& query, std::size_t budget, const CoverLowerBoundOptions& o) {
  if (budget == 0) throw std::invalid_argument("budget must be >= 1, got 0");
  if (o.resolution < 4 || o.resolution > 256)
    throw std::invalid_argument("resolution must be in [4, 256], got " +
                                std::to_string(o.resolution));
  if (o.candidates < 2)
    throw std::invalid_argument("candidates must be >= 2, got " + std::to_string(o.candidates));
  if (o.starts < 1)
    throw std::invalid_argument("starts must be >= 1, got " + std::to_string(o.starts));
  if (o.count_passes < 1)
    throw std::invalid_argument("count_passes must be >= 1, got " + std::to_string(o.count_passes));
  if (o.count_witnesses < 2)
    throw std::invalid_argument("count_witnesses must be >= 2, got " +
                                std::to_string(o.count_witnesses));
  if (o.count_even_witnesses == 1)
    throw std::invalid_argument("count_even_witnesses must be 0 or >= 2, got 1");
  check_threads(o.threads);
  if (!o.winding_solid && !solid_volume(query.mesh()))
    throw InputError(ErrorKind::kUnsupported, "mesh",
                     "is not closed (or bounds no volume): the cover lower bound needs a solid "
                     "(winding_solid accepts it, with the assumption of cover_lower_bound.h)");
}

// Step 4's grid: the centres counted (inside the solid; on an open mesh also their
// neighbours, step 7) with their distance to the surface, and delta.
struct DepthGrid {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Array3i> cells;  // the grid index of each point
  std::vector<double> depth;
  std::size_t grid_points = 0, inside = 0;
  double delta = 0.0;
  Eigen::Vector3d origin, cell;  // centre (i, j, k) is origin + (i + 1/2, j + 1/2, k + 1/2) cell
  Eigen::Array3i n;              // cells along each axis
};

// Which centres count: inside ones, and on an open mesh (\p band) their 26 neighbours.
std::vector<char> counted_centres(const std::vector<double>& w, const Eigen::Array3i& n,
                                  bool band) {
  std::vector<char> in(w.size());
  for (std::size_t i = 0; i < w.size(); ++i) in[i] = w[i] > 0.5;
  if (!band) return in;
  std::vector<char> out = in;
  const auto at = [&](int i, int j, int k) {
    return static_cast<std::size_t>((i * n[1] + j) * n[2] + k);
  };
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int k = 0; k < n[2]; ++k) {
        if (!in[at(i, j, k)]) continue;
        for (int a = std::max(0, i - 1); a <= std::min(n[0] - 1, i + 1); ++a)
          for (int b = std::max(0, j - 1); b <= std::min(n[1] - 1, j + 1); ++b)
            for (int c = std::max(0, k - 1); c <= std::min(n[2] - 1, k + 1); ++c)
              out[at(a, b, c)] = 1;
      }
  return out;
}

DepthGrid depth_grid(const MeshQuery& query, int resolution, bool closed, int threads) {
  const Eigen::AlignedBox3d box = query.mesh().bounds();
  const Eigen::Vector3d size = box.sizes();
  const double s = size.maxCoeff() / resolution;
  Eigen::Array3i n;
  Eigen::Vector3d cell;
  for (int a = 0; a < 3; ++a) {
    n[a] = std::max(1, static_cast<int>(std::ceil(size[a] / s)));
    cell[a] = size[a] / n[a];
  }
  std::vector<Eigen::Vector3d> centres;
  centres.reserve(static_cast<std::size_t>(n.prod()));
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int k = 0; k < n[2]; ++k)
        centres.push_back(box.min() +
                          Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5).cwiseProduct(cell));
  std::vector<double> w = query.winding_numbers(centres, threads);
  const long long count = closed ? static_cast<long long>(centres.size()) : 0;
#pragma omp parallel for schedule(dynamic, 64) num_threads(thread_count(threads))
  for (long long i = 0; i < count; ++i) {
    double& v = w[static_cast<std::size_t>(i)];
    v = settled_winding(query, centres[static_cast<std::size_t>(i)], v);
  }
  const std::vector<char> counted = counted_centres(w, n, !closed);
  DepthGrid g;
  g.grid_points = centres.size();
  g.inside =
      static_cast<std::size_t>(std::count_if(w.begin(), w.end(), [](double v) { return v > 0.5; }));
  g.delta = 0.5 * cell.norm();
  g.origin = box.min();
  g.cell = cell;
  g.n = n;
  for (std::size_t i = 0; i < centres.size(); ++i)
    if (counted[i]) {
      g.points.push_back(centres[i]);
      const int c = static_cast<int>(i);
      g.cells.emplace_back(c / (n[1] * n[2]), c / n[2] % n[1], c % n[2]);
    }
  for (const ClosestPoint& c : query.closest_points(g.points, threads))
    g.depth.push_back(c.distance());
  return g;
}

// The first index of the largest gap in [begin, end).
std::size_t farthest(const std::vector<double>& gap, std::size_t begin, std::size_t end) {
  return static_cast<std::size_t>(std::max_element(gap.begin() + static_cast<long>(begin),
                                                   gap.begin() + static_cast<long>(end)) -
                                  gap.begin());
}

// The candidate witnesses: farthest-point sampling of the surface samples and vertices (one
// fused pass per point chosen, split over \p threads; ties to the first index, so the same
// points for every thread count).
std::vector<Eigen::Vector3d> candidates(const TriangleMesh& mesh, std::size_t count,
                                        std::uint64_t seed, int threads) {
  const std::vector<Eigen::Vector3d> pool =
      sample_surface(mesh, kSamplesPerCandidate * count, seed).points;
  const Eigen::Vector3d centre = mesh.bounds().center();
  std::vector<double> gap(pool.size());
  for (std::size_t i = 0; i < pool.size(); ++i) gap[i] = (pool[i] - centre).squaredNorm();
  std::size_t next = farthest(gap, 0, gap.size());
  std::vector<Eigen::Vector3d> out;
  const int parts = pool.size() < 65536 ? 1 : thread_count(threads);
  std::vector<std::size_t> best(static_cast<std::size_t>(parts));
  while (out.size() < std::min(count, pool.size())) {
    if (!out.empty() && !(gap[next] > 0.0)) break;  // only repeated points are left
    out.push_back(pool[next]);
    const Eigen::Vector3d x = pool[next];
#pragma omp parallel for schedule(static, 1) num_threads(parts) if (parts > 1)
    for (int part = 0; part < parts; ++part) {
      const std::size_t begin = pool.size() * static_cast<std::size_t>(part) / parts,
                        end = pool.size() * static_cast<std::size_t>(part + 1) / parts;
      for (std::size_t i = begin; i < end; ++i)
        gap[i] = std::min(gap[i], (pool[i] - x).squaredNorm());
      best[static_cast<std::size_t>(part)] = farthest(gap, begin, end);
    }
    next = best[0];
    for (std::size_t b : best)
      if (gap[b] > gap[next]) next = b;
  }
  return out;
}

// Step 4's bound on rho for every candidate (step 7's on an open mesh), and step 2's m.
class DepthProfiles {
 public:
  DepthProfiles(const DepthGrid& grid, const std::vector<Eigen::Vector3d>& points, double diagonal,
                bool penalized, int threads)
      : delta_(grid.delta), bin_(0.5 * grid.delta) {
    bins_ = static_cast<std::size_t>((diagonal + 2.0 * delta_) / bin_) + 2;
    table_.assign(points.size() * bins_, 0.0);  // 0: the max(0, ...) of step 4
    const long long n = static_cast<long long>(points.size());
#pragma omp parallel for schedule(dynamic, 8) num_threads(thread_count(threads))
    for (long long i = 0; i < n; ++i)
      fill(grid, points[static_cast<std::size_t>(i)], penalized,
           &table_[static_cast<std::size_t>(i) * bins_]);
  }

  // An upper bound on rho(x_i, h) (step 4).
  double rho(std::size_t i, double h) const {
    const double reach = (h + delta_) * (1.0 + 1e-12) / bin_;
    const std::size_t b =
        reach < static_cast<double>(bins_ - 1) ? static_cast<std::size_t>(reach) : bins_ - 1;
    return std::min(h, table_[i * bins_ + b] + delta_);
  }

  // m(x_i, x_j) of step 2 with \p h = |x_i - x_j| / 2.
  double pair(std::size_t i, std::size_t j, double h) const {
    return h - std::min(rho(i, h), rho(j, h));
  }

 private:
  // Row j of x: the largest depth of a counted centre in bins 0 to j, and with \p penalized
  // also (depth - (b - j - 1) w) over the bins b > j (step 7).
  void fill(const DepthGrid& grid, const Eigen::Vector3d& x, bool penalized, double* row) const {
    for (std::size_t g = 0; g < grid.points.size(); ++g) {
      const std::size_t b =
          std::min(bins_ - 1, static_cast<std::size_t>((grid.points[g] - x).norm() / bin_));
      row[b] = std::max(row[b], grid.depth[g]);
    }
    std::vector<double> beyond(bins_, 0.0);  // beyond[j]: max over b > j of row[b] - (b-j-1) w
    for (std::size_t j = bins_ - 1; j-- > 0;)
      beyond[j] = std::max(row[j + 1], beyond[j + 1] - bin_);
    for (std::size_t j = 1; j < bins_; ++j) row[j] = std::max(row[j], row[j - 1]);
    if (penalized)
      for (std::size_t j = 0; j < bins_; ++j) row[j] = std::max(row[j], beyond[j]);
  }

  double delta_, bin_;
  std::size_t bins_ = 0;
  std::vector<double> table_;
};

// Step 8's m*: the counted centres in blocks of 4^3 cells, each block with a bounding ball
// and its largest depth, for a branch-and-bound minimum over the centres.
class CentreBlocks {
 public:
  explicit CentreBlocks(const DepthGrid& grid)
      : delta_(grid.delta),
        origin_(grid.origin),
        side_(kBlock * grid.cell),
        n_((grid.n + kBlock - 1) / kBlock) {
    const auto block = [&](std::size_t i) {
      const Eigen::Array3i b = grid.cells[i] / kBlock;
      return static_cast<std::size_t>((b[0] * n_[1] + b[1]) * n_[2] + b[2]);
    };
    std::vector<std::size_t> order(grid.points.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return block(a) < block(b); });
    slot_.assign(static_cast<std::size_t>(n_.prod()), -1);
    for (std::size_t k = 0; k < order.size(); ++k) {
      if (k == 0 || block(order[k]) != block(order[k - 1])) {
        slot_[block(order[k])] = static_cast<int>(blocks_.size());
        blocks_.push_back({Eigen::Vector3d::Zero(), 0.0, 0.0, k, k});
      }
      points_.push_back(grid.points[order[k]]);
      depth_.push_back(grid.depth[order[k]]);
      blocks_.back().end = k + 1;
      deepest_ = std::max(deepest_, depth_.back());
    }
    for (Block& b : blocks_) {
      Eigen::AlignedBox3d box;
      for (std::size_t k = b.begin; k < b.end; ++k) {
        box.extend(points_[k]);
        b.depth = std::max(b.depth, depth_[k]);
      }
      b.centre = box.center();
      for (std::size_t k = b.begin; k < b.end; ++k)
        b.radius = std::max(b.radius, (points_[k] - b.centre).norm());
    }
  }

  // m*(x, y) of step 8 with h = |x - y| / 2. Only centres g with v(g) < h can lower the
  // result below h - delta; they lie within R = h + delta + the largest depth of both x and
  // y, so only the blocks meeting that box are visited, and of them those whose bounding
  // ball and depth allow a smaller value.
  double pair(const Eigen::Vector3d& x, const Eigen::Vector3d& y, double h) const {
    const double R = h + delta_ + deepest_;
    const Eigen::Vector3d lo = (x.array() - R).max(y.array() - R).matrix();
    const Eigen::Vector3d hi = (x.array() + R).min(y.array() + R).matrix();
    Eigen::Array3i a, z;
    for (int k = 0; k < 3; ++k) {
      if (!(lo[k] <= hi[k])) return h - delta_;
      if (!(side_[k] > 0.0)) {  // a flat box: one block along this axis
        a[k] = 0;
        z[k] = n_[k] - 1;
        continue;
      }
      const double first = std::floor((lo[k] - origin_[k]) / side_[k]) - 1.0;
      const double last = std::floor((hi[k] - origin_[k]) / side_[k]) + 1.0;
      a[k] = static_cast<int>(std::clamp(first, 0.0, static_cast<double>(n_[k] - 1)));
      z[k] = static_cast<int>(std::clamp(last, 0.0, static_cast<double>(n_[k] - 1)));
    }
    const Eigen::Vector3d mid = 0.5 * (x + y);
    double best = h;
    for (int i = a[0]; i <= z[0]; ++i)
      for (int j = a[1]; j <= z[1]; ++j)
        for (int k = a[2]; k <= z[2]; ++k) {
          const int b = slot_[static_cast<std::size_t>((i * n_[1] + j) * n_[2] + k)];
          if (b < 0) continue;
          const Block& q = blocks_[static_cast<std::size_t>(b)];
          const double far =
              std::max(detail::distance(x, q.centre), detail::distance(y, q.centre)) - q.radius;
          const double off = std::max(0.0, detail::distance(mid, q.centre) - q.radius - delta_);
          if (std::max(far - delta_, std::sqrt(h * h + off * off)) - q.depth < best)
            best = scan(q, x, y, mid, h, best);
        }
    return std::min(h - delta_, best - delta_);
  }

  // The largest depth of a counted centre.
  double deepest() const { return deepest_; }

 private:
  static constexpr int kBlock = 4;
  struct Block {
    Eigen::Vector3d centre;
    double radius, depth;
    std::size_t begin, end;
  };

  // min(best, v(g) over the block's centres), v of step 8.
  double scan(const Block& b, const Eigen::Vector3d& x, const Eigen::Vector3d& y,
              const Eigen::Vector3d& mid, double h, double best) const {
    for (std::size_t k = b.begin; k < b.end; ++k) {
      const Eigen::Vector3d& g = points_[k];
      const double off = std::max(0.0, detail::distance(g, mid) - delta_);
      const double reach =
          std::max(std::max(detail::distance(g, x), detail::distance(g, y)) - delta_,
                   std::sqrt(h * h + off * off));
      best = std::min(best, reach - depth_[k]);
    }
    return best;
  }

  double delta_, deepest_ = 0.0;
  Eigen::Vector3d origin_, side_;
  Eigen::Array3i n_;
  std::vector<int> slot_;  // block (i, j, k) -> index into blocks_, -1 when empty
  std::vector<Eigen::Vector3d> points_;
  std::vector<double> depth_;
  std::vector<Block> blocks_;
};

// The bound of a pair of candidates: max(m, m*) lowered by the rounding slack (steps 2, 5
// and 8).
class PairBound {
 public:
  PairBound(const DepthProfiles& rho, const CentreBlocks& blocks,
            const std::vector<Eigen::Vector3d>& points, double slack)
      : rho_(rho), blocks_(blocks), points_(points), slack_(slack) {}

  double pair(std::size_t i, std::size_t j) const {
    const double h = 0.5 * (points_[i] - points_[j]).norm();
    return std::max(rho_.pair(i, j, h), blocks_.pair(points_[i], points_[j], h)) - slack_;
  }

  std::size_t size() const { return points_.size(); }
  const Eigen::Vector3d& point(std::size_t i) const { return points_[i]; }

 private:
  const DepthProfiles& rho_;
  const CentreBlocks& blocks_;
  const std::vector<Eigen::Vector3d>& points_;
  double slack_;
};

// The least bound over the pairs of \p chosen but position \p skip, from their matrix.
struct WorstPair {
  double value = std::numeric_limits<double>::infinity();
  std::size_t a = 0, b = 0;  // positions in chosen
};

WorstPair worst_pair(const std::vector<std::vector<double>>& pairs, std::size_t skip) {
  WorstPair w;
  for (std::size_t a = 0; a < pairs.size(); ++a)
    for (std::size_t b = a + 1; b < pairs.size(); ++b)
      if (a != skip && b != skip && pairs[a][b] < w.value) w = {pairs[a][b], a, b};
  return w;
}

// The candidate not in \p chosen whose least bound to the chosen points but position \p skip
// is largest (ties: lowest index), with that value. In parallel over the candidates: each
// thread stops a candidate's minimum once it falls strictly below the best value the thread
// has seen, so every candidate whose value reaches the overall best is computed exactly and
// the choice does not depend on the threads.
std::pair<std::size_t, double> best_addition(const PairBound& m,
                                             const std::vector<std::size_t>& chosen,
                                             std::size_t skip, int threads) {
  std::vector<char> taken(m.size(), 0);
  for (std::size_t c : chosen) taken[c] = 1;
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  std::vector<double> value(m.size(), kNone);
  const long long n = static_cast<long long>(m.size());
#pragma omp parallel num_threads(threads)
  {
    double seen = kNone;
#pragma omp for schedule(static)
    for (long long q = 0; q < n; ++q) {
      const std::size_t p = static_cast<std::size_t>(q);
      if (taken[p]) continue;
      double v = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < chosen.size() && !(v < seen); ++k)
        if (k != skip) v = std::min(v, m.pair(p, chosen[k]));
      value[p] = v;
      seen = std::max(seen, v);
    }
  }
  std::pair<std::size_t, double> best{m.size(), kNone};
  for (std::size_t p = 0; p < m.size(); ++p)
    if (!taken[p] && value[p] > best.second) best = {p, value[p]};
  return best;
}

// Greedy max-min from candidate \p first (file comment), lazily: a candidate's least bound
// to the chosen points only falls as points are added, so the candidate with the largest
// stale value is brought up to date, and taken when it stays on top (ties: lowest index).
// Returns the chosen candidates; fewer than \p count when the candidates run out.
std::vector<std::size_t> greedy_witnesses(const PairBound& m, std::size_t first,
                                          std::size_t count) {
  std::vector<std::size_t> chosen{first};
  std::vector<double> least(m.size(), std::numeric_limits<double>::infinity());
  std::vector<std::size_t> upto(m.size(), 0);  // chosen points least[p] accounts for
  using Entry = std::pair<double, std::size_t>;
  const auto below = [](const Entry& a, const Entry& b) {
    return a.first < b.first || (a.first == b.first && a.second > b.second);
  };
  std::priority_queue<Entry, std::vector<Entry>, decltype(below)> heap(below);
  for (std::size_t p = 0; p < m.size(); ++p)
    if (p != first) heap.push({least[p], p});
  while (chosen.size() < count && !heap.empty()) {
    const std::size_t p = heap.top().second;
    heap.pop();
    if (upto[p] == chosen.size()) {
      chosen.push_back(p);
      continue;
    }
    for (; upto[p] < chosen.size(); ++upto[p])
      least[p] = std::min(least[p], m.pair(p, chosen[upto[p]]));
    heap.push({least[p], p});
  }
  return chosen;
}

// The least bound over the pairs of \p chosen.
double least_pair(const PairBound& m, const std::vector<std::size_t>& chosen) {
  double v = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < chosen.size(); ++a)
    for (std::size_t b = a + 1; b < chosen.size(); ++b)
      v = std::min(v, m.pair(chosen[a], chosen[b]));
  return v;
}

// Single swaps (file comment), at most 2 |chosen| of them; returns the least bound over pairs.
double swap_witnesses(const PairBound& m, std::vector<std::size_t>& chosen, int threads) {
  const std::size_t n = chosen.size();
  std::vector<std::vector<double>> pairs(n, std::vector<double>(n, 0.0));
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b)
      pairs[a][b] = pairs[b][a] = m.pair(chosen[a], chosen[b]);
  WorstPair w = worst_pair(pairs, n);
  for (std::size_t pass = 0; pass < 2 * n; ++pass) {
    bool improved = false;
    for (std::size_t drop : {w.a, w.b}) {
      const auto [p, v] = best_addition(m, chosen, drop, threads);
      if (p == m.size() || !(std::min(v, worst_pair(pairs, drop).value) > w.value)) continue;
      chosen[drop] = p;
      for (std::size_t k = 0; k < n; ++k)
        if (k != drop) pairs[drop][k] = pairs[k][drop] = m.pair(p, chosen[k]);
      w = worst_pair(pairs, n);
      improved = true;
      break;
    }
    if (!improved) break;
  }
  return w.value;
}

// Step 9: branch and bound on min_c phi(c) for one pair of witnesses, over boxes (cells)
// that partition the part of the mesh's box where phi can fall below h.
class PairRefinement {
 public:
  PairRefinement(const MeshQuery& query, bool closed, const Eigen::Vector3d& x,
                 const Eigen::Vector3d& y, double deepest, const Eigen::AlignedBox3d& box)
      : query_(query),
        closed_(closed),
        x_(x),
        y_(y),
        mid_(0.5 * (x + y)),
        h_(0.5 * (x - y).norm()) {
    const double R = h_ + deepest;
    const Eigen::Vector3d lo = (x.array() - R).max(y.array() - R).max(box.min().array()).matrix();
    const Eigen::Vector3d hi = (x.array() + R).min(y.array() + R).min(box.max().array()).matrix();
    if ((lo.array() <= hi.array()).all()) add(0.5 * (lo + hi), 0.5 * (hi - lo));
  }

  // min(h, the least value of a cell): a lower bound on phi over all space.
  double bound() const { return cells_.empty() ? h_ : std::min(h_, cells_.top().value); }

  // Splits the cell of least value into 8; false when it is already below \p finest across.
  bool split(double finest) {
    if (cells_.empty() || cells_.top().half.norm() < finest) return false;
    const Cell c = cells_.top();
    cells_.pop();
    const Eigen::Vector3d e = 0.5 * c.half;
    for (int k = 0; k < 8; ++k)
      add(c.centre + Eigen::Vector3d(k & 1 ? e.x() : -e.x(), k & 2 ? e.y() : -e.y(),
                                     k & 4 ? e.z() : -e.z()),
          e);
    return true;
  }

  std::size_t queries() const { return queries_; }

 private:
  struct Cell {
    Eigen::Vector3d centre, half;
    double value;
    bool operator<(const Cell& o) const { return value > o.value; }  // least on top
  };

  // The value of the cell (step 9); kept only below h.
  void add(const Eigen::Vector3d& g, const Eigen::Vector3d& half) {
    ++queries_;
    const double r = half.norm(), d = query_.closest_point(g).distance();
    double w = query_.winding_number(g);
    if (closed_) w = settled_winding(query_, g, w);
    if (!(w > 0.5) && d > r) return;  // the whole cell is outside the solid: phi >= h
    const double off = std::max(0.0, (g - mid_).norm() - r);
    const double reach =
        std::max(std::max((g - x_).norm(), (g - y_).norm()) - r, std::sqrt(h_ * h_ + off * off));
    const double value = reach - d - r;
    if (value < h_) cells_.push({g, half, value});
  }

  const MeshQuery& query_;
  bool closed_;
  Eigen::Vector3d x_, y_, mid_;
  double h_;
  std::priority_queue<Cell> cells_;
  std::size_t queries_ = 0;
};

// Step 9 over the witnesses' pairs: the pair of least bound (its coarse bound, or its
// refinement's once that is higher) is refined, cell by cell, until \p budget queries are
// spent or its cells are below \p finest. Returns the least bound over pairs.
double refine_pairs(const MeshQuery& query, bool closed, const PairBound& m,
                    const std::vector<std::size_t>& chosen, double deepest, double slack,
                    std::size_t budget, double finest) {
  const Eigen::AlignedBox3d box = query.mesh().bounds();
  struct Pair {
    std::size_t a, b;
    double coarse;
    std::unique_ptr<PairRefinement> fine;
    bool done = false;
  };
  std::vector<Pair> pairs;
  for (std::size_t a = 0; a < chosen.size(); ++a)
    for (std::size_t b = a + 1; b < chosen.size(); ++b)
      pairs.push_back({a, b, m.pair(chosen[a], chosen[b]), nullptr});
  const auto value = [&](const Pair& p) {
    return p.fine ? std::max(p.coarse, p.fine->bound() - slack) : p.coarse;
  };
  std::size_t spent = 0;
  while (spent < budget) {
    Pair* worst = nullptr;
    for (Pair& p : pairs)
      if (!worst || value(p) < value(*worst)) worst = &p;
    if (!worst || worst->done) break;
    if (!worst->fine) {
      worst->fine = std::make_unique<PairRefinement>(query, closed, m.point(chosen[worst->a]),
                                                     m.point(chosen[worst->b]), deepest, box);
      spent += worst->fine->queries();
    } else {
      const std::size_t before = worst->fine->queries();
      worst->done = !worst->fine->split(finest);
      spent += worst->fine->queries() - before;
    }
  }
  double least = std::numeric_limits<double>::infinity();
  for (const Pair& p : pairs) least = std::min(least, value(p));
  return least;
}

}  // namespace

CoverLowerBound cover_protrusion_lower_bound(const MeshQuery& query, std::size_t budget,
                                             const CoverLowerBoundOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  check_input(query, budget, options);
  const TriangleMesh& mesh = query.mesh();
  const Eigen::AlignedBox3d box = mesh.bounds();
  const double L = box.sizes().maxCoeff();
  const double X = std::max(box.min().cwiseAbs().maxCoeff(), box.max().cwiseAbs().maxCoeff());
  const bool closed = solid_volume(mesh).has_value();
  const DepthGrid grid = depth_grid(query, options.resolution, closed, options.threads);
  const std::vector<Eigen::Vector3d> points = candidates(
      mesh, std::max(options.candidates, 4 * (budget + 1)), options.seed, options.threads);
  const DepthProfiles rho(grid, points, box.diagonal().norm(), !closed, options.threads);
  const CentreBlocks blocks(grid);
  const PairBound m(rho, blocks, points, 4.0 * cover_radius_slack(L, X));

  CoverLowerBound out;
  out.grid_points = grid.grid_points;
  out.inside_points = grid.inside;
  out.closed = closed;
  out.cell_reach = grid.delta;
  const std::size_t starts = std::min(points.size(), static_cast<std::size_t>(options.starts));
  std::vector<std::vector<std::size_t>> chosen(starts);
  std::vector<double> value(starts, -std::numeric_limits<double>::infinity());
  const long long n = static_cast<long long>(starts);
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count(options.threads))
  for (long long s = 0; s < n; ++s) {
    const std::size_t k = static_cast<std::size_t>(s);
    chosen[k] = greedy_witnesses(m, k, budget + 1);
    if (chosen[k].size() == budget + 1) value[k] = least_pair(m, chosen[k]);
  }
  const std::size_t best =
      static_cast<std::size_t>(std::max_element(value.begin(), value.end()) - value.begin());
  if (chosen[best].size() == budget + 1) {
    out.bound = swap_witnesses(m, chosen[best], thread_count(options.threads));
    if (options.refine_queries > 0)
      out.bound = refine_pairs(query, closed, m, chosen[best], blocks.deepest() + grid.delta,
                               4.0 * cover_radius_slack(L, X), options.refine_queries, 1e-4 * L);
    out.bound = std::max(0.0, out.bound);
    for (std::size_t c : chosen[best]) out.witnesses.push_back(points[c]);
  }
  out.pair_bound = out.bound;
  if (options.count_queries > 0) {
    const detail::CountBound c = detail::count_lower_bound(
        query, closed, budget,
        candidates(mesh, options.count_witnesses, options.seed, options.threads),
        {&grid.points, &grid.depth}, out.witnesses,
        options.count_even_witnesses > 0
            ? candidates(mesh, options.count_even_witnesses, options.seed, options.threads)
            : std::vector<Eigen::Vector3d>{},
        4.0 * cover_radius_slack(L, X), options.count_queries, options.count_passes,
        options.threads);
    out.count_bound = c.bound;
    out.count_points = c.points;
    out.count_weights = c.weights;
    out.bound = std::max(out.bound, c.bound);
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace medspheres
