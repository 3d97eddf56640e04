#include "medspheres/mesh/robust_solid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "medspheres/distance_transform.h"
#include "medspheres/error.h"
#include "medspheres/number_text.h"
#include "medspheres/point_triangle.h"

namespace medspheres {

namespace {

constexpr int kMinResolution = 8;
constexpr int kMaxResolution = 1024;
// The resolution of the triangle budget: probed at (the next when the walls enclose
// nothing), and chosen within.
constexpr int kProbeResolutions[] = {32, 48, 96};
// The probes of an escalated thickness: walls thickened by t >= 0.02 L are no thinner on a
// finer grid, and what the finest probe still encloses then are crevices of a few cells
// (the ur5e wrist meshes of the README: 3 and 5 cells at resolution 96, a solid of 10^5
// triangles whose bake fills half of it).
constexpr int kEscalatedProbeResolutions[] = {32, 48};
constexpr int kMinAutoResolution = 16;
constexpr int kMaxAutoResolution = 96;
constexpr int kAutoSteps = 5;

// kWall: within the base radius (1 + sqrt(3)/2) h of a triangle; kThick: within the
// thickness t of a kWall cell; kEroded: a kThick cell the closing may take back.
enum : std::uint8_t { kFree = 0, kWall = 1, kOutside = 2, kAdded = 3, kThick = 4, kEroded = 5 };

// Cells of the padded grid: cell (i, j, k) spans origin + h [i, i+1] x [j, j+1] x [k, k+1].
struct CellGrid {
  Eigen::Vector3d origin;
  double h = 0;
  std::array<std::int64_t, 3> n = {0, 0, 0};
  std::vector<std::uint8_t> state;

  std::int64_t index(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return i + n[0] * (j + n[1] * k);
  }
  bool solid(std::array<std::int64_t, 3> c) const {
    for (int a = 0; a < 3; ++a)
      if (c[a] < 0 || c[a] >= n[a]) return false;
    return state[static_cast<std::size_t>(index(c[0], c[1], c[2]))] != kOutside;
  }
  Eigen::Vector3d lattice(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return {origin.x() + static_cast<double>(i) * h, origin.y() + static_cast<double>(j) * h,
            origin.z() + static_cast<double>(k) * h};
  }
};

// The grid over the mesh's box, padded so that walls stay two cells off its outer layer.
CellGrid make_cell_grid(const Eigen::AlignedBox3d& box, int resolution, double wall_radius) {
  CellGrid g;
  g.h = box.sizes().maxCoeff() / resolution;
  const std::int64_t pad = static_cast<std::int64_t>(std::ceil(wall_radius / g.h)) + 2;
  g.origin = box.min() - Eigen::Vector3d::Constant(static_cast<double>(pad) * g.h);
  for (int a = 0; a < 3; ++a)
    g.n[a] = static_cast<std::int64_t>(std::ceil(box.sizes()[a] / g.h)) + 2 * pad + 1;
  g.state.assign(static_cast<std::size_t>(g.n[0] * g.n[1] * g.n[2]), kFree);
  return g;
}

// Step 2: cells whose centre is within base_radius of a triangle are kWall. A cell is
// tested only inside the triangle's box grown by base_radius, which holds every such
// centre, and skipped when its centre is farther than base_radius from the triangle's
// plane (by a margin far above the rounding of either distance: the walls are those the
// closest-point test alone marks).
void mark_walls(const TriangleMesh& mesh, double base_radius, CellGrid& g) {
  const double base2 = base_radius * base_radius * (1.0 + 1e-9);
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d& b = mesh.vertices[static_cast<std::size_t>(t[1])];
    const Eigen::Vector3d& c = mesh.vertices[static_cast<std::size_t>(t[2])];
    const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c).array() - base_radius;
    const Eigen::Vector3d hi = a.cwiseMax(b).cwiseMax(c).array() + base_radius;
    // The plane test only for a triangle whose angle at a has a sine of at least 1e-6, so
    // that the computed normal is within about 1e-9 rad of the true one.
    Eigen::Vector3d normal = (b - a).cross(c - a);
    const double area2 = normal.norm();
    const bool planar = area2 >= 1e-6 * (b - a).norm() * (c - a).norm() && area2 > 0.0;
    normal = planar ? Eigen::Vector3d(normal / area2) : Eigen::Vector3d::Zero();
    const double slab = planar ? base_radius * (1.0 + 1e-6) + 1e-8 * (hi - lo).norm()
                               : std::numeric_limits<double>::infinity();
    std::array<std::int64_t, 3> from{}, to{};
    for (int x = 0; x < 3; ++x) {
      from[x] = std::max<std::int64_t>(
          0, static_cast<std::int64_t>(std::floor((lo[x] - g.origin[x]) / g.h - 0.5)));
      to[x] = std::min<std::int64_t>(
          g.n[x] - 1, static_cast<std::int64_t>(std::ceil((hi[x] - g.origin[x]) / g.h - 0.5)));
    }
    for (std::int64_t k = from[2]; k <= to[2]; ++k)
      for (std::int64_t j = from[1]; j <= to[1]; ++j)
        for (std::int64_t i = from[0]; i <= to[0]; ++i) {
          std::uint8_t& s = g.state[static_cast<std::size_t>(g.index(i, j, k))];
          if (s == kWall) continue;
          const Eigen::Vector3d centre = g.lattice(i, j, k) + Eigen::Vector3d::Constant(0.5 * g.h);
          if (std::abs(normal.dot(centre - a)) > slab) continue;
          if ((closest_point_on_triangle(centre, a, b, c) - centre).squaredNorm() <= base2)
            s = kWall;
        }
  }
}

// The squared distance, in cells, from each cell's centre to the nearest centre of a cell
// in state \p seed (distance_transform.h).
std::vector<std::int64_t> squared_distances_to(const CellGrid& g, std::uint8_t seed) {
  std::vector<bool> is_seed(g.state.size());
  for (std::size_t v = 0; v < g.state.size(); ++v) is_seed[v] = g.state[v] == seed;
  return detail::squared_distance_transform(g.n, is_seed);
}

// (t / h)^2, the squared thickness in cells, with a relative margin far above the rounding
// of the division (squared distances between cell centres are integers).
double squared_cells(double thickness, double h) {
  const double cells = thickness / h;
  return cells * cells * (1.0 + 1e-12);
}

// Step 2b: free cells whose centre is within the thickness t of a kWall cell's centre
// become kThick. Returns the squared distances (in cells) to the walls, or nothing for
// t = 0.
std::vector<std::int64_t> thicken(CellGrid& g, double thickness) {
  if (!(thickness > 0.0)) return {};
  std::vector<std::int64_t> to_wall = squared_distances_to(g, kWall);
  const double t2 = squared_cells(thickness, g.h);
  for (std::size_t v = 0; v < g.state.size(); ++v)
    if (g.state[v] == kFree && static_cast<double>(to_wall[v]) <= t2) g.state[v] = kThick;
  return to_wall;
}

// A 6-connected breadth-first spread from the cells of \p queue (marked outside) into
// cells of state \p into, at most \p depth steps; each cell reached is marked outside.
void spread_outside(CellGrid& g, std::vector<std::int64_t> queue, std::uint8_t into,
                    std::int64_t depth) {
  const std::array<std::int64_t, 3> stride = {1, g.n[0], g.n[0] * g.n[1]};
  std::vector<std::int64_t> steps(queue.size(), 0);
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::int64_t v = queue[head];
    if (steps[head] >= depth) continue;
    const std::array<std::int64_t, 3> c = {v % g.n[0], (v / g.n[0]) % g.n[1],
                                           v / (g.n[0] * g.n[1])};
    for (int a = 0; a < 3; ++a)
      for (int dir : {-1, 1}) {
        const std::int64_t next = c[a] + dir;
        if (next < 0 || next >= g.n[a]) continue;
        const std::int64_t w = v + dir * stride[a];
        if (g.state[static_cast<std::size_t>(w)] != into) continue;
        g.state[static_cast<std::size_t>(w)] = kOutside;
        queue.push_back(w);
        steps.push_back(steps[head] + 1);
      }
  }
}

// Step 3: the flood fill from cell (0, 0, 0) over free cells: what it reaches is outside.
void flood_outside(CellGrid& g) {
  g.state[0] = kOutside;
  spread_outside(g, {0}, kFree, std::numeric_limits<std::int64_t>::max());
}

// Step 3b, for a thickness t: the closing. kThick cells whose centre is within t of an
// outside cell's centre become outside again (what the thickness added on the outside is
// taken away, what it plugged stays), those of them that the outside reaches through
// each other; the others stay kThick (the closing makes no cavity).
void close_outside(CellGrid& g, double thickness) {
  if (!(thickness > 0.0)) return;
  const std::vector<std::int64_t> to_outside = squared_distances_to(g, kOutside);
  const double t2 = squared_cells(thickness, g.h);
  std::vector<std::int64_t> seeds;
  for (std::size_t v = 0; v < g.state.size(); ++v) {
    if (g.state[v] == kOutside) seeds.push_back(static_cast<std::int64_t>(v));
    if (g.state[v] == kThick && static_cast<double>(to_outside[v]) <= t2) g.state[v] = kEroded;
  }
  spread_outside(g, std::move(seeds), kEroded, std::numeric_limits<std::int64_t>::max());
  for (std::uint8_t& s : g.state)
    if (s == kEroded) s = kThick;
}

// The cells the walls enclose: free cells the flood fill did not reach, and kThick cells
// the closing kept that are more than sqrt(3) cells from every kWall centre (\p to_wall).
// The closing's residue on the outside of a wall lies within sqrt(3) h of it, so a sheet,
// however thick its walls, encloses nothing.
std::size_t enclosed_cells(const CellGrid& g, const std::vector<std::int64_t>& to_wall) {
  std::size_t n = 0;
  for (std::size_t v = 0; v < g.state.size(); ++v)
    n += g.state[v] == kFree || (g.state[v] == kThick && to_wall[v] > 3);
  return n;
}

// Step 4: around each grid edge, two diagonal solid cells and two non-solid ones make
// the boundary non-manifold there; the first non-solid one (in cell order) becomes solid.
// Repeats until a pass changes nothing (cells are only added, so it ends).
void fill_diagonal_contacts(CellGrid& g) {
  bool changed = true;
  while (changed) {
    changed = false;
    for (int a = 0; a < 3; ++a) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;
      for (std::int64_t k = 0; k < g.n[2]; ++k)
        for (std::int64_t j = 0; j < g.n[1]; ++j)
          for (std::int64_t i = 0; i < g.n[0]; ++i) {
            // The edge along axis a whose four cells are c + {0, e_u, e_v, e_u + e_v}.
            std::array<std::int64_t, 3> c = {i, j, k};
            if (c[u] + 1 >= g.n[u] || c[v] + 1 >= g.n[v]) continue;
            auto at = [&](int du, int dv) {
              std::array<std::int64_t, 3> x = c;
              x[u] += du;
              x[v] += dv;
              return x;
            };
            const bool s00 = g.solid(at(0, 0)), s11 = g.solid(at(1, 1));
            const bool s10 = g.solid(at(1, 0)), s01 = g.solid(at(0, 1));
            std::array<std::int64_t, 3> fill;
            if (s00 && s11 && !s10 && !s01)
              fill = at(1, 0);
            else if (s10 && s01 && !s00 && !s11)
              fill = at(0, 0);
            else
              continue;
            g.state[static_cast<std::size_t>(g.index(fill[0], fill[1], fill[2]))] = kAdded;
            changed = true;
          }
    }
  }
}

// Step 5: the faces between solid and non-solid cells, wound outward.
TriangleMesh boundary_mesh(const CellGrid& g) {
  TriangleMesh mesh;
  std::unordered_map<std::int64_t, int> ids;
  const std::int64_t m0 = g.n[0] + 1, m1 = g.n[1] + 1;
  auto vertex = [&](const std::array<std::int64_t, 3>& p) {
    const std::int64_t key = p[0] + m0 * (p[1] + m1 * p[2]);
    const auto [it, fresh] = ids.emplace(key, static_cast<int>(mesh.vertices.size()));
    if (fresh) mesh.vertices.push_back(g.lattice(p[0], p[1], p[2]));
    return it->second;
  };
  for (std::int64_t k = 0; k < g.n[2]; ++k)
    for (std::int64_t j = 0; j < g.n[1]; ++j)
      for (std::int64_t i = 0; i < g.n[0]; ++i) {
        const std::array<std::int64_t, 3> c = {i, j, k};
        if (!g.solid(c)) continue;
        for (int a = 0; a < 3; ++a)
          for (int dir : {-1, 1}) {
            std::array<std::int64_t, 3> nb = c;
            nb[a] += dir;
            if (g.solid(nb)) continue;
            // Corners base, base + e_u, base + e_u + e_v, base + e_v: e_u x e_v = e_a.
            const int u = (a + 1) % 3, v = (a + 2) % 3;
            std::array<std::int64_t, 3> p[4] = {c, c, c, c};
            for (auto& q : p) q[a] += dir > 0 ? 1 : 0;
            p[1][u] += 1;
            p[2][u] += 1;
            p[2][v] += 1;
            p[3][v] += 1;
            int id[4];
            for (int q = 0; q < 4; ++q) id[q] = vertex(p[q]);
            if (dir > 0) {
              mesh.triangles.push_back({id[0], id[1], id[2]});
              mesh.triangles.push_back({id[0], id[2], id[3]});
            } else {
              mesh.triangles.push_back({id[0], id[2], id[1]});
              mesh.triangles.push_back({id[0], id[3], id[2]});
            }
          }
      }
  return mesh;
}

// Step 6: Laplacian smoothing of the boundary's vertices (kSmoothingSteps Jacobi steps of
// weight 1/2 towards the mean of the edge neighbours), each vertex kept within h/2 per
// axis of its lattice point, so that no point moves by more than sqrt(3)/2 h < h. The
// connectivity is kept: the surface stays closed and consistently wound.
constexpr int kSmoothingSteps = 8;

void smooth(TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& lattice, double h) {
  const std::size_t n = mesh.vertices.size();
  std::vector<std::vector<int>> next(n);
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) next[static_cast<std::size_t>(t[k])].push_back(t[(k + 1) % 3]);
  std::vector<Eigen::Vector3d> moved(n);
  for (int step = 0; step < kSmoothingSteps; ++step) {
    for (std::size_t v = 0; v < n; ++v) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int w : next[v]) mean += mesh.vertices[static_cast<std::size_t>(w)];
      mean /= static_cast<double>(next[v].size());
      const Eigen::Vector3d p = 0.5 * (mesh.vertices[v] + mean);
      const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5 * h);
      moved[v] = p.cwiseMax(lattice[v] - half).cwiseMin(lattice[v] + half);
    }
    mesh.vertices.swap(moved);
  }
}

InputError option_error(const char* field, double value, const std::string& problem) {
  return InputError::option(ErrorKind::kOutOfRange, field, number_text(value), problem);
}

}  // namespace

const char* to_string(SolidKind kind) {
  switch (kind) {
    case SolidKind::kAuto:
      return "auto";
    case SolidKind::kWinding:
      return "winding";
    case SolidKind::kRobust:
      return "robust";
  }
  return "?";
}

namespace {

// The box of the triangles' corners, checking indices; a mesh that is one point has no
// volume.
Eigen::AlignedBox3d checked_box(const TriangleMesh& mesh, const std::string& name) {
  if (mesh.triangles.empty()) throw std::invalid_argument("make_robust_solid: no triangles");
  Eigen::AlignedBox3d box;
  for (const auto& t : mesh.triangles)
    for (int v : t) {
      if (v < 0 || static_cast<std::size_t>(v) >= mesh.vertices.size())
        throw std::invalid_argument("make_robust_solid: vertex index out of range");
      box.extend(mesh.vertices[static_cast<std::size_t>(v)]);
    }
  if (!(box.sizes().maxCoeff() > 0.0))
    throw InputError(ErrorKind::kNoInterior, name,
                     "the mesh is a single point: it bounds no volume");
  return box;
}

// Steps 1 to 6 at resolution n.
RobustSolid solid_at(const TriangleMesh& mesh, const Eigen::AlignedBox3d& box, int n,
                     double thickness, const std::string& name) {
  RobustSolid out;
  out.resolution = n;
  out.cell = box.sizes().maxCoeff() / n;
  const double base_radius = (1.0 + std::sqrt(3.0) / 2.0) * out.cell;
  out.wall_radius = base_radius + thickness;
  out.thickness = thickness;
  CellGrid g = make_cell_grid(box, n, out.wall_radius);
  mark_walls(mesh, base_radius, g);
  const std::vector<std::int64_t> to_wall = thicken(g, thickness);
  out.wall_cells = static_cast<std::size_t>(std::count_if(
      g.state.begin(), g.state.end(), [](std::uint8_t s) { return s == kWall || s == kThick; }));
  flood_outside(g);
  close_outside(g, thickness);
  out.enclosed_cells = enclosed_cells(g, to_wall);
  if (out.enclosed_cells == 0)
    throw InputError(ErrorKind::kNoInterior, name,
                     "the mesh bounds no volume at robust resolution " + std::to_string(n) +
                         ": walls of " + number_text(out.wall_radius) +
                         " around its triangles enclose no cell, so it is a sheet, its holes "
                         "are wider than the walls close (raise robust_thickness), or its parts "
                         "are thinner than the walls (raise robust_resolution)");
  fill_diagonal_contacts(g);
  out.solid_cells = static_cast<std::size_t>(
      std::count_if(g.state.begin(), g.state.end(), [](std::uint8_t s) { return s != kOutside; }));
  out.mesh = boundary_mesh(g);
  const std::vector<Eigen::Vector3d> lattice = out.mesh.vertices;
  smooth(out.mesh, lattice, g.h);
  return out;
}

// The first solid of resolutions kProbeResolutions whose walls enclose a cell (thinner
// walls enclose smaller parts); the last error when none does.
template <std::size_t N>
RobustSolid probe_solid(const TriangleMesh& mesh, const Eigen::AlignedBox3d& box, double thickness,
                        const std::string& name, const int (&probes)[N]) {
  std::optional<InputError> failure;
  for (int n : probes) {
    try {
      return solid_at(mesh, box, n, thickness, name);
    } catch (const InputError& e) {
      if (e.kind() != ErrorKind::kNoInterior) throw;
      failure = e;
    }
  }
  throw *failure;
}

// The resolution of the triangle budget (resolution 0): boundary triangles grow about as
// n^2, so from a solid of t triangles at resolution n the next guess is n sqrt(budget / t),
// within [kMinAutoResolution, kMaxAutoResolution], below every resolution found over the
// budget (and, while over it, below every coarser one whose walls enclosed nothing: the
// enclosed cells depend on how the grid falls); from the probe, kAutoSteps more solids at
// most. The solid kept is the finest one within the budget, or, when none is, the coarsest
// built. An \p escalated thickness is probed at kEscalatedProbeResolutions.
RobustSolid solid_of_budget(const TriangleMesh& mesh, const Eigen::AlignedBox3d& box,
                            double thickness, const std::string& name, bool escalated) {
  RobustSolid best = escalated ? probe_solid(mesh, box, thickness, name, kEscalatedProbeResolutions)
                               : probe_solid(mesh, box, thickness, name, kProbeResolutions);
  int too_fine = kMaxAutoResolution + 1;  // the coarsest resolution found over the budget
  int coarse_limit = kMaxAutoResolution;  // below the coarser grids that enclosed nothing
  for (int step = 0; step < kAutoSteps; ++step) {
    const std::size_t triangles = best.mesh.triangles.size();
    const bool over = triangles > kRobustTriangleBudget;
    if (over) too_fine = std::min(too_fine, best.resolution);
    const double scale =
        std::sqrt(static_cast<double>(kRobustTriangleBudget) / static_cast<double>(triangles));
    int n = std::min(
        std::max(static_cast<int>(std::floor(best.resolution * scale)), kMinAutoResolution),
        too_fine - 1);
    if (over) n = std::min(n, coarse_limit);
    if (n == best.resolution || n < kMinAutoResolution) break;
    try {
      RobustSolid next = solid_at(mesh, box, n, thickness, name);
      if (over || next.mesh.triangles.size() <= kRobustTriangleBudget)
        best = std::move(next);
      else
        too_fine = n;
    } catch (const InputError& e) {
      if (e.kind() != ErrorKind::kNoInterior) throw;
      if (n > best.resolution)
        too_fine = n;
      else
        coarse_limit = n - 1;
    }
  }
  return best;
}

}  // namespace

void validate(const RobustSolidOptions& options) {
  const bool automatic = options.resolution == 0;
  if (!automatic && !(options.resolution >= kMinResolution && options.resolution <= kMaxResolution))
    throw option_error("robust_resolution", options.resolution,
                       "must be 0 (chosen by the triangle budget) or in [8, 1024], got " +
                           std::to_string(options.resolution));
  if (!(std::isfinite(options.thickness) && options.thickness >= 0.0))
    throw option_error("robust_thickness", options.thickness,
                       "must be a finite length >= 0, got " + number_text(options.thickness));
}

RobustSolid make_robust_solid(const TriangleMesh& mesh, const RobustSolidOptions& options,
                              const std::string& name) {
  validate(options);
  const Eigen::AlignedBox3d box = checked_box(mesh, name);
  const double longest = box.sizes().maxCoeff();
  // Thicker walls than the mesh is wide would only grow the grid (5 L: 11 L a side).
  if (options.thickness > longest)
    throw option_error("robust_thickness", options.thickness,
                       "must be at most the mesh's largest side L = " + number_text(longest) +
                           ", got " + number_text(options.thickness));
  auto solid = [&](double thickness, bool escalated = false) {
    if (options.resolution == 0) return solid_of_budget(mesh, box, thickness, name, escalated);
    return solid_at(mesh, box, options.resolution, thickness, name);
  };
  if (!options.escalate) return solid(options.thickness);
  // The given thickness, then each step of the schedule above it, until the walls enclose a
  // cell; the error of the last one tried when none does.
  try {
    return solid(options.thickness);
  } catch (const InputError& e) {
    if (e.kind() != ErrorKind::kNoInterior) throw;
    std::optional<InputError> failure = e;
    for (double step : kRobustThicknessSteps) {
      if (step * longest <= options.thickness) continue;
      try {
        return solid(step * longest, true);
      } catch (const InputError& thicker) {
        if (thicker.kind() != ErrorKind::kNoInterior) throw;
        failure = InputError(ErrorKind::kNoInterior, name,
                             thicker.problem() + " (walls thickened by robust_thickness up to " +
                                 number_text(step) + "L = " + number_text(step * longest) +
                                 " enclose nothing either)");
      }
    }
    throw *failure;
  }
}

std::string describe(const RobustSolid& s) {
  return "the robust solid at resolution " + std::to_string(s.resolution) + " (" +
         count_text(s.mesh.triangles.size(), "triangle") + "): cells of " + number_text(s.cell) +
         " within " + number_text(s.wall_radius) + " of the surface made walls, and the " +
         count_text(s.enclosed_cells, "cell") + " they enclose " +
         (s.enclosed_cells == 1 ? "was" : "were") +
         " added, the boundary smoothed (an outward offset of at most " +
         number_text(s.wall_radius + std::sqrt(3.0) * s.cell) + ")";
}

}  // namespace medspheres
