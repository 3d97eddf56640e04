// The covering bake to a budget (cover.h).
//
// Why these steps. A covering ball must hold whole pieces of the surface; the least it can
// stick out is set by the patch it holds, so the problem is one of partitioning the
// surface into K patches and fitting each with its smallest ball: a k-center problem on
// the surface, for which farthest-point sampling is the classical 2-approximation (step 2)
// and alternating assignment and minimum-enclosing-ball refits the Lloyd-like local
// improvement (step 3). Interior points join the patches so that a patch's ball is pulled
// into the solid rather than centred on a flat face: a ball centred at depth t under a
// flat patch of radius R sticks out by sqrt(R^2 + t^2) - t, less than the R of a ball
// centred on the face. The elements are the pieces of the certificate's own midpoint
// subdivision, so a ball that holds an element's three computed corners with a margin
// above the certificate's rounding allowance certifies it (step 5 rarely has anything to
// repair).
//
// Why step 4c. Steps 3 to 4b minimise the union's volume; the largest protrusion is a
// bottleneck they do not see: one ball over a thin fin or a corner sticks out far while
// the rest fit closely. With the protrusion of a ball at c holding a point p written as
// |p - c| - D(c), the least largest protrusion of K balls is a k-center problem under an
// additively weighted distance: the threshold search with a greedy set cover gives a
// global start (a log-factor approximation of the bottleneck), and the minimax rounds
// (weighted Voronoi assignment, then each centre moved to lower its own protrusion) the
// local improvement, the analogue of step 3 for the largest protrusion.
#include "medspheres/cover/cover.h"

#include "cover_threshold.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "medspheres/measure/fit_metrics.h"
#include "medspheres/measure/union_volume.h"
#include "medspheres/mesh/threads.h"
#include "medspheres/min_enclosing_ball.h"

namespace medspheres {

namespace {

constexpr int kMaxElementDepth = 5;
constexpr double kElementCap = 40000.0;
// Patches (step 1b): at most max(kPatchFloor, kPatchesPerBall K) on the surface.
constexpr double kPatchFloor = 1500.0;
constexpr double kPatchesPerBall = 60.0;
constexpr double kFinePatchFloor = 4000.0;  // step 4c

// Constraint points and the elements made of them: elements [0, surface) are surface
// pieces (three point indices), the rest interior points (one index, thrice).
// Patches (step 1b) are elements too, without points: each is the ball (centroid, reach)
// that holds the points of the fine elements it stands for.
struct Elements {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> items;  // empty for patches
  std::vector<Eigen::Vector3d> centroids;
  std::vector<double> reach;  // largest centroid-corner distance
  std::size_t surface = 0;
  double element_size = 0.0;  // the surface elements' target length
  bool patches() const { return items.empty(); }
  std::size_t size() const { return centroids.size(); }
};

void push_element(Elements& e, int a, int b, int c) {
  e.items.push_back({a, b, c});
  const Eigen::Vector3d g = (e.points[a] + e.points[b] + e.points[c]) / 3.0;
  e.centroids.push_back(g);
  e.reach.push_back(
      std::max({(e.points[a] - g).norm(), (e.points[b] - g).norm(), (e.points[c] - g).norm()}));
}

// The lattice of midpoint subdivision at depth d: the points w0 a + w1 b + w2 c with
// weights (n - i - j, i, j) / n, n = 2^d, and its n^2 triangles.
void subdivide(Elements& e, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
               const Eigen::Vector3d& c, int d) {
  const int n = 1 << d;
  const int base = static_cast<int>(e.points.size());
  std::vector<int> row_start(static_cast<std::size_t>(n) + 2);
  for (int i = 0, k = base; i <= n; ++i) {
    row_start[static_cast<std::size_t>(i)] = k;
    for (int j = 0; i + j <= n; ++j, ++k) {
      const double w1 = static_cast<double>(i) / n, w2 = static_cast<double>(j) / n;
      const double w0 = static_cast<double>(n - i - j) / n;
      e.points.push_back(a * w0 + b * w1 + c * w2);
    }
  }
  auto at = [&](int i, int j) { return row_start[static_cast<std::size_t>(i)] + j; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      push_element(e, at(i, j), at(i + 1, j), at(i, j + 1));
      if (i + j + 1 < n) push_element(e, at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
    }
}

// The centres of the cells of side \p cell of a grid from the corner of \p box.
std::vector<Eigen::Vector3d> cell_centres(const Eigen::AlignedBox3d& box, double cell) {
  std::vector<Eigen::Vector3d> grid;
  for (double x = box.min().x() + 0.5 * cell; x < box.max().x(); x += cell)
    for (double y = box.min().y() + 0.5 * cell; y < box.max().y(); y += cell)
      for (double z = box.min().z() + 0.5 * cell; z < box.max().z(); z += cell)
        grid.emplace_back(x, y, z);
  return grid;
}

Elements make_elements(const MeshQuery& query, std::size_t budget, const CoverOptions& o) {
  const TriangleMesh& mesh = query.mesh();
  const Eigen::AlignedBox3d box = mesh.bounds();
  const double L = box.sizes().maxCoeff();
  // Element size: about L / (2 + 3 sqrt K), coarsened (by 1.5 at a time) until there are
  // at most max(2 triangles, kElementCap) elements: beyond that, finer elements cost time
  // and gain little.
  std::vector<double> edge(mesh.num_triangles());
  for (std::size_t t = 0; t < edge.size(); ++t) {
    const Eigen::Vector3d &a = mesh.corner(t, 0), &b = mesh.corner(t, 1), &c = mesh.corner(t, 2);
    edge[t] = std::max({(a - b).norm(), (b - c).norm(), (c - a).norm()});
  }
  auto depth = [](double length, double size) {
    int d = 0;
    while (d < kMaxElementDepth && length > size * (1 << d)) ++d;
    return d;
  };
  double h = L / (2.0 + 3.0 * std::sqrt(static_cast<double>(budget)));
  const double cap = std::max(2.0 * static_cast<double>(mesh.num_triangles()), kElementCap);
  for (;;) {
    double count = 0.0;
    for (double l : edge) count += std::pow(4.0, depth(l, h));
    if (count <= cap) break;
    h *= 1.5;
  }
  Elements e;
  e.element_size = h;
  e.points = mesh.vertices;
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
    const int d = depth(edge[t], h);
    if (d == 0)
      push_element(e, mesh.triangles[t][0], mesh.triangles[t][1], mesh.triangles[t][2]);
    else
      subdivide(e, mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2), d);
  }
  e.surface = e.items.size();
  if (o.interior_resolution <= 0) return e;
  const std::vector<Eigen::Vector3d> grid = cell_centres(box, L / o.interior_resolution);
  const std::vector<double> w = query.winding_numbers(grid, o.threads);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (!(w[i] > 0.5)) continue;
    const int k = static_cast<int>(e.points.size());
    e.points.push_back(grid[i]);
    push_element(e, k, k, k);
  }
  return e;
}

// The growth ball (c, r) needs to hold element i: max over its points of |p - c| - r.
// The distance from c to the farthest point of element i (of its ball, for a patch).
double farthest(const Elements& e, std::size_t i, const Eigen::Vector3d& c) {
  if (e.patches()) return (e.centroids[i] - c).norm() + e.reach[i];
  double m = 0.0;
  for (int p : e.items[i]) m = std::max(m, (e.points[static_cast<std::size_t>(p)] - c).norm());
  return m;
}

double need(const Elements& e, std::size_t i, const Sphere& b) {
  return farthest(e, i, b.center) - b.radius;
}

// Step 1b. The surface elements grouped by the cell (side \p cell) of a grid that holds
// their centroid; each group becomes one patch, the ball about its points' bounding box
// that holds them. Interior points stay patches of their own. Patches are numbered by
// their first element, so the grouping depends on nothing but the elements.
struct Patching {
  Elements patches;
  std::vector<int> patch_of;  // per element
};

// The grid cell of side \p cell that holds g (21 bits per axis).
std::uint64_t cell_key(const Eigen::Vector3d& g, const Eigen::Vector3d& origin, double cell) {
  std::uint64_t key = 0;
  for (int a = 0; a < 3; ++a)
    key = key << 21 |
          (static_cast<std::uint64_t>(std::max(0.0, std::floor((g[a] - origin[a]) / cell))) &
           0x1FFFFF);
  return key;
}

Patching make_patches(const Elements& e, double cell, const Eigen::Vector3d& origin) {
  Patching out;
  out.patch_of.resize(e.size());
  std::unordered_map<std::uint64_t, int> index;
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < e.size(); ++i) {
    const std::uint64_t key = cell_key(e.centroids[i], origin, cell);
    const int fresh = static_cast<int>(groups.size());
    const int g = i < e.surface ? index.emplace(key, fresh).first->second : fresh;
    if (g == fresh) groups.emplace_back();
    groups[static_cast<std::size_t>(g)].push_back(i);
    out.patch_of[i] = g;
    if (i + 1 == e.surface) out.patches.surface = groups.size();
  }
  Elements& p = out.patches;
  for (const std::vector<std::size_t>& group : groups) {
    Eigen::AlignedBox3d box;
    for (std::size_t i : group)
      for (int q : e.items[i]) box.extend(e.points[static_cast<std::size_t>(q)]);
    const Eigen::Vector3d c = box.center();
    double r = 0.0;
    for (std::size_t i : group) r = std::max(r, farthest(e, i, c));
    p.centroids.push_back(c);
    p.reach.push_back(r * (1.0 + 4.0 * std::numeric_limits<double>::epsilon()));
  }
  return out;
}

// The side of the patch grid: half the element size, coarsened (by 1.25 at a time) until
// there are at most max(floor, kPatchesPerBall K) surface patches.
double patch_cell(const Elements& e, std::size_t budget, double element_size,
                  const Eigen::Vector3d& origin, double floor = kPatchFloor) {
  const double cap = std::max(floor, kPatchesPerBall * static_cast<double>(budget));
  std::unordered_map<std::uint64_t, char> seen;
  for (double cell = 0.5 * element_size;; cell *= 1.25) {
    seen.clear();
    for (std::size_t i = 0; i < e.surface && static_cast<double>(seen.size()) <= cap; ++i) {
      seen.emplace(cell_key(e.centroids[i], origin, cell), 1);
    }
    if (static_cast<double>(seen.size()) <= cap) return cell;
  }
}

// Each element to the centre whose farthest point of the element is nearest (ties: lowest
// index), a Voronoi assignment of whole elements. (Assigning by the growth a ball needs,
// which favours large balls, gave larger unions on most meshes tried.) The centroid
// bounds the farthest distance within |g - c| +- reach, which skips most centres.
// With \p depth (one per ball) the cost of centre j is that distance minus depth[j]: the
// protrusion ball j would need to hold the element (step 4c).
void assign(const Elements& e, const std::vector<Sphere>& balls, std::vector<int>& owner,
            int threads, const std::vector<double>& depth = {}) {
  const long long n = static_cast<long long>(e.size());
  owner.resize(e.size());
#pragma omp parallel num_threads(threads)
  {
    std::vector<double> lo(balls.size());
#pragma omp for schedule(static)
    for (long long ii = 0; ii < n; ++ii) {
      const std::size_t i = static_cast<std::size_t>(ii);
      double best_hi = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < balls.size(); ++j) {
        const double g =
            (e.centroids[i] - balls[j].center).norm() - (depth.empty() ? 0.0 : depth[j]);
        lo[j] = g - e.reach[i];
        best_hi = std::min(best_hi, g + e.reach[i]);
      }
      double best = std::numeric_limits<double>::infinity();
      int arg = 0;
      for (std::size_t j = 0; j < balls.size(); ++j) {
        if (lo[j] > best_hi || lo[j] >= best) continue;
        const double v = farthest(e, i, balls[j].center) - (depth.empty() ? 0.0 : depth[j]);
        if (v < best) {
          best = v;
          arg = static_cast<int>(j);
        }
      }
      owner[i] = arg;
    }
  }
}

// Farthest-point sampling of the centroids up to k centres, after the centres of \p start;
// for an empty start the first centre is centroid \p first.
std::vector<Sphere> seeds(const Elements& e, std::size_t k, std::vector<Sphere> start,
                          std::size_t first) {
  std::vector<double> d(e.centroids.size(), std::numeric_limits<double>::infinity());
  auto add = [&](const Eigen::Vector3d& c) {
    for (std::size_t i = 0; i < d.size(); ++i)
      d[i] = std::min(d[i], (e.centroids[i] - c).squaredNorm());
  };
  if (start.empty()) start.push_back({e.centroids[first], 0.0});
  for (const Sphere& b : start) add(b.center);
  std::vector<Sphere> out = std::move(start);
  while (out.size() < k) {
    const std::size_t far =
        static_cast<std::size_t>(std::max_element(d.begin(), d.end()) - d.begin());
    if (d[far] <= 0.0) break;  // fewer distinct centroids than k
    out.push_back({e.centroids[far], 0.0});
    add(e.centroids[far]);
  }
  return out;
}

// The first centre of start s: for s = 0 the centroid farthest from the mean of all; for
// s > 0 one drawn by a hash of (seed, s).
std::size_t first_seed(const Elements& e, std::uint64_t seed, int s) {
  if (s > 0) {
    std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(s);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;  // splitmix64 finaliser
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return static_cast<std::size_t>((z ^ (z >> 31)) % e.centroids.size());
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& g : e.centroids) mean += g;
  mean /= static_cast<double>(e.centroids.size());
  std::size_t far = 0;
  for (std::size_t i = 1; i < e.centroids.size(); ++i)
    if ((e.centroids[i] - mean).squaredNorm() > (e.centroids[far] - mean).squaredNorm()) far = i;
  return far;
}

// What a ball must hold to hold the elements in \p members: their distinct points (balls
// of radius 0), or for patches their balls.
std::vector<Sphere> atoms_of(const Elements& e, const std::vector<std::size_t>& members,
                             std::vector<char>& mark) {
  std::vector<Sphere> atoms;
  if (e.patches()) {
    for (std::size_t i : members) atoms.push_back({e.centroids[i], e.reach[i]});
    return atoms;
  }
  for (std::size_t i : members)
    for (int p : e.items[i])
      if (!mark[static_cast<std::size_t>(p)]) {
        mark[static_cast<std::size_t>(p)] = 1;
        atoms.push_back({e.points[static_cast<std::size_t>(p)], 0.0});
      }
  for (std::size_t i : members)
    for (int p : e.items[i]) mark[static_cast<std::size_t>(p)] = 0;
  return atoms;
}

// The radius that the ball centred at c needs to hold \p atoms.
double reach_from(const std::vector<Sphere>& atoms, const Eigen::Vector3d& c) {
  double r = 0.0;
  for (const Sphere& a : atoms) r = std::max(r, (a.center - c).norm() + a.radius);
  return r;
}

// The radius of a ball centred at c that holds \p atoms: reach_from, raised by 4 ulps so
// that the rounding of the distances never leaves an atom outside.
double holding_radius(const std::vector<Sphere>& atoms, const Eigen::Vector3d& c) {
  return reach_from(atoms, c) * (1.0 + 4.0 * std::numeric_limits<double>::epsilon());
}

// The minimum enclosing ball of the points of the elements in \p members, by a core set:
// the minimum ball of a subset (first the extreme points along the axes and the
// diagonals) is the answer once it holds every point; otherwise the farthest points
// outside join the subset. The subset stays small, so each exact solve is cheap.
Sphere fit(const Elements& e, const std::vector<std::size_t>& members, std::vector<char>& mark) {
  const std::vector<Sphere> pts = atoms_of(e, members, mark);
  std::vector<Sphere> core;
  static const double kDirections[13][3] = {
      {1, 0, 0}, {0, 1, 0},  {0, 0, 1}, {1, 1, 0},  {1, -1, 0}, {1, 0, 1}, {1, 0, -1},
      {0, 1, 1}, {0, 1, -1}, {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {-1, 1, 1}};
  for (const auto& d : kDirections) {
    const Eigen::Vector3d dir(d[0], d[1], d[2]);
    const double norm = dir.norm();
    auto low = [&](std::size_t i) { return pts[i].center.dot(dir) - pts[i].radius * norm; };
    auto high = [&](std::size_t i) { return pts[i].center.dot(dir) + pts[i].radius * norm; };
    std::size_t lo = 0, hi = 0;
    for (std::size_t i = 1; i < pts.size(); ++i) {
      if (low(i) < low(lo)) lo = i;
      if (high(i) > high(hi)) hi = i;
    }
    core.push_back(pts[lo]);
    core.push_back(pts[hi]);
  }
  for (;;) {
    const Sphere b = min_enclosing_ball(core);
    std::vector<std::pair<double, std::size_t>> out;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const double d = (pts[i].center - b.center).norm() + pts[i].radius;
      if (d > b.radius) out.emplace_back(-d, i);
    }
    if (out.empty()) return b;
    const std::size_t take = std::min<std::size_t>(out.size(), 32);
    std::partial_sort(out.begin(), out.begin() + static_cast<long>(take), out.end());
    for (std::size_t k = 0; k < take; ++k) core.push_back(pts[out[k].second]);
  }
}

std::vector<std::vector<std::size_t>> members_of(const std::vector<int>& owner, std::size_t k) {
  std::vector<std::vector<std::size_t>> m(k);
  for (std::size_t i = 0; i < owner.size(); ++i) m[static_cast<std::size_t>(owner[i])].push_back(i);
  return m;
}

double union_volume(const std::vector<Sphere>& balls) {
  std::vector<Sphere> s;
  for (const Sphere& b : balls)
    if (b.radius > 0.0) s.push_back({b.center, b.radius});
  return measure_union(s).volume;
}

// Step 3. An empty cluster is reseeded at the element that needs the most growth.
struct Clustering {
  std::vector<Sphere> balls;
  std::vector<int> owner;
  int rounds = 0, best_round = 0;
};

Clustering lloyd(const Elements& e, std::vector<Sphere> balls, const CoverOptions& o, int threads) {
  Clustering best;
  std::vector<int> owner;
  std::vector<char> mark(e.points.size(), 0);
  double best_volume = std::numeric_limits<double>::infinity();
  for (int round = 1; round <= o.rounds; ++round) {
    const std::vector<int> previous = owner;
    assign(e, balls, owner, threads);
    const auto members = members_of(owner, balls.size());
    for (std::size_t j = 0; j < balls.size(); ++j) {
      if (!members[j].empty()) {
        balls[j] = fit(e, members[j], mark);
        continue;
      }
      std::size_t worst = 0;
      double worst_need = -1.0;
      for (std::size_t i = 0; i < e.size(); ++i) {
        const double v = need(e, i, balls[static_cast<std::size_t>(owner[i])]);
        if (v > worst_need) worst_need = v, worst = i;
      }
      balls[j] = {e.centroids[worst], 0.0};
    }
    const bool full =
        std::none_of(members.begin(), members.end(), [](const auto& m) { return m.empty(); });
    best.rounds = round;
    if (full) {
      const double v = union_volume(balls);
      if (v < best_volume)
        best_volume = v, best.balls = balls, best.owner = owner, best.best_round = round;
    }
    if (full && owner == previous) break;
    if (round - best.best_round >= 4) break;  // no smaller union for four rounds
  }
  if (best.balls.empty()) best.balls = balls, best.owner = owner;  // every round had a hole
  return best;
}

}  // namespace

namespace {

bool holds(const Elements& e, std::size_t i, const Sphere& b) {
  const double reach = b.radius + e.reach[i];
  if ((e.centroids[i] - b.center).squaredNorm() > reach * reach) return false;
  return farthest(e, i, b.center) <= b.radius;
}

// The signed distance to the surface (positive inside) at a point y near x, whose own
// value px is known: the closest-point search starts from x's triangle, and when |y - x|
// < |px.depth| the segment xy does not meet the surface, so y is on x's side and no
// winding number is needed.
struct Probe {
  double depth = 0.0;
  int triangle = -1;
};

Probe probe(const MeshQuery& query, const Eigen::Vector3d& y, const Eigen::Vector3d& x,
            const Probe& px) {
  const ClosestPoint cp =
      px.triangle >= 0 ? query.closest_point(y, px.triangle) : query.closest_point(y);
  const double d = cp.distance();
  const bool in =
      px.triangle >= 0 && std::abs(px.depth) > (y - x).norm() ? px.depth > 0.0 : query.inside(y);
  return {in ? d : -d, cp.triangle};
}

// reach_from(atoms, y) for points y near a pivot x0, exactly, from a subset: an atom with
// |a - x0| + r_a < R(x0) - 2 delta (R the reach at x0) is nearer than R - delta to any y
// within delta of x0, while the atom farthest from x0 is at least that far from y; so
// only the others are scanned. The pivot moves (a full scan) when y leaves its delta
// ball or the asked delta falls below an eighth of the pivot's.
class FarthestAtoms {
 public:
  explicit FarthestAtoms(const std::vector<Sphere>& atoms) : atoms_(atoms) {}
  double operator()(const Eigen::Vector3d& y, double delta) {
    if (near_.empty() || delta > delta_ || 8.0 * delta < delta_ || (y - pivot_).norm() > delta_)
      pivot(y, delta);
    return reach_from(near_, y);
  }

 private:
  void pivot(const Eigen::Vector3d& x, double delta) {
    pivot_ = x, delta_ = delta;
    const double R = reach_from(atoms_, x);
    near_.clear();
    for (const Sphere& a : atoms_)
      if ((a.center - x).norm() + a.radius >= R - 2.0 * delta) near_.push_back(a);
  }
  const std::vector<Sphere>& atoms_;
  std::vector<Sphere> near_;
  Eigen::Vector3d pivot_ = Eigen::Vector3d::Zero();
  double delta_ = 0.0;
};

// Step 3b. The minimum enclosing ball is the smallest ball holding a patch, not the one
// that sticks out least: under a flat patch a centre at depth t sticks out by sqrt(R^2 +
// t^2) - t < R. A pattern search (the six axis steps, halved on failure, from \p first
// times the radius down to 1e-3 of it) moves each centre to lower its protrusion, the
// radius needed to hold its elements minus the depth of the centre; the radius is then
// the distance to the farthest point.
void deepen(const MeshQuery& query, const Elements& e, Clustering& c, int threads,
            double first = 0.25) {
  const auto members = members_of(c.owner, c.balls.size());
  const long long k = static_cast<long long>(c.balls.size());
#pragma omp parallel num_threads(threads)
  {
    std::vector<char> mark(e.points.size(), 0);
#pragma omp for schedule(dynamic, 1)
    for (long long jj = 0; jj < k; ++jj) {
      const std::size_t j = static_cast<std::size_t>(jj);
      if (members[j].empty()) continue;
      const std::vector<Sphere> pts = atoms_of(e, members[j], mark);
      FarthestAtoms reach(pts);
      Eigen::Vector3d x = c.balls[j].center;
      Probe px = probe(query, x, x, {});
      double fx = reach_from(pts, x) - px.depth;
      const double r = std::max(c.balls[j].radius, fx);
      for (double step = first * r; step > 1e-3 * r;) {
        bool moved = false;
        for (int axis = 0; axis < 6 && !moved; ++axis) {
          const Eigen::Vector3d y = x + (axis % 2 ? -step : step) * Eigen::Vector3d::Unit(axis / 2);
          const Probe py = probe(query, y, x, px);
          const double fy = reach(y, 4.0 * step) - py.depth;
          if (fy < fx) x = y, fx = fy, px = py, moved = true;
        }
        if (!moved) step *= 0.5;
      }
      c.balls[j] = {x, holding_radius(pts, x)};
    }
  }
}

// Step 4. Ball j gives up the elements another ball holds (they move to the first such
// ball) and keeps its centre, its radius shrunk to the farthest point it still holds; a
// ball left with nothing goes.
// Every element stays held by its owner throughout.
void shrink(const Elements& e, Clustering& c) {
  std::vector<char> mark(e.points.size(), 0);
  const std::size_t k = c.balls.size();
  for (int pass = 0; pass < 4; ++pass) {
    bool changed = false;
    auto members = members_of(c.owner, k);
    for (std::size_t j = 0; j < k; ++j) {
      if (members[j].empty()) continue;
      std::vector<std::size_t> keep;
      for (std::size_t i : members[j]) {
        std::size_t other = k;
        for (std::size_t m = 0; m < k && other == k; ++m)
          if (m != j && c.balls[m].radius > 0.0 && holds(e, i, c.balls[m])) other = m;
        if (other == k) {
          keep.push_back(i);
        } else {
          c.owner[i] = static_cast<int>(other);
          members[other].push_back(i);
        }
      }
      if (keep.size() == members[j].size()) continue;
      members[j] = keep;
      const double before = c.balls[j].radius;
      // The same centre, just large enough for what it keeps.
      c.balls[j].radius =
          keep.empty() ? 0.0 : holding_radius(atoms_of(e, keep, mark), c.balls[j].center);
      changed = changed || c.balls[j].radius < before;
    }
    if (!changed) break;
  }
}

// Steps 3 and 4 from the centres \p start.
Clustering optimise(const MeshQuery& query, const Elements& e, std::vector<Sphere> start,
                    const CoverOptions& o, int threads) {
  Clustering c = lloyd(e, std::move(start), o, threads);
  deepen(query, e, c, threads);
  shrink(e, c);
  return c;
}

// Step 4b. The elements follow the patches that stood for them (\p c clusters the
// patches); each ball is refitted as the minimum enclosing ball of its elements' points,
// then the inward moves of step 3 and the shrink of step 4 run on the elements themselves,
// whose points are tighter than the patches' balls. (So one ball is the same whatever the
// patches: the minimum ball of the surface, moved inward.)
Clustering follow(const MeshQuery& query, const Elements& e, const Patching& patching, Clustering c,
                  int threads) {
  std::vector<int> owner(e.size());
  for (std::size_t i = 0; i < e.size(); ++i)
    owner[i] = c.owner[static_cast<std::size_t>(patching.patch_of[i])];
  c.owner = std::move(owner);
  const auto members = members_of(c.owner, c.balls.size());
  std::vector<char> mark(e.points.size(), 0);
  for (std::size_t j = 0; j < c.balls.size(); ++j)
    c.balls[j] = members[j].empty() ? Sphere{c.balls[j].center, 0.0} : fit(e, members[j], mark);
  deepen(query, e, c, threads);
  shrink(e, c);
  return c;
}

// The live balls of \p c (radius > 0), their elements renumbered.
void drop_empty(Clustering& c) {
  std::vector<int> index(c.balls.size(), -1);
  std::vector<Sphere> live;
  for (std::size_t j = 0; j < c.balls.size(); ++j)
    if (c.balls[j].radius > 0.0)
      index[j] = static_cast<int>(live.size()), live.push_back(c.balls[j]);
  for (int& o : c.owner) o = std::max(0, index[static_cast<std::size_t>(o)]);
  c.balls = std::move(live);
}

// Step 4c, the rounds. Minimax rounds on the elements. Each element goes to the ball whose
// protrusion would need to grow least to hold it (its farthest point's distance to the
// centre minus the centre's depth; for fixed centres this assignment gives the least
// largest protrusion, as a Voronoi assignment gives the least largest radius), then each
// centre moves as in step 3b, starting from a tenth of its radius. The rounds stop when
// the largest protrusion drops by less than 1e-3 of itself; the best round is kept, then
// shrunk (step 4), which only lowers protrusions.
Clustering minimax(const MeshQuery& query, const Elements& e, Clustering c, int rounds,
                   int threads) {
  drop_empty(c);
  auto largest = [&](const std::vector<Sphere>& balls, std::vector<double>* depth) {
    const std::vector<double> p = sphere_protrusions(query, balls, threads);
    if (depth) {
      depth->resize(balls.size());
      for (std::size_t j = 0; j < balls.size(); ++j) (*depth)[j] = balls[j].radius - p[j];
    }
    return *std::max_element(p.begin(), p.end());
  };
  std::vector<double> depth;
  double best_p = largest(c.balls, &depth);
  Clustering best = c;
  for (int round = 0; round < rounds; ++round) {
    assign(e, c.balls, c.owner, threads, depth);
    const auto members = members_of(c.owner, c.balls.size());
    for (std::size_t j = 0; j < c.balls.size(); ++j)
      if (members[j].empty()) c.balls[j].radius = 0.0;
    deepen(query, e, c, threads, 0.1);
    drop_empty(c);
    const double p = largest(c.balls, &depth);
    if (p < best_p) best = c;
    if (!(p < best_p - 1e-3 * std::abs(best_p))) break;
    best_p = p;
  }
  shrink(e, best);
  return best;
}

// Each ball, its centre kept, made just large enough for the elements it owns (radius 0
// when it owns none).
void hold_members(const Elements& e, Clustering& c) {
  const auto members = members_of(c.owner, c.balls.size());
  std::vector<char> mark(e.points.size(), 0);
  for (std::size_t j = 0; j < c.balls.size(); ++j)
    c.balls[j].radius =
        members[j].empty() ? 0.0 : holding_radius(atoms_of(e, members[j], mark), c.balls[j].center);
}

// Step 4c candidates: the points of a grid inside the solid (about kCandidates of them,
// the grid at most kCandidateGrid points) and the centres \p extra, each with its depth.
constexpr double kCandidates = 2000.0;
constexpr int kThresholdHalvings = 10;
constexpr int kMinimaxRounds = 8;
constexpr double kCandidateGrid = 20000.0;

struct Candidates {
  std::vector<Eigen::Vector3d> centres;
  std::vector<double> depth;
};

Candidates candidates(const MeshQuery& query, const std::vector<Eigen::Vector3d>& extra,
                      const std::optional<double>& volume, int threads) {
  const Eigen::AlignedBox3d box = query.mesh().bounds();
  const double box_volume = box.sizes().prod();
  const double cell = std::max(std::cbrt(volume.value_or(box_volume) / kCandidates),
                               std::cbrt(box_volume / kCandidateGrid));
  std::vector<Eigen::Vector3d> points = cell_centres(box, cell);
  points.insert(points.end(), extra.begin(), extra.end());
  const std::vector<double> w = query.winding_numbers(points, threads);
  Candidates out;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (w[i] > 0.5) out.centres.push_back(points[i]);
  const std::vector<ClosestPoint> near = query.closest_points(out.centres, threads);
  for (const ClosestPoint& c : near) out.depth.push_back(c.distance());
  return out;
}

// Step 4c. The minimax start: the K candidate centres chosen by the least threshold cover
// of the patches, each patch's cost at a candidate the protrusion a ball there needs to
// hold it (distance to its farthest point minus the candidate's depth); the elements then
// go to them as in the rounds below, each ball as large as its elements need, and the
// minimax rounds follow. Empty when no cover is found.
Clustering threshold_start(const MeshQuery& query, const Elements& e, const Elements& p,
                           std::size_t budget, const Candidates& cand, double hi, int rounds,
                           int threads) {
  const std::size_t m_count = cand.centres.size(), items = p.size();
  // Filled below, every entry: not zeroed first (tens of MB at the larger budgets).
  const std::unique_ptr<float[]> cost(new float[m_count * items]);
  const long long n = static_cast<long long>(m_count);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long long mm = 0; mm < n; ++mm) {
    const std::size_t m = static_cast<std::size_t>(mm);
    for (std::size_t q = 0; q < items; ++q)
      cost[m * items + q] = static_cast<float>(farthest(p, q, cand.centres[m]) - cand.depth[m]);
  }
  const ThresholdCover tc =
      least_threshold_cover(cost.get(), m_count, items, budget, hi, kThresholdHalvings, threads);
  Clustering c;
  if (tc.picks.empty()) return c;
  std::vector<double> depth;
  for (std::size_t m : tc.picks)
    c.balls.push_back({cand.centres[m], 1.0}), depth.push_back(cand.depth[m]);
  assign(e, c.balls, c.owner, threads, depth);
  hold_members(e, c);
  return minimax(query, e, std::move(c), rounds, threads);
}

// The largest protrusion of the balls of radius > 0.
double largest_protrusion(const MeshQuery& query, const std::vector<Sphere>& balls, int threads) {
  std::vector<Sphere> live;
  for (const Sphere& b : balls)
    if (b.radius > 0.0) live.push_back(b);
  const std::vector<double> p = sphere_protrusions(query, live, threads);
  return p.empty() ? 0.0 : *std::max_element(p.begin(), p.end());
}

// What a candidate cover costs, to choose among starts: the product of its volume
// outside the solid (its union's volume minus V; the union's alone on an open mesh) and
// its largest protrusion, so that neither is traded away for a small gain in the other.
double cover_cost(const MeshQuery& query, const std::vector<Sphere>& balls,
                  const std::optional<double>& volume, int threads) {
  std::vector<Sphere> live;
  for (const Sphere& b : balls)
    if (b.radius > 0.0) live.push_back(b);
  const double outside = std::max(union_volume(live) - volume.value_or(0.0), 0.0);
  return outside * std::max(largest_protrusion(query, live, threads), 0.0);
}

// Step 4e. Ball j's elements split in two about their two most distant centroids (the
// farthest from the ball's centre, then the farthest from that), each part fitted with its
// minimum enclosing ball; the second part becomes a new ball. False when j has fewer than
// two elements.
bool split(const Elements& e, Clustering& c, std::size_t j) {
  std::vector<std::size_t> members;
  for (std::size_t i = 0; i < c.owner.size(); ++i)
    if (c.owner[i] == static_cast<int>(j)) members.push_back(i);
  if (members.size() < 2) return false;
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
  const auto parts = members_of(c.owner, c.balls.size());
  std::vector<char> mark(e.points.size(), 0);
  for (std::size_t part : {j, static_cast<std::size_t>(fresh)})
    c.balls[part] =
        parts[part].empty() ? Sphere{c.balls[part].center, 0.0} : fit(e, parts[part], mark);
  return true;
}

// The ball other than j (the one element i belongs to) that holds i at the least
// protrusion, given each ball's \p depth, and that protrusion.
std::pair<std::size_t, double> cheapest_other(const Elements& e, const Clustering& c, std::size_t i,
                                              const std::vector<double>& depth) {
  const std::size_t j = static_cast<std::size_t>(c.owner[i]);
  std::pair<std::size_t, double> best{j, std::numeric_limits<double>::infinity()};
  for (std::size_t m = 0; m < c.balls.size(); ++m) {
    const double v = farthest(e, i, c.balls[m].center) - depth[m];
    if (m != j && c.balls[m].radius > 0.0 && v < best.second) best = {m, v};
  }
  return best;
}

// The ball whose elements the other balls can take at the least largest protrusion.
std::size_t cheapest_removal(const Elements& e, const Clustering& c,
                             const std::vector<double>& depth) {
  std::vector<double> worst(c.balls.size(), -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < e.size(); ++i) {
    double& w = worst[static_cast<std::size_t>(c.owner[i])];
    w = std::max(w, cheapest_other(e, c, i, depth).second);
  }
  return static_cast<std::size_t>(std::min_element(worst.begin(), worst.end()) - worst.begin());
}

// Ball \p gone's elements to their cheapest other balls; \p gone is left empty (radius 0).
void hand_over(const Elements& e, Clustering& c, std::size_t gone,
               const std::vector<double>& depth) {
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (c.owner[i] != static_cast<int>(gone)) continue;
    const std::size_t m = cheapest_other(e, c, i, depth).first;
    c.owner[i] = static_cast<int>(m);
  }
  c.balls[gone].radius = 0.0;
}

// Step 4e. Local search on the ball count: the ball that protrudes most is split in two,
// filling the budget while balls are missing, else in exchange for the ball whose elements
// the others take most cheaply (hand_over); then minimax rounds (step 4c). A move is kept
// when it lowers cover_cost (\p cost, that of \p c, follows the moves kept) and its union
// is no larger than \p one_ball. The search stops at the first move that does not help.
constexpr std::size_t kLocalSearchBudget = 16;  // step 4e, and 4f's full rounds, up to this K
constexpr int kRefineMoves = 3;
constexpr int kRefineRounds = 2;

Clustering refine(const MeshQuery& query, const Elements& e, Clustering c, std::size_t budget,
                  const std::optional<double>& volume, double one_ball, double& cost, int threads) {
  for (int move = 0; move < kRefineMoves; ++move) {
    Clustering d = c;
    drop_empty(d);
    if (d.balls.empty()) break;
    const std::vector<double> p = sphere_protrusions(query, d.balls, threads);
    std::vector<double> depth(p.size());
    for (std::size_t j = 0; j < p.size(); ++j) depth[j] = d.balls[j].radius - p[j];
    const std::size_t worst =
        static_cast<std::size_t>(std::max_element(p.begin(), p.end()) - p.begin());
    if (d.balls.size() >= budget) {
      const std::size_t gone = cheapest_removal(e, d, depth);
      if (gone == worst) break;
      hand_over(e, d, gone, depth);
    }
    if (!split(e, d, worst)) break;
    hold_members(e, d);
    d = minimax(query, e, std::move(d), kRefineRounds, threads);
    const double v = cover_cost(query, d.balls, volume, threads);
    if (!(v < cost && union_volume(d.balls) <= one_ball)) break;
    c = std::move(d), cost = v;
  }
  return c;
}

// Step 4f. Union-volume descent. With each ball's elements fixed, its radius is the
// distance to its farthest point, so the union's volume U is a function of the centres.
// Its gradient in centre c_j: the integral of the outward normal over ball j's exposed
// sphere (the part in no other ball) plus the exposed area times d r_j / d c_j, the unit
// vector from the farthest point to c_j (here the sum of those vectors over the points
// within 1% of the radius, cut to length 1: the radius is a maximum, and at a minimum
// enclosing ball the single farthest point's direction says little). Both integrals are estimated
// on kDirections Fibonacci points of the sphere. Each ball in turn then moves against its gradient
// by a step s, halved until the move lowers U: the exact change of U from moving ball j alone is
// that of vol(B_j u N) - vol(N), N the balls that can meet B_j before or after (the radius is
// 1-Lipschitz in the centre), so each accepted move lowers the exact U. A move is also refused when
// the ball would stick out beyond \p cap. A round is the moves of every ball, then the shrink of
// step 4 (which only lowers radii); rounds stop when U falls by less than kDescentProgress of
// itself. Every element stays held by its owner: a moved ball's radius is that of its elements'
// farthest point.
//
// Why two runs, and the product rule of step 4d to choose. Free, the descent lowers U on
// robot links but most often raises the largest protrusion (it pulls balls off the
// protrusion-balanced places of steps 4c and 4e) and the product rejects it; capped at
// the winner's largest protrusion, a lower U is a lower product, so the capped run is
// kept almost always, while on links of two or three balls the free run's much lower U
// (a third of it on some) outweighs its somewhat larger protrusion; so the free run is
// made at small budgets only.
constexpr int kDescentRounds = 12;
constexpr int kLightDescentRounds = 3;  // above kLocalSearchBudget
constexpr double kDescentProgress = 3e-4;
constexpr int kDescentHalvings = 4;
constexpr int kDirections = 160;

std::vector<Eigen::Vector3d> fibonacci_directions(int n) {
  std::vector<Eigen::Vector3d> u;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / n, rho = std::sqrt(1.0 - z * z);
    u.emplace_back(rho * std::cos(golden * k), rho * std::sin(golden * k), z);
  }
  return u;
}

// The balls other than j that can meet ball j when its centre moves by up to \p reach.
std::vector<Sphere> neighbours(const std::vector<Sphere>& balls, std::size_t j, double reach) {
  std::vector<Sphere> n;
  for (std::size_t m = 0; m < balls.size(); ++m) {
    const double d = balls[j].radius + balls[m].radius + 2.0 * reach;
    if (m != j && balls[m].radius > 0.0 &&
        (balls[m].center - balls[j].center).squaredNorm() < d * d)
      n.push_back(balls[m]);
  }
  return n;
}

// The gradient of U in ball j's centre (the file comment of step 4f), \p atoms what it
// holds.
Eigen::Vector3d volume_gradient(const std::vector<Sphere>& balls, std::size_t j,
                                const std::vector<Sphere>& atoms,
                                const std::vector<Eigen::Vector3d>& dirs) {
  const Sphere& b = balls[j];
  const std::vector<Sphere> others = neighbours(balls, j, 0.0);
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  int exposed = 0;
  for (const Eigen::Vector3d& u : dirs) {
    const Eigen::Vector3d x = b.center + b.radius * u;
    const bool hidden = std::any_of(others.begin(), others.end(), [&](const Sphere& o) {
      return (x - o.center).squaredNorm() < o.radius * o.radius;
    });
    if (!hidden) normal += u, ++exposed;
  }
  Eigen::Vector3d pull = Eigen::Vector3d::Zero();
  for (const Sphere& a : atoms) {
    const Eigen::Vector3d d = b.center - a.center;
    const double n = d.norm();
    if (n + a.radius >= 0.99 * b.radius && n > 0.0) pull += d / n;
  }
  if (pull.norm() > 1.0) pull.normalize();
  const double patch = 4.0 * M_PI * b.radius * b.radius / static_cast<double>(dirs.size());
  return patch * (normal + static_cast<double>(exposed) * pull);
}

// Whether ball b, moved from centre x (whose probe is px), sticks out at most \p cap: the
// depth is 1-Lipschitz, so r - depth(x) + |c - x| <= cap settles it without a query.
bool within_cap(const MeshQuery& query, const Sphere& b, const Eigen::Vector3d& x, const Probe& px,
                double cap) {
  if (std::isinf(cap) || b.radius - px.depth + (b.center - x).norm() <= cap) return true;
  return b.radius - probe(query, b.center, x, px).depth <= cap;
}

// Ball j moved against \p g by the largest of s, s/2, ... (times its radius) that lowers U
// and leaves its protrusion at most \p cap (an infinite cap spares the distance queries);
// \p s grows by half after a success. True when it moved.
bool descend_ball(const MeshQuery& query, std::vector<Sphere>& balls, std::size_t j,
                  const std::vector<Sphere>& atoms, const Eigen::Vector3d& g, double cap,
                  double& s) {
  if (!(g.norm() > 0.0)) return false;
  const Probe here = std::isinf(cap) ? Probe{} : probe(query, balls[j].center, balls[j].center, {});
  const Eigen::Vector3d dir = -g.normalized();
  const double step = s * balls[j].radius;
  std::vector<Sphere> set = neighbours(balls, j, step);
  const double rest = measure_union(set).volume;
  set.push_back(balls[j]);
  const double before = measure_union(set).volume - rest;
  for (int h = 0; h <= kDescentHalvings; ++h) {
    const Eigen::Vector3d c = balls[j].center + std::ldexp(step, -h) * dir;
    set.back() = {c, holding_radius(atoms, c)};
    if (measure_union(set).volume - rest < before &&
        within_cap(query, set.back(), balls[j].center, here, cap)) {
      balls[j] = set.back();
      s = std::min(0.5, h == 0 ? 1.5 * s : std::ldexp(s, -h));
      return true;
    }
  }
  s = std::ldexp(s, -kDescentHalvings - 1);
  return false;
}

Clustering descend_volume(const MeshQuery& query, const Elements& e, Clustering c, bool capped,
                          int rounds, int threads) {
  drop_empty(c);
  const double cap = capped ? largest_protrusion(query, c.balls, threads)
                            : std::numeric_limits<double>::infinity();
  const std::vector<Eigen::Vector3d> dirs = fibonacci_directions(kDirections);
  std::vector<double> step(c.balls.size(), 0.1);
  std::vector<char> mark(e.points.size(), 0);
  double volume = union_volume(c.balls);
  for (int round = 0; round < rounds; ++round) {
    const auto members = members_of(c.owner, c.balls.size());
    for (std::size_t j = 0; j < c.balls.size(); ++j) {
      if (members[j].empty() || step[j] < 1e-3) continue;
      const std::vector<Sphere> atoms = atoms_of(e, members[j], mark);
      descend_ball(query, c.balls, j, atoms, volume_gradient(c.balls, j, atoms, dirs), cap,
                   step[j]);
    }
    shrink(e, c);
    const double v = union_volume(c.balls);
    const bool slow = !(v < volume * (1.0 - kDescentProgress));
    volume = v;
    if (slow) break;
  }
  return c;
}

// Step 4f on the winner: the capped descent and, for budgets up to kFreeDescentBudget, the
// free one beside it (each serial, the two side by side); the one of least cover_cost is
// kept when it is below the winner's, \p cost_c. (The free run wins on few-ball links only, where
// one ball's move changes much of the union; at larger budgets it costs time for
// nothing.)
constexpr std::size_t kFreeDescentBudget = 4;

Clustering volume_step(const MeshQuery& query, const Elements& e, Clustering c, std::size_t budget,
                       const std::optional<double>& volume, double cost_c, int threads) {
  const int run_count = budget <= kFreeDescentBudget ? 2 : 1;
  const int rounds = budget <= kLocalSearchBudget ? kDescentRounds : kLightDescentRounds;
  std::array<Clustering, 2> runs;
  std::array<double, 2> cost{std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::infinity()};
#pragma omp parallel for schedule(static, 1) num_threads(std::min(threads, run_count))
  for (int run = 0; run < run_count; ++run) {
    const std::size_t r = static_cast<std::size_t>(run);
    runs[r] = descend_volume(query, e, c, run == 0, rounds, run_count == 1 ? threads : 1);
    cost[r] = cover_cost(query, runs[r].balls, volume, run_count == 1 ? threads : 1);
  }
  const std::size_t pick = cost[1] < cost[0] ? 1 : 0;
  if (cost[pick] < cost_c) return std::move(runs[pick]);
  return c;
}

// Steps 2 to 4 from every start, on the patches, each result carried over to the elements
// (step 4b); then the minimax start (step 4c) from candidates that include every start's
// centres, and its threshold search bounded by the best start's largest protrusion. The
// least cover_cost wins (step 4d) among the results whose union is no larger than start
// 0's single ball.
Clustering search(const MeshQuery& query, const Elements& e, const Patching& patching,
                  const Elements& fine, std::size_t budget, const CoverOptions& options,
                  int threads) {
  const Elements& p = patching.patches;
  const std::optional<double> volume = solid_volume(query.mesh());
  Clustering c;
  double best = std::numeric_limits<double>::infinity();
  std::vector<Eigen::Vector3d> centres;  // of every start's balls: candidates of step 4c
  // The union of start 0's single ball: no result with a larger union is kept, so the
  // cover is never looser than the (inward-moved) bounding sphere.
  double one_ball = std::numeric_limits<double>::infinity();
  for (int start = 0; start < options.starts; ++start) {
    // Start 0 is the single enclosing ball, which the refill below grows to K balls seeded
    // from its centre; it alone is kept where one ball is the tightest cover (a sphere).
    const std::size_t first_k = start == 0 ? 1 : budget;
    Clustering d = optimise(query, p, seeds(p, first_k, {}, first_seed(p, options.seed, start)),
                            options, threads);
    // Balls the shrink removed leave budget: reseed it where the surface is farthest from a
    // centre, and keep the result if its union is smaller.
    std::vector<Sphere> live;
    for (const Sphere& b : d.balls)
      if (b.radius > 0.0) live.push_back(b);
    Clustering f;
    if (live.size() < budget)
      f = follow(query, e, patching,
                 optimise(query, p, seeds(p, budget, live, 0), options, threads), threads);
    d = follow(query, e, patching, std::move(d), threads);
    if (start == 0) one_ball = union_volume(d.balls);
    if (!f.balls.empty() && union_volume(f.balls) < union_volume(d.balls)) d = std::move(f);
    for (const Sphere& b : d.balls)
      if (b.radius > 0.0) centres.push_back(b.center);
    const double v = cover_cost(query, d.balls, volume, threads);
    if (union_volume(d.balls) <= one_ball && v < best) best = v, c = std::move(d);
  }
  Clustering t =
      threshold_start(query, e, fine, budget, candidates(query, centres, volume, threads),
                      largest_protrusion(query, c.balls, threads),
                      std::min(options.rounds, kMinimaxRounds), threads);
  if (!t.balls.empty() && union_volume(t.balls) <= one_ball) {
    const double v = cover_cost(query, t.balls, volume, threads);
    if (v < best) best = v, c = std::move(t);
  }
  // Step 4e, and 4f's full rounds, where each ball matters most and they cost least: their
  // cost grows with K (at K = 32 they add a quarter to the bake) while their gain falls.
  // Above, 4f's first rounds, which make most of its gain (about 5% of the excess volume on
  // the larger robot links) at a small part of its cost.
  if (budget <= kLocalSearchBudget)
    c = refine(query, e, std::move(c), budget, volume, one_ball, best, threads);
  if (!options.volume_descent) return c;
  return volume_step(query, e, std::move(c), budget, volume, best, threads);
}

void check_cover_options(std::size_t budget, const CoverOptions& o) {
  if (budget == 0) throw std::invalid_argument("budget must be >= 1, got 0");
  if (o.starts < 1)
    throw std::invalid_argument("starts must be >= 1, got " + std::to_string(o.starts));
  if (o.rounds < 1)
    throw std::invalid_argument("rounds must be >= 1, got " + std::to_string(o.rounds));
  if (o.interior_resolution < 0 || o.interior_resolution > 256)
    throw std::invalid_argument("interior_resolution must be in [0, 256], got " +
                                std::to_string(o.interior_resolution));
  if (o.repair_rounds < 1)
    throw std::invalid_argument("repair_rounds must be >= 1, got " +
                                std::to_string(o.repair_rounds));
  if (o.certificate.max_depth < kMaxElementDepth)
    throw std::invalid_argument(
        "certificate.max_depth must be >= " + std::to_string(kMaxElementDepth) + ", got " +
        std::to_string(o.certificate.max_depth));
  check_threads(o.threads);
}

void measure(const MeshQuery& query, const std::vector<Sphere>& balls, int threads, CoverStats& s) {
  s.union_volume = measure_union(balls).volume;
  s.mesh_volume = solid_volume(query.mesh());
  s.excess_volume = s.mesh_volume ? (s.union_volume - *s.mesh_volume) / *s.mesh_volume
                                  : std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> p = sphere_protrusions(query, balls, threads);
  s.max_protrusion = p.empty() ? 0.0 : *std::max_element(p.begin(), p.end());
}

// Step 5 and the figures, for both entry points: the live balls of \p c with the slack,
// certified and repaired, then measured; \p start is when the call began.
void finish(const MeshQuery& query, const Clustering& c, const CoverOptions& options,
            std::chrono::steady_clock::time_point start, CoverResult& out) {
  const TriangleMesh& mesh = query.mesh();
  CoverStats& s = out.stats;
  const double coordinates =
      mesh.bounds().min().cwiseAbs().cwiseMax(mesh.bounds().max().cwiseAbs()).maxCoeff();
  std::vector<Sphere>& balls = out.spheres.spheres;
  for (const Sphere& b : c.balls)
    if (b.radius > 0.0)
      balls.push_back(
          {b.center, b.radius + cover_radius_slack(s.largest_side, coordinates + b.radius)});
  CoverCertificateOptions co = options.certificate;
  co.threads = options.threads;
  for (int round = 0; round < options.repair_rounds; ++round) {
    out.certificate = certify_cover(mesh, balls, co);
    s.repair_rounds_run = round;
    if (out.certificate.certified) break;
    s.repaired += grow_to_hold(balls, out.certificate,
                               cover_radius_slack(s.largest_side, coordinates + s.largest_side));
  }
  if (!out.certificate.certified && s.repaired > 0)
    out.certificate = certify_cover(mesh, balls, co);
  s.certified = out.certificate.certified;
  s.spheres = balls.size();
  measure(query, balls, options.threads, s);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// tighten_cover's descent: rounds at most (it stops earlier when the union falls by less
// than kDescentProgress of itself).
constexpr int kTightenRounds = 40;

}  // namespace

CoverResult bake_cover(const MeshQuery& query, std::size_t budget, const CoverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  check_cover_options(budget, options);
  const int threads = thread_count(options.threads);
  const TriangleMesh& mesh = query.mesh();
  CoverResult out;
  CoverStats& s = out.stats;
  s.budget = budget;
  s.largest_side = mesh.bounds().sizes().maxCoeff();
  const Elements e = make_elements(query, budget, options);
  s.elements = e.surface;
  s.interior_points = e.items.size() - e.surface;
  const Eigen::Vector3d origin = mesh.bounds().min();
  const Patching patching = make_patches(e, patch_cell(e, budget, e.element_size, origin), origin);
  s.patches = patching.patches.surface;
  // Finer patches for the threshold cover of step 4c.
  const Patching fine =
      make_patches(e, patch_cell(e, budget, e.element_size, origin, kFinePatchFloor), origin);
  const Clustering c = search(query, e, patching, fine.patches, budget, options, threads);
  s.rounds_run = c.rounds;
  s.best_round = c.best_round;
  finish(query, c, options, start, out);
  return out;
}

CoverResult tighten_cover(const MeshQuery& query, const std::vector<Sphere>& start_balls,
                          const CoverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::string problem = cover_start_problem(start_balls);
  if (!problem.empty()) throw std::invalid_argument("start: " + problem);
  check_cover_options(start_balls.size(), options);
  const int threads = thread_count(options.threads);
  CoverResult out;
  CoverStats& s = out.stats;
  s.budget = s.start_spheres = start_balls.size();
  s.largest_side = query.mesh().bounds().sizes().maxCoeff();
  CoverOptions surface_only = options;
  surface_only.interior_resolution = 0;
  const Elements e = make_elements(query, start_balls.size(), surface_only);
  s.elements = e.surface;
  // Each element to the ball that must grow least to hold it, each ball then just large
  // enough for its elements (grown or shrunk), then steps 4 and 4f (capped).
  Clustering c;
  c.balls = start_balls;
  std::vector<double> radii;
  for (const Sphere& b : start_balls) radii.push_back(b.radius);
  assign(e, c.balls, c.owner, threads, radii);
  hold_members(e, c);
  shrink(e, c);
  if (options.volume_descent)
    c = descend_volume(query, e, std::move(c), true, kTightenRounds, threads);
  finish(query, c, options, start, out);
  return out;
}

std::string cover_start_problem(const std::vector<Sphere>& start) {
  if (start.empty()) return "no spheres";
  for (std::size_t j = 0; j < start.size(); ++j)
    if (!start[j].center.allFinite() || !std::isfinite(start[j].radius) || start[j].radius < 0.0)
      return "sphere " + std::to_string(j) +
             " has a non-finite centre or a radius that is not >= 0";
  return "";
}

std::size_t grow_to_hold(std::vector<Sphere>& balls, const CoverCertificate& cert, double slack) {
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  std::size_t grown = 0;
  for (const CoverPiece& piece : cert.uncertified_pieces) {
    std::size_t chosen = 0;
    double least = std::numeric_limits<double>::infinity(), needed = 0.0;
    for (std::size_t j = 0; j < balls.size(); ++j) {
      double reach = 0.0;
      for (const Eigen::Vector3d& corner : piece.corners)
        reach = std::max(reach, (corner - balls[j].center).norm());
      if (reach - balls[j].radius < least) {
        least = reach - balls[j].radius;
        chosen = j;
        needed = reach;
      }
    }
    const double radius = needed + slack + 64.0 * kEps * needed;
    if (radius > balls[chosen].radius) {
      balls[chosen].radius = radius;
      ++grown;
    }
  }
  return grown;
}

// Far above the certificate's rounding allowance (a few ulps of the coordinates), so that a
// ball holding an element's computed corners certifies it.
double cover_radius_slack(double L, double coordinates) {
  return 1e-9 * L + 64.0 * std::numeric_limits<double>::epsilon() * coordinates;
}

}  // namespace medspheres
