// The elements of the covering bake and the clustering that holds them (cover_elements.h).
//
// The elements are the pieces of the certificate's own midpoint subdivision, so a ball
// that holds an element's three computed corners with a margin above the certificate's
// rounding allowance certifies it (cover.cpp's last step rarely has anything to repair).
// Interior points join them so that the balls also fill the solid (not certified). Every
// operation here keeps each element held by its owner.
#include "cover_elements.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

#include "medspheres/measure/union_volume.h"
#include "medspheres/min_enclosing_ball.h"
#include "medspheres/point_triangle.h"

namespace medspheres::detail {

namespace {

constexpr double kElementCap = 40000.0;
// Up to this budget the element size is coarsened by kCoarsen at a time until the elements
// fit the cap; above it, the finest size that fits is found exactly (element_size).
constexpr std::size_t kExactSizeAbove = 64;
constexpr double kCoarsen = 1.5;
constexpr double kPatchesPerBall = 60.0;

// reach_from(atoms, c) of the atoms that atoms_into lists for \p members, without the list:
// the largest farthest() over the members. The same bits: over points, the root of the largest
// squared distance is the largest root (repeated points change no maximum); over patches, the same
// sums.
double reach_of(const Elements& e, const std::vector<std::size_t>& members,
                const Eigen::Vector3d& c) {
  double r = 0.0;
  for (std::size_t i : members) r = std::max(r, farthest(e, i, c));
  return r;
}

void push_element(Elements& e, int a, int b, int c) {
  e.items.push_back({a, b, c, c});
  const Eigen::Vector3d &pa = e.points[static_cast<std::size_t>(a)],
                        &pb = e.points[static_cast<std::size_t>(b)],
                        &pc = e.points[static_cast<std::size_t>(c)];
  const Eigen::Vector3d g = (pa + pb + pc) / 3.0;
  e.centroids.push_back(g);
  e.reach.push_back(std::max({(pa - g).norm(), (pb - g).norm(), (pc - g).norm()}));
  e.weight.push_back(0.5 * (pb - pa).cross(pc - pa).norm());
}

// The two triangles abc and abd as one element (a, b, c, d).
void push_quad(Elements& e, int a, int b, int c, int d) {
  e.items.push_back({a, b, c, d});
  auto at = [&](int q) -> const Eigen::Vector3d& { return e.points[static_cast<std::size_t>(q)]; };
  const Eigen::Vector3d g = (at(a) + at(b) + at(c) + at(d)) / 4.0;
  e.centroids.push_back(g);
  e.reach.push_back(
      std::max({(at(a) - g).norm(), (at(b) - g).norm(), (at(c) - g).norm(), (at(d) - g).norm()}));
  e.weight.push_back(0.5 * ((at(b) - at(a)).cross(at(c) - at(a)).norm() +
                            (at(b) - at(a)).cross(at(d) - at(a)).norm()));
}

// Two mesh triangles that share an edge as one element (their shared corners first).
void push_pair(Elements& e, const std::array<int, 3>& s, const std::array<int, 3>& t) {
  auto in_t = [&](int q) { return q == t[0] || q == t[1] || q == t[2]; };
  int k = 0;  // the corner of s that t lacks
  while (in_t(s[static_cast<std::size_t>(k)])) ++k;
  const int a = s[static_cast<std::size_t>((k + 1) % 3)],
            b = s[static_cast<std::size_t>((k + 2) % 3)];
  const int d = t[0] != a && t[0] != b ? t[0] : t[1] != a && t[1] != b ? t[1] : t[2];
  push_quad(e, a, b, s[static_cast<std::size_t>(k)], d);
}

// A matching of the triangles with \p whole set: each to at most one other across an edge
// that exactly those two triangles share, greedily in triangle order, to the neighbour
// whose centroid is nearest (compact pairs). -1: unpaired.
std::vector<int> pair_triangles(const TriangleMesh& mesh, const std::vector<char>& whole) {
  const std::size_t n = mesh.num_triangles();
  std::vector<std::pair<std::uint64_t, std::size_t>> edges;  // (edge key, 3 triangle + edge)
  for (std::size_t t = 0; t < n; ++t)
    for (std::size_t k = 0; k < 3 && whole[t]; ++k) {
      const auto u = static_cast<std::uint32_t>(mesh.triangles[t][k]),
                 v = static_cast<std::uint32_t>(mesh.triangles[t][(k + 1) % 3]);
      edges.emplace_back(static_cast<std::uint64_t>(std::min(u, v)) << 32 | std::max(u, v),
                         3 * t + k);
    }
  std::sort(edges.begin(), edges.end());
  std::vector<int> across(3 * n, -1);  // the one other triangle on edge k of t, or -1
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    if (j - i == 2) {
      across[edges[i].second] = static_cast<int>(edges[i + 1].second / 3);
      across[edges[i + 1].second] = static_cast<int>(edges[i].second / 3);
    }
    i = j;
  }
  auto shared = [&](std::size_t t, std::size_t u) {  // corners of u in t
    int m = 0;
    for (int q : mesh.triangles[u])
      m += q == mesh.triangles[t][0] || q == mesh.triangles[t][1] || q == mesh.triangles[t][2];
    return m;
  };
  auto centroid = [&](std::size_t t) {
    return mesh.corner(t, 0) + mesh.corner(t, 1) + mesh.corner(t, 2);
  };
  std::vector<int> partner(n, -1);
  for (std::size_t t = 0; t < n; ++t) {
    if (!whole[t] || partner[t] >= 0) continue;
    double least = std::numeric_limits<double>::infinity();
    int best = -1;
    for (int k = 0; k < 3; ++k) {
      const int u = across[3 * t + static_cast<std::size_t>(k)];
      if (u < 0 || partner[static_cast<std::size_t>(u)] >= 0 ||
          shared(t, static_cast<std::size_t>(u)) != 2)
        continue;
      const double gap = (centroid(static_cast<std::size_t>(u)) - centroid(t)).squaredNorm();
      if (gap < least) least = gap, best = u;
    }
    if (best < 0) continue;
    partner[t] = best;
    partner[static_cast<std::size_t>(best)] = static_cast<int>(t);
  }
  return partner;
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

// The grid cell of side \p cell that holds g (21 bits per axis).
std::uint64_t cell_key(const Eigen::Vector3d& g, const Eigen::Vector3d& origin, double cell) {
  std::uint64_t key = 0;
  for (int a = 0; a < 3; ++a)
    key = key << 21 |
          (static_cast<std::uint64_t>(std::max(0.0, std::floor((g[a] - origin[a]) / cell))) &
           0x1FFFFF);
  return key;
}

// The surface elements grouped by the cell (side \p cell) of a grid that holds their
// centroid; each group becomes one patch, the ball about its points' bounding box that
// holds them. Interior points stay patches of their own. Patches are numbered by their
// first element, so the grouping depends on nothing but the elements.
Elements group_patches(const Elements& e, double cell, const Eigen::Vector3d& origin) {
  std::unordered_map<std::uint64_t, int> index;
  std::vector<std::vector<std::size_t>> groups;
  Elements p;
  for (std::size_t i = 0; i < e.size(); ++i) {
    const std::uint64_t key = cell_key(e.centroids[i], origin, cell);
    const int fresh = static_cast<int>(groups.size());
    const int g = i < e.surface ? index.emplace(key, fresh).first->second : fresh;
    if (g == fresh) groups.emplace_back();
    groups[static_cast<std::size_t>(g)].push_back(i);
    if (i + 1 == e.surface) p.surface = groups.size();
  }
  for (const std::vector<std::size_t>& group : groups) {
    Eigen::AlignedBox3d box;
    for (std::size_t i : group)
      for (int q : e.items[i]) box.extend(e.points[static_cast<std::size_t>(q)]);
    const Eigen::Vector3d c = box.center();
    p.centroids.push_back(c);
    p.reach.push_back(raised(reach_of(e, group, c)));
    double w = 0.0;
    for (std::size_t i : group) w += e.weight[i];
    p.weight.push_back(w);
  }
  return p;
}

// The depth of midpoint subdivision that brings a triangle of longest edge \p length to
// \p size (at most kMaxElementDepth).
int element_depth(double length, double size) {
  int d = 0;
  while (d < kMaxElementDepth && length > size * (1 << d)) ++d;
  return d;
}

// The elements that triangles of longest edges \p edge make at \p size.
double element_count(const std::vector<double>& edge, double size) {
  double count = 0.0;
  for (double l : edge) count += std::pow(4.0, element_depth(l, size));
  return count;
}

// The element size for budget K: L / (2 + 3 sqrt K) when its elements fit \p cap, else
// coarser. Up to kExactSizeAbove by kCoarsen at a time: hundreds of elements a ball, whose
// grain matters little, and a finer size there moves the covers only within their local
// optima's noise (steps of 1.05 took the G1's false self-collisions at 32 spheres a link
// from 1788 to 1842 configurations of 10^4). Above it the cap binds at large K and leaves few
// elements a ball (cap / K), so their grain sets the balls' protrusion, and steps of 1.5 from
// different starts land on different sizes: on the G1's right hip roll link K = 4096 got coarser
// elements than K = 1024, and a cover that stuck out 5.9 mm against 4.7 (docs/covers.md). There the
// least size >= the start whose elements fit is found: the count is a step function of the
// size, falling at the sizes l / 2^d (a triangle's longest edge l halved d times), so that
// size is the start or the least such breakpoint above it that fits (binary search; the
// count never rises with the size). It never grows with K.
double element_size(const std::vector<double>& edge, std::size_t budget, double L, double cap) {
  double h = L / (2.0 + 3.0 * std::sqrt(static_cast<double>(budget)));
  if (element_count(edge, h) <= cap) return h;
  if (budget <= kExactSizeAbove) {
    do h *= kCoarsen;
    while (element_count(edge, h) > cap);
    return h;
  }
  std::vector<double> sizes;
  for (double l : edge)
    for (int d = 0; d <= kMaxElementDepth; ++d)
      if (l / (1 << d) > h) sizes.push_back(l / (1 << d));
  std::sort(sizes.begin(), sizes.end());
  // Every triangle at depth 0 fits (cap >= the triangles), so the largest breakpoint does.
  std::size_t lo = 0, hi = sizes.size() - 1;
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (element_count(edge, sizes[mid]) <= cap)
      hi = mid;
    else
      lo = mid + 1;
  }
  return sizes[lo];
}

}  // namespace

Elements make_elements(const MeshQuery& query, std::size_t budget, int interior_resolution,
                       int threads) {
  const TriangleMesh& mesh = query.mesh();
  const Eigen::AlignedBox3d box = mesh.bounds();
  const double L = box.sizes().maxCoeff();
  // Element size: about L / (2 + 3 sqrt K), coarsened (element_size) until there are at
  // most max(2 triangles, kElementCap) elements: beyond that, finer elements cost time and
  // gain little.
  std::vector<double> edge(mesh.num_triangles());
  for (std::size_t t = 0; t < edge.size(); ++t) {
    const Eigen::Vector3d &a = mesh.corner(t, 0), &b = mesh.corner(t, 1), &c = mesh.corner(t, 2);
    edge[t] = std::max({(a - b).norm(), (b - c).norm(), (c - a).norm()});
  }
  const double cap = std::max(2.0 * static_cast<double>(mesh.num_triangles()), kElementCap);
  const double h = element_size(edge, budget, L, cap);
  // Still more than twice kElementCap (a mesh of that many triangles smaller than the
  // size, such as quartet/dragon.obj's 100k): the triangles left whole go in pairs, about
  // halving what every step scans, and still more elements than the other meshes have.
  // (Meshes between one and two caps, such as the G1's torso at 51k triangles, keep their
  // triangles: pairs there gave a cover 5% and 12% worse on protrusion and excess.)
  std::vector<char> whole(edge.size());
  for (std::size_t t = 0; t < edge.size(); ++t) whole[t] = element_depth(edge[t], h) == 0;
  Elements e;
  e.element_size = h;
  e.paired = element_count(edge, h) > 2.0 * kElementCap;
  e.points = mesh.vertices;
  const std::vector<int> partner =
      e.paired ? pair_triangles(mesh, whole) : std::vector<int>(edge.size(), -1);
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
    const std::array<int, 3>& v = mesh.triangles[t];
    if (partner[t] >= 0 && partner[t] < static_cast<int>(t)) continue;  // in its partner's pair
    if (partner[t] >= 0)
      push_pair(e, mesh.triangles[static_cast<std::size_t>(partner[t])], v);
    else if (whole[t])
      push_element(e, v[0], v[1], v[2]);
    else
      subdivide(e, mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2),
                element_depth(edge[t], h));
  }
  e.surface = e.items.size();
  if (interior_resolution <= 0) return e;
  const double cell = L / interior_resolution;
  const std::vector<Eigen::Vector3d> grid = cell_centres(box, cell);
  const std::vector<double> w = query.winding_numbers(grid, threads);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (!(w[i] > 0.5)) continue;
    const int k = static_cast<int>(e.points.size());
    e.points.push_back(grid[i]);
    push_element(e, k, k, k);
    e.weight.back() = cell * cell;
  }
  return e;
}

double need(const Elements& e, std::size_t i, const Sphere& b) {
  return farthest(e, i, b.center) - b.radius;
}

// The side of the patch grid: half the element size, coarsened (by 1.25 at a time) until
// there are at most max(floor, kPatchesPerBall K) surface patches.
Elements make_patches(const Elements& e, std::size_t budget, double floor,
                      const Eigen::Vector3d& origin) {
  const double cap = std::max(floor, kPatchesPerBall * static_cast<double>(budget));
  std::unordered_map<std::uint64_t, char> seen;
  for (double cell = 0.5 * e.element_size;; cell *= 1.25) {
    seen.clear();
    for (std::size_t i = 0; i < e.surface && static_cast<double>(seen.size()) <= cap; ++i)
      seen.emplace(cell_key(e.centroids[i], origin, cell), 1);
    if (static_cast<double>(seen.size()) <= cap) return group_patches(e, cell, origin);
  }
}

// Each element to the centre whose farthest point of the element is nearest (ties: lowest
// index), a Voronoi assignment of whole elements. (Assigning by the growth a ball needs,
// which favours large balls, gave larger unions on most meshes tried.) The centroid
// bounds the farthest distance within |g - c| +- reach, which skips most centres.
// With \p depth (one per ball) the cost of centre j is that distance minus depth[j]: the
// protrusion ball j would need to hold the element.
// The centres are laid out by coordinate and the bounds computed in a loop of their own,
// which the compiler vectorizes (the bounds are most of assign's work; the same arithmetic).
void assign(const Elements& e, const std::vector<Sphere>& balls, std::vector<int>& owner,
            int threads, const std::vector<double>& depth) {
  const long long n = static_cast<long long>(e.size());
  const std::size_t k = balls.size();
  owner.resize(e.size());
  std::vector<double> cx(k), cy(k), cz(k), off(k, 0.0);
  for (std::size_t j = 0; j < k; ++j) {
    cx[j] = balls[j].center.x(), cy[j] = balls[j].center.y(), cz[j] = balls[j].center.z();
    if (!depth.empty()) off[j] = depth[j];
  }
#pragma omp parallel num_threads(threads)
  {
    std::vector<double> lo(k);
#pragma omp for schedule(static)
    for (long long ii = 0; ii < n; ++ii) {
      const std::size_t i = static_cast<std::size_t>(ii);
      const double gx = e.centroids[i].x(), gy = e.centroids[i].y(), gz = e.centroids[i].z();
      for (std::size_t j = 0; j < k; ++j) {  // lo[j]: |g - c_j| - depth_j, for now
        const double dx = gx - cx[j], dy = gy - cy[j], dz = gz - cz[j];
        lo[j] = std::sqrt(dx * dx + dy * dy + dz * dz) - off[j];
      }
      // The least of them, in four independent runs (rounding is monotone, so the least
      // plus the reach is the least of each plus the reach).
      constexpr double kInf = std::numeric_limits<double>::infinity();
      double m[4] = {kInf, kInf, kInf, kInf};
      for (std::size_t j = 0; j < k; ++j) m[j % 4] = std::min(m[j % 4], lo[j]);
      const double best_hi = std::min(std::min(m[0], m[1]), std::min(m[2], m[3])) + e.reach[i];
      for (std::size_t j = 0; j < k; ++j) lo[j] -= e.reach[i];
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

// What a ball must hold to hold the elements in \p members: their distinct points (balls
// of radius 0), or for patches their balls.
void atoms_into(const Elements& e, const std::vector<std::size_t>& members, std::vector<char>& mark,
                std::vector<Sphere>& atoms) {
  atoms.clear();
  if (e.patches()) {
    for (std::size_t i : members) atoms.push_back({e.centroids[i], e.reach[i]});
    return;
  }
  for (std::size_t i : members)
    for (int p : e.items[i])
      if (!mark[static_cast<std::size_t>(p)]) {
        mark[static_cast<std::size_t>(p)] = 1;
        atoms.push_back({e.points[static_cast<std::size_t>(p)], 0.0});
      }
  for (std::size_t i : members)
    for (int p : e.items[i]) mark[static_cast<std::size_t>(p)] = 0;
}

// The radius that the ball centred at c needs to hold \p atoms: the largest |a - c| + r_a.
// The square root is correctly rounded, so monotone: over the points (radius 0) the largest
// distance is the root of the largest squared distance, bit for bit (norm() is the root of
// squaredNorm()), and one root serves them all. Four running maxima, for the pipeline.
double reach_from(const std::vector<Sphere>& atoms, const Eigen::Vector3d& c) {
  double far2[4] = {0.0, 0.0, 0.0, 0.0};
  double r = 0.0;
  for (std::size_t i = 0; i < atoms.size(); ++i) {
    const double d2 = squared_distance(atoms[i].center, c);
    if (atoms[i].radius == 0.0)
      far2[i % 4] = std::max(far2[i % 4], d2);
    else
      r = std::max(r, std::sqrt(d2) + atoms[i].radius);
  }
  return std::max(r, std::sqrt(std::max(std::max(far2[0], far2[1]), std::max(far2[2], far2[3]))));
}

// The radius of a ball centred at c that holds \p atoms.
double holding_radius(const std::vector<Sphere>& atoms, const Eigen::Vector3d& c) {
  return raised(reach_from(atoms, c));
}

void FarthestAtoms::pivot(const Eigen::Vector3d& x, double delta) {
  pivot_ = x, delta_ = delta;
  const double R = reach_from(atoms_, x);
  near_.clear();
  for (const Sphere& a : atoms_)
    if ((a.center - x).norm() + a.radius >= R - 2.0 * delta) near_.push_back(a);
}

// The minimum enclosing ball of the points of the elements in \p members, by a core set:
// the minimum ball of a subset (first the extreme points along the axes and the
// diagonals) is the answer once it holds every point; otherwise the farthest points
// outside join the subset. The subset stays small, so each exact solve is cheap.
Sphere fit(const Elements& e, const std::vector<std::size_t>& members, std::vector<char>& mark) {
  std::vector<Sphere> pts;
  atoms_into(e, members, mark, pts);
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

// Each list reserved at its size first: growing them cost a copy and fresh pages at each
// doubling.
std::vector<std::vector<std::size_t>> members_of(const std::vector<int>& owner, std::size_t k) {
  std::vector<std::size_t> count(k, 0);
  for (int o : owner) ++count[static_cast<std::size_t>(o)];
  std::vector<std::vector<std::size_t>> m(k);
  for (std::size_t j = 0; j < k; ++j) m[j].reserve(count[j]);
  for (std::size_t i = 0; i < owner.size(); ++i) m[static_cast<std::size_t>(owner[i])].push_back(i);
  return m;
}

double union_volume(const std::vector<Sphere>& balls) {
  std::vector<Sphere> s;
  for (const Sphere& b : balls)
    if (b.radius > 0.0) s.push_back({b.center, b.radius});
  return measure_union(s).volume;
}

void hold_members(const Elements& e, Clustering& c) {
  c.settled.clear();
  const auto members = members_of(c.owner, c.balls.size());
  for (std::size_t j = 0; j < c.balls.size(); ++j)
    c.balls[j].radius =
        members[j].empty() ? 0.0 : raised(reach_of(e, members[j], c.balls[j].center));
}

void hold_all(const Elements& e, Clustering& c, int threads) {
  std::vector<double> radii;
  for (const Sphere& b : c.balls) radii.push_back(b.radius);
  // The growth ball j needs, far - r_j, is assign's cost with depth r_j.
  assign(e, c.balls, c.owner, threads, radii);
  hold_members(e, c);
}

namespace {

// The balls other than j, in order, that may hold one of \p members: a ball holding element i
// holds its centroid g_i, so |c_j - c_m| <= r_m + |g_i - c_j|; the others are skipped
// (a relative 1e-9 of slack keeps rounding from dropping one).
std::vector<std::size_t> may_hold(const Elements& e, const std::vector<Sphere>& balls,
                                  const std::vector<std::size_t>& members, std::size_t j) {
  double spread = 0.0;
  for (std::size_t i : members)
    spread = std::max(spread, (e.centroids[i] - balls[j].center).norm());
  std::vector<std::size_t> near;
  for (std::size_t m = 0; m < balls.size(); ++m)
    if (m != j && balls[m].radius > 0.0 &&
        (balls[m].center - balls[j].center).norm() <= (balls[m].radius + spread) * (1.0 + 1e-9))
      near.push_back(m);
  return near;
}

}  // namespace

// Ball j gives up the elements another ball holds (they move to the first such ball) and
// keeps its centre, its radius shrunk to the farthest point it still holds; a ball left
// with nothing goes. Every element stays held by its owner throughout.
void shrink(const Elements& e, Clustering& c, bool refining) {
  const std::size_t k = c.balls.size();
  // settled[i]: no other ball held element i when its owner last kept it. Balls only
  // shrink about fixed centres, so it stays so until one grows (then all are checked again).
  std::vector<char>& settled = c.settled;
  if (!refining || settled.size() != e.size()) settled.assign(e.size(), 0);
  for (int pass = 0; pass < 4; ++pass) {
    bool changed = false;
    auto members = members_of(c.owner, k);
    for (std::size_t j = 0; j < k; ++j) {
      if (members[j].empty()) continue;
      const std::vector<std::size_t> near = may_hold(e, c.balls, members[j], j);
      std::vector<std::size_t> keep, held;  // held by no other ball; by another (then moved)
      std::vector<std::size_t> to;
      for (std::size_t i : members[j]) {
        std::size_t other = k;
        for (std::size_t n = 0; n < near.size() && other == k && !settled[i]; ++n)
          if (holds(e, i, c.balls[near[n]])) other = near[n];
        if (other == k) {
          keep.push_back(i);
          settled[i] = 1;
        } else {
          held.push_back(i), to.push_back(other);
        }
      }
      if (held.empty()) continue;
      const double before = c.balls[j].radius;
      const double reach = reach_of(e, keep, c.balls[j].center);
      members[j] = keep;
      for (std::size_t h = 0; h < held.size(); ++h) {
        const std::size_t i = held[h];
        if (refining && farthest(e, i, c.balls[j].center) <= reach - 2.0 * e.reach[i]) {
          members[j].push_back(i);  // well within what ball j keeps: it stays
          continue;
        }
        c.owner[i] = static_cast<int>(to[h]);
        members[to[h]].push_back(i);
      }
      // The same centre, just large enough for what it keeps.
      c.balls[j].radius = keep.empty() ? 0.0 : raised(reach);
      changed = changed || c.balls[j].radius < before;
      if (c.balls[j].radius > before) std::fill(settled.begin(), settled.end(), 0);
    }
    if (!changed) break;
  }
}

namespace {

// The triangle abc of \p f split at its edge midpoints, each piece owned by \p owner.
void split_triangle(int a, int b, int c, int owner, Elements& f, std::vector<int>& owners) {
  auto mid = [&](int u, int v) {
    f.points.push_back(
        0.5 * (f.points[static_cast<std::size_t>(u)] + f.points[static_cast<std::size_t>(v)]));
    return static_cast<int>(f.points.size() - 1);
  };
  const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
  for (const std::array<int, 3>& q :
       {std::array<int, 3>{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}}) {
    push_element(f, q[0], q[1], q[2]);
    owners.push_back(owner);
  }
}

// Element i of \p e into \p f, each piece owned by \p owner: a triangle split at its edge
// midpoints; a pair into its two triangles, each split so only when it binds \p ball itself.
void split_element(const Elements& e, std::size_t i, int owner, const Sphere& ball, Elements& f,
                   std::vector<int>& owners) {
  const std::array<int, 4>& t = e.items[i];
  if (!paired(e, i)) return split_triangle(t[0], t[1], t[2], owner, f, owners);
  for (int far : {t[2], t[3]}) {
    push_element(f, t[0], t[1], far);
    owners.push_back(owner);
    const std::size_t last = f.size() - 1;
    if (!(farthest(f, last, ball.center) > ball.radius - 2.0 * f.reach[last])) continue;
    f.items.pop_back(), f.centroids.pop_back(), f.reach.pop_back(), f.weight.pop_back();
    owners.pop_back();
    split_triangle(t[0], t[1], far, owner, f, owners);
  }
}

}  // namespace

// An element binds its ball's radius when its farthest point is within twice its reach of
// the radius: a piece of it may then be the ball's farthest. Split, the pieces that another
// ball holds leave (shrink), and the ball shrinks to the farthest piece it keeps. The
// midpoints are computed from the corners as computed, within a few ulps of the
// certificate's own lattice points, far below the radius slack the cover adds.
// A pair that binds goes into its two triangles, each split only when it binds itself (so
// its pieces are no deeper than a triangle's). On such a dense mesh no element smaller than
// the grain h / 2^levels (a reach below half of it) is split: the other meshes' pieces end
// there, and the dragon's triangles (median edge 0.007 L) would otherwise be split to a
// fifth of that at K = 64, for 0.6% less excess volume at 1.5 times the cost.
// Only the pieces are new: an element left whole keeps the last shrink's mark (splitting
// moves no ball), so that shrink checks only the pieces and the unmarked elements.
void refine_binding(Elements& e, Clustering& c, int levels) {
  const double grain = e.paired ? std::ldexp(e.element_size, -levels) : 0.0;
  for (int level = 0; level < levels; ++level) {
    const bool marked = c.settled.size() == e.size();
    std::vector<char> split(e.surface, 0);
    std::size_t splits = 0;
    for (std::size_t i = 0; i < e.surface; ++i) {
      const Sphere& b = c.balls[static_cast<std::size_t>(c.owner[i])];
      split[i] = e.reach[i] > 0.5 * grain && farthest(e, i, b.center) > b.radius - 2.0 * e.reach[i];
      splits += split[i];
    }
    if (splits == 0) return;
    // Reserved for the most the splits add (a pair: 8 pieces, 6 midpoints), so that no list
    // grows by copies.
    Elements f;
    f.points.reserve(e.points.size() + 6 * splits);
    f.points.assign(e.points.begin(), e.points.end());
    f.element_size = 0.5 * e.element_size;
    f.paired = e.paired;
    const std::size_t most = e.size() + 7 * splits;
    f.items.reserve(most), f.centroids.reserve(most), f.reach.reserve(most), f.weight.reserve(most);
    std::vector<int> owners;
    std::vector<char> marks;
    owners.reserve(most), marks.reserve(most);
    for (std::size_t i = 0; i < e.size(); ++i) {
      if (i < e.surface && split[i]) {
        split_element(e, i, c.owner[i], c.balls[static_cast<std::size_t>(c.owner[i])], f, owners);
        marks.resize(owners.size(), 0);
      } else {
        f.items.push_back(e.items[i]);
        f.centroids.push_back(e.centroids[i]);
        f.reach.push_back(e.reach[i]);
        f.weight.push_back(e.weight[i]);
        owners.push_back(c.owner[i]);
        marks.push_back(marked ? c.settled[i] : 0);
      }
      if (i + 1 == e.surface) f.surface = f.items.size();
    }
    e = std::move(f);
    c.owner = std::move(owners);
    c.settled = std::move(marks);
    shrink(e, c, true);
  }
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

Probe probe(const MeshQuery& query, const Eigen::Vector3d& y, const Eigen::Vector3d& x,
            const Probe& px) {
  const ClosestPoint cp =
      px.triangle >= 0 ? query.closest_point(y, px.triangle) : query.closest_point(y);
  const double d = cp.distance();
  const bool in =
      px.triangle >= 0 && std::abs(px.depth) > (y - x).norm() ? px.depth > 0.0 : query.inside(y);
  return {in ? d : -d, cp.triangle, cp.point};
}

// point_triangle.h's distance is within 32 u S of the true one (S = |y| + |y - a| + the
// longest edge), as is the closest-point query's for the same triangle, and the query returns
// at most that: a margin of 1e-12 S (far above 64 u S) makes the bound hold as computed.
double depth_bound(const MeshQuery& query, const Eigen::Vector3d& y, const Probe& px) {
  const TriangleMesh& mesh = query.mesh();
  if (px.triangle < 0 || static_cast<std::size_t>(px.triangle) >= mesh.num_triangles())
    return std::numeric_limits<double>::infinity();
  const std::size_t t = static_cast<std::size_t>(px.triangle);
  const Eigen::Vector3d &a = mesh.corner(t, 0), &b = mesh.corner(t, 1), &c = mesh.corner(t, 2);
  const double d = (closest_point_on_triangle(y, a, b, c) - y).norm();
  const double S =
      y.norm() + (y - a).norm() + std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  return d + 1e-12 * S;
}

}  // namespace medspheres::detail
