#include "medspheres/bake/bake.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "medspheres/error.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/number_text.h"

// The method (bake.h states the contract).
// Tolerances. kMinMedialTolerance: below a few eps L (about 1e-15 L) halving the bracket
// no longer moves the probe point of a mesh near the origin (farther out, sooner), so a
// smaller tolerance could never be reached and every search would run to kMaxBisections;
// 1e-9 L keeps well clear of that up to coordinates of about 1e6 L, and is a million times
// finer than the default. With it the bracket is short enough after about 60 halvings.
// An explicit tolerance must stay below a cell: a bracket as long as a cell no longer says
// which cell the medial point is in, and a tolerance that large also loosens check (a) of
// step 3 by as much.
//
// Medial sphere baking (Stolpner, Kry and Siddiqi, "Medial Spheres for Shape
// Approximation", section 3): spheres centred near the medial surface of a solid,
// each tangent to the boundary and inside the solid.
//
// The method, with every choice the paper leaves open made explicit:
//
// 1. Grid. A regular grid of cubic cells of size h = L / `resolution` (L the largest
//    side of the mesh's bounding box) covers the box, centred on it, with one cell
//    more than the box needs along each axis: `resolution` + 1 cells along the longest
//    side, so that grid vertices sit off the box's faces and mid-planes.
//    The sample points are the grid vertices. Each vertex is classified with the
//    generalized winding number (inside when > 0.5), and each inside vertex v gets its
//    exact nearest mesh point c(v) and the unit direction u(v) = (c(v) - v)/|c(v) - v|
//    toward it (the paper's gradient field, nabla D). A vertex exactly on the surface
//    has no direction and counts as outside.
// 2. Cells where the medial surface likely passes. A cell is flagged when at least
//    two of its corners are inside and two inside corners have directions at least
//    `object_angle` apart. Points on the two sides of a medial sheet whose object
//    angle is alpha have directions alpha apart, so this finds the sheets the filter
//    in step 4 keeps, and skips the sheets of tiny object angle that every convex edge
//    of a polyhedron grows.
// 3. Search. From every inside corner p of a flagged cell, along the segment
//    (p, p - gamma u(p)), i.e. away from p's nearest boundary point, binary search for
//    the first point whose direction differs from u(p) by at least `object_angle`.
//    Along that segment the nearest point stays put until the segment meets the
//    medial surface (the property of section 3, from Stolpner and Whitesides 2009),
//    so the search brackets a medial point; it stops when the bracket is shorter than
//    `medial_tolerance` (or after kMaxBisections halvings, which only a tolerance near
//    the rounding of the coordinates could need), and the candidate m is the bracket's
//    near end, whose nearest point A is exact and still on p's side of the sheet. The
//    segment length is gamma = sqrt(3) h / sin(object_angle / 2): a sheet of object angle at
//    least `object_angle` that passes through a cell is met within that distance by
//    the segment from any of the cell's corners.
//    A candidate is dropped unless (a) the distance grew along the segment as it must
//    before the first medial crossing, D(m) >= D(p) + t cos(object_angle) - tolerance,
//    (b) m is inside (winding number), and (c) its object angle, the angle at m between
//    its exact nearest point A and the far-side point B (the nearest point of the
//    bracket's far end), is at least `object_angle`.
// 4. One point per cell. Each surviving candidate belongs to the cell that contains
//    it; a cell keeps its candidate of largest radius (ties: lowest grid vertex
//    index). This is what spreads the spheres evenly (paper, Fig. 1).
// 5. Radius. r = D(m) - s, where D(m) is the distance from m to the mesh as computed
//    (the exact nearest point, rounded to doubles) and s = 1e-12 L + 4 eps (X + L),
//    with eps the double epsilon and X the largest |coordinate| of the bounding box.
//    s exceeds the rounding error of D, so |m - x| > r for every mesh point x: on a
//    closed mesh every sphere lies inside the solid. The derivation: the computed
//    nearest point is a + (v ab + w ac) for a triangle corner a; forming the offset
//    and the distance from the local vectors p - a, ab, ac, all shorter than about 2 L,
//    costs a few eps L (more on slivers, which the 1e-12 L = 4500 eps L term covers),
//    and adding a, whose coordinates reach X, then rounds each coordinate of the point
//    by up to eps X / 2, i.e. moves it by up to (sqrt(3) / 2) eps X and changes D by as
//    much. The 4 eps (X + L) term covers that more than four times over (X + L also
//    bounds the coordinates of the centres, which lie within a cell or two of the
//    box). For a mesh near the origin it is below 1e-15 L and changes nothing; for one
//    far from it (X = 1e6 L, say) the 1e-12 L term alone would not cover the rounding,
//    which is about 2e-10 L there.
//
// Determinism: every step is a pure function of the mesh, the options and the grid
// vertex or cell it works on, and results are gathered in index order, so the same
// input gives a bit-identical sphere list whatever the thread count.
//
// Open, non-manifold or self-intersecting meshes are baked against the solid their
// winding number defines: every centre is inside that solid, and every sphere is
// tangent to its nearest triangle and contains no point of any triangle.

namespace medspheres {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The grid: cubic cells of side h; vertex (i, j, k) sits at origin + h (i, j, k).
struct Grid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double h = 0.0;
  std::array<int, 3> cells = {0, 0, 0};

  std::array<int, 3> verts() const { return {cells[0] + 1, cells[1] + 1, cells[2] + 1}; }
  std::size_t num_vertices() const {
    const auto v = verts();
    return static_cast<std::size_t>(v[0]) * v[1] * v[2];
  }
  std::size_t num_cells() const { return static_cast<std::size_t>(cells[0]) * cells[1] * cells[2]; }
  std::size_t vertex_index(int i, int j, int k) const {
    const auto v = verts();
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(v[0]) * (j + static_cast<std::size_t>(v[1]) * k);
  }
  std::size_t cell_index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(cells[0]) * (j + static_cast<std::size_t>(cells[1]) * k);
  }
  Eigen::Vector3d vertex(int i, int j, int k) const {
    return origin + h * Eigen::Vector3d(i, j, k);
  }
  /// Cell containing p, or -1 outside the grid.
  long long cell_of(const Eigen::Vector3d& p) const {
    int c[3];
    for (int a = 0; a < 3; ++a) {
      const double x = std::floor((p[a] - origin[a]) / h);
      if (!(x >= 0.0) || x >= cells[a]) return -1;
      c[a] = static_cast<int>(x);
    }
    return static_cast<long long>(cell_index(c[0], c[1], c[2]));
  }
};

// Grid of `resolution` cells along the box's longest side plus one cell per axis,
// centred on the box, so that vertices are offset from the box's faces and from its
// mid-planes (both would put sample points exactly on the surface or on the medial
// surface of axis-aligned shapes).
Grid make_grid(const Eigen::AlignedBox3d& box, int resolution) {
  Grid g;
  const double longest = box.sizes().maxCoeff();
  g.h = longest / resolution;
  for (int a = 0; a < 3; ++a) {
    const int n = static_cast<int>(std::ceil(box.sizes()[a] / g.h - 1e-9));
    g.cells[a] = std::max(n, 1) + 1;
  }
  const Eigen::Vector3d span = g.h * Eigen::Vector3d(g.cells[0], g.cells[1], g.cells[2]);
  g.origin = box.center() - span / 2.0;
  return g;
}

struct VertexSample {
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // u: unit vector toward the nearest point
  double distance = 0.0;
  int triangle = -1;
  bool inside = false;
};

struct Candidate {
  Eigen::Vector3d centre;
  double radius = 0.0;
  MedialSample sample;
  std::size_t vertex = 0;  // the grid vertex whose search found it
};

struct Counters {
  std::uint64_t closest = 0, winding = 0;
  std::uint64_t inside = 0;            // grid vertices inside, with a direction
  std::uint64_t evaluated_inside = 0;  // inside by an evaluated winding number...
  std::uint64_t confident = 0;         // ... of at least kConfidentWinding
  void add(const Counters& o) {
    closest += o.closest;
    winding += o.winding;
    inside += o.inside;
    evaluated_inside += o.evaluated_inside;
    confident += o.confident;
  }
};

// A mesh bounds a volume when most grid points its winding number puts inside are
// confidently inside. On a closed or nearly closed surface the winding number is close
// to 1 inside (measured on the test meshes: at least 80% of inside points have
// w >= 0.75, open ones with holes included); on a triangle soup it wanders between 0
// and 1 (51% on trimesh's soup.stl).
constexpr double kConfidentWinding = 0.75;
constexpr double kMinConfidentShare = 0.7;

InputError out_of_range(std::string field, std::string value, std::string problem) {
  return InputError::option(ErrorKind::kOutOfRange, std::move(field), std::move(value),
                            std::move(problem));
}

// An explicit medial tolerance against the range for this box and the finest resolution
// that will be baked.
void check_tolerance(double tolerance, double longest, int resolution) {
  if (const auto problem = medial_tolerance_problem(tolerance, longest, resolution))
    throw std::invalid_argument("medial_tolerance " + problem->problem());
}

// Radius shrink s = 1e-12 L + 4 eps (X + L) of step 5 (derived above).
double radius_shrink(const Eigen::AlignedBox3d& box) {
  const double longest = box.sizes().maxCoeff();
  const double far = box.min().cwiseAbs().cwiseMax(box.max().cwiseAbs()).maxCoeff();
  return 1e-12 * longest + 4.0 * std::numeric_limits<double>::epsilon() * (far + longest);
}

class Baker {
 public:
  Baker(const MeshQuery& query, const BakeOptions& options)
      : query_(query), options_(options), cos_angle_(std::cos(options.object_angle)) {
    const Eigen::AlignedBox3d box = query.mesh().bounds();
    longest_ = box.sizes().maxCoeff();
    grid_ = make_grid(box, options.resolution);
    check_tolerance(options.medial_tolerance, longest_, options.resolution);
    tolerance_ = options.medial_tolerance > 0.0
                     ? options.medial_tolerance
                     : std::min(kDefaultMedialTolerance * longest_, 0.5 * grid_.h);
    shrink_ = radius_shrink(box);
    gamma_ = std::sqrt(3.0) * grid_.h / std::sin(options.object_angle / 2.0);
    threads_ = thread_count(options.threads);
    closed_ = is_closed_consistent(query.mesh());
  }

  // A bake; when no grid vertex is inside the solid, an InputError, or with
  // \p empty_if_no_interior an empty result with stats.inside_vertices 0 (the resolution
  // searches treat that resolution as too coarse).
  BakeResult run(bool empty_if_no_interior = false) {
    const auto t0 = std::chrono::steady_clock::now();
    // The grid is processed a chunk of slabs at a time, holding the vertex layers that
    // bound the chunk: memory grows with resolution squared, not cubed. A chunk holds
    // about 2^16 vertices (at most 2^22), so that a small grid is one parallel pass and
    // a large one synchronizes rarely compared with its work.
    const auto nv = grid_.verts();
    const std::size_t layer = static_cast<std::size_t>(nv[0]) * nv[1];
    const int slabs = grid_.cells[2];
    const int per_chunk = static_cast<int>(
        std::clamp<std::size_t>((std::size_t{1} << 16) / layer, 1,
                                std::max<std::size_t>((std::size_t{1} << 22) / layer, 1)));
    // layers[0] is the chunk's first layer (the previous chunk's last); searched[l]
    // marks vertices of layer l already searched.
    std::vector<VertexSample> layers(layer * (per_chunk + 1));
    std::vector<char> searched(layer * (per_chunk + 1), 0);
    std::vector<Candidate> found;
    sample_layers(0, 1, layers.data());
    for (int k0 = 0; k0 < slabs; k0 += per_chunk) {
      const int count = std::min(per_chunk, slabs - k0);
      sample_layers(k0 + 1, count, layers.data() + layer);
      std::vector<Start> starts;
      for (int k = 0; k < count; ++k)
        flag_slab(k0 + k, layers.data() + k * layer, layers.data() + (k + 1) * layer,
                  searched.data() + k * layer, searched.data() + (k + 1) * layer, starts);
      search(starts, found);
      // The chunk's last layer is the next chunk's first.
      std::copy(layers.begin() + static_cast<std::ptrdiff_t>(count * layer),
                layers.begin() + static_cast<std::ptrdiff_t>((count + 1) * layer), layers.begin());
      std::copy(searched.begin() + static_cast<std::ptrdiff_t>(count * layer),
                searched.begin() + static_cast<std::ptrdiff_t>((count + 1) * layer),
                searched.begin());
      std::fill(searched.begin() + static_cast<std::ptrdiff_t>(layer), searched.end(), 0);
      if (options_.progress)
        options_.progress("baking", static_cast<std::size_t>(k0 + count),
                          static_cast<std::size_t>(slabs));
    }
    // No inside vertex means no search ran and nothing was found.
    if (!empty_if_no_interior || counters_.inside > 0) check_interior();
    BakeResult result = keep_one_per_cell(std::move(found));
    stats_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    stats_.total_seconds = stats_.seconds;
    result.stats = stats_;
    return result;
  }

 private:
  struct Start {
    std::size_t vertex;  // global grid vertex index
    VertexSample sample;
  };

  // Step 1 for vertex layers first .. first + count - 1, written to out (layer by
  // layer): inside status everywhere, nearest point at the inside vertices. A row
  // along x is one unit of work, done in order by one thread, each query hinted with
  // the previous one's triangle: the same answers for any thread count. On a closed
  // mesh the winding number is constant off the surface, so a vertex at exact distance
  // d from the surface passes its status to the next ceil(d / h) - 1 vertices of its
  // row, whose segments lie in the empty open ball: those need no winding number, and
  // outside ones no query at all. On an open mesh every vertex gets its winding number.
  void sample_layers(int first, int count, VertexSample* out) {
    const auto nv = grid_.verts();
    const long long rows = static_cast<long long>(nv[1]) * count;
    Counters total;
#pragma omp parallel num_threads(threads_)
    {
      Counters mine;
#pragma omp for schedule(dynamic, 1)
      for (long long row = 0; row < rows; ++row) {
        const int j = static_cast<int>(row % nv[1]);
        const int k = first + static_cast<int>(row / nv[1]);
        VertexSample* line = out + static_cast<std::size_t>(row) * nv[0];
        int hint = -1;
        long long known = 0;  // following vertices whose status is known
        bool known_inside = false;
        auto ball = [&](double d) {
          return static_cast<long long>(std::floor(d / grid_.h * (1.0 - 1e-12)));
        };
        for (int i = 0; i < nv[0]; ++i) {
          VertexSample& s = line[i];
          s = VertexSample{};
          const Eigen::Vector3d p = grid_.vertex(i, j, k);
          bool inside;
          if (known > 0) {
            inside = known_inside;
            --known;
          } else {
            ++mine.winding;
            const double w = query_.winding_number(p);
            inside = w > 0.5;
            if (inside) {
              ++mine.evaluated_inside;
              mine.confident += w >= kConfidentWinding;
            }
          }
          if (!inside && (!closed_ || known > 0)) continue;
          ++mine.closest;
          const ClosestPoint c = hint < 0 ? query_.closest_point(p) : query_.closest_point(p, hint);
          hint = c.triangle;
          const double d = c.distance();
          if (closed_ && ball(d) > known) {
            known = ball(d);
            known_inside = inside;
          }
          if (!inside || !(d > 0.0)) continue;  // outside, or on the surface: no direction
          ++mine.inside;
          s.inside = true;
          s.distance = d;
          s.direction = (c.point - p) / d;
          s.triangle = c.triangle;
        }
      }
#pragma omp critical
      total.add(mine);
    }
    counters_.add(total);
  }

  // After the last slab: a mesh without a volume is an input error, not an empty set.
  void check_interior() {
    stats_.inside_vertices = counters_.inside;
    if (counters_.inside == 0)
      throw InputError(ErrorKind::kNoInterior, "mesh",
                       "no grid vertex lies inside the solid at resolution " +
                           std::to_string(options_.resolution) +
                           ": the mesh bounds no volume (a flat sheet or a triangle "
                           "soup?), or its parts are thinner than a grid cell");
    const double share =
        static_cast<double>(counters_.confident) /
        static_cast<double>(std::max<std::uint64_t>(counters_.evaluated_inside, 1));
    if (share < kMinConfidentShare)
      throw InputError(ErrorKind::kNoInterior, "mesh",
                       "the mesh bounds no well-defined volume: its winding number is "
                       "ambiguous almost everywhere (only " +
                           std::to_string(static_cast<int>(100 * share)) +
                           "% of the points it puts inside have a winding number of at "
                           "least 0.75; a triangle soup?)");
  }

  // Step 2 for slab k, bounded by vertex layers k (lower) and k + 1 (upper): cells with
  // two inside corners whose directions differ by at least the object angle. Appends
  // their inside corners not searched before, in vertex order; the searched flags keep
  // a vertex from being searched twice.
  void flag_slab(int k, const VertexSample* lower, const VertexSample* upper, char* lower_searched,
                 char* upper_searched, std::vector<Start>& starts) {
    const auto nv = grid_.verts();
    const std::size_t layer = static_cast<std::size_t>(nv[0]) * nv[1];
    std::vector<char> lower_new(layer, 0), upper_new(layer, 0);
    for (int j = 0; j < grid_.cells[1]; ++j)
      for (int i = 0; i < grid_.cells[0]; ++i) {
        const VertexSample* in[8];
        std::size_t where[8];
        bool top[8];
        int n = 0;
        for (int corner = 0; corner < 8; ++corner) {
          const std::size_t v = static_cast<std::size_t>(i + (corner & 1)) +
                                static_cast<std::size_t>(nv[0]) * (j + ((corner >> 1) & 1));
          const bool up = (corner >> 2) != 0;
          const VertexSample& smp = up ? upper[v] : lower[v];
          if (!smp.inside) continue;
          in[n] = &smp;
          where[n] = v;
          top[n] = up;
          ++n;
        }
        bool split = false;
        for (int x = 0; x < n && !split; ++x)
          for (int y = x + 1; y < n && !split; ++y)
            split = in[x]->direction.dot(in[y]->direction) <= cos_angle_;
        if (!split) continue;
        ++stats_.flagged_cells;
        for (int x = 0; x < n; ++x) (top[x] ? upper_new : lower_new)[where[x]] = 1;
      }
    const std::size_t before = starts.size();
    for (std::size_t v = 0; v < layer; ++v)
      if (lower_new[v] && !lower_searched[v]) {
        lower_searched[v] = 1;
        starts.push_back({static_cast<std::size_t>(k) * layer + v, lower[v]});
      }
    for (std::size_t v = 0; v < layer; ++v)
      if (upper_new[v]) {
        upper_searched[v] = 1;
        starts.push_back({static_cast<std::size_t>(k + 1) * layer + v, upper[v]});
      }
    stats_.searches += starts.size() - before;
  }

  Eigen::Vector3d vertex_position(std::size_t v) const {
    const auto n = grid_.verts();
    const int i = static_cast<int>(v % n[0]);
    const int j = static_cast<int>((v / n[0]) % n[1]);
    const int k = static_cast<int>(v / (static_cast<std::size_t>(n[0]) * n[1]));
    return grid_.vertex(i, j, k);
  }

  // The segment (p, p - gamma u(p)) of one start vertex, probed at parameters t: each
  // probe is counted and hinted with the previous probe's triangle.
  struct Segment {
    const MeshQuery& query;
    const VertexSample& s;
    Eigen::Vector3d p;
    Eigen::Vector3d dir;
    double tolerance;
    Counters& count;
    int hint;

    ClosestPoint probe(double t) {
      ++count.closest;
      const ClosestPoint c = query.closest_point(p + t * dir, hint);
      hint = c.triangle;
      return c;
    }
    // Angle between u(p) and the direction from the probe point to its nearest point;
    // a probe on the surface itself has no direction and counts as fully turned (pi).
    double deviation(const ClosestPoint& c, double t) const {
      const Eigen::Vector3d to = c.point - (p + t * dir);
      const double len = to.norm();
      if (!(len > 0.0)) return kPi;
      return std::acos(std::clamp(to.dot(s.direction) / len, -1.0, 1.0));
    }
    // Has the segment passed a sheet of at least `angle` by parameter t? Before the
    // first such sheet the direction has turned by less than `angle`, so the distance
    // has grown at a rate of at least cos(angle). A probe whose direction has turned
    // further, or whose distance has fallen below that line (past a sheet, or out of
    // the solid through its far side, where the direction points back), has passed.
    bool passed(const ClosestPoint& c, double t, double angle) const {
      if (c.distance() < s.distance + t * std::cos(angle) - tolerance) return true;
      return deviation(c, t) >= angle;
    }
    // Bisection on [lo, hi] with passed(lo) false and passed(hi) true; *at_lo and
    // *at_hi receive the probes at the final ends (when probed).
    std::pair<double, double> bisect(double lo, double hi, double angle, ClosestPoint* at_lo,
                                     ClosestPoint* at_hi) {
      for (int step = 0; step < kMaxBisections && hi - lo > tolerance; ++step) {
        const double mid = 0.5 * (lo + hi);
        if (!(mid > lo && mid < hi)) break;  // adjacent doubles: nothing left to halve
        const ClosestPoint c = probe(mid);
        if (passed(c, mid, angle)) {
          hi = mid;
          *at_hi = c;
        } else {
          lo = mid;
          *at_lo = c;
        }
      }
      return std::make_pair(lo, hi);
    }
  };

  // Step 3 for one start vertex. Returns a candidate, or nothing; `reason` tells why
  // a bracketed candidate was dropped (1: invalid, 2: object angle).
  std::optional<Candidate> search_from(const Start& start, Counters& count, int* reason) const {
    *reason = 0;
    const VertexSample& s = start.sample;
    Segment seg{query_, s,         vertex_position(start.vertex), -s.direction, tolerance_,
                count,  s.triangle};
    // Phase 1: the first point past a sheet of at least the object angle.
    ClosestPoint at_lo = seg.probe(0.0), at_hi = seg.probe(gamma_);
    if (!seg.passed(at_hi, gamma_, options_.object_angle)) return std::nullopt;
    auto [lo, hi] = seg.bisect(0.0, gamma_, options_.object_angle, &at_lo, &at_hi);
    const double threshold = refine_gradual_turn(seg, at_lo, at_hi, lo, hi);
    return candidate_at(seg, start.vertex, lo, threshold, reason);
  }

  // Phase 2, for gradual turns only. A tessellated smooth surface grows a fan of
  // tiny-angle sheets, one per convex edge, and across them the direction turns in
  // small steps; phase 1 then stops at the first point turned by the object angle,
  // up to (facet width / 2) / sin(angle) short of the sheet the filter keeps. When the
  // final bracket did not itself jump by the object angle, the turn was gradual: half
  // a cell and a cell further the turn is nearer complete, Delta being the largest
  // turn seen there (probes that left the solid, as their distance shows, do not
  // count), and the sheet is where the direction has turned by Delta / 2, the middle
  // of the transition (never by less than the object angle, so that the search
  // cannot stop at an edge's own small sheet). A sharp jump is a sheet already: the
  // search stays there, and cannot run on to a second sheet beyond it.
  // Moves the bracket [lo, hi]; returns the turn it brackets.
  double refine_gradual_turn(Segment& seg, const ClosestPoint& at_lo, const ClosestPoint& at_hi,
                             double& lo, double& hi) const {
    double threshold = options_.object_angle;
    const bool sharp = seg.deviation(at_hi, hi) - seg.deviation(at_lo, lo) >= options_.object_angle;
    if (sharp) return threshold;
    double full = seg.deviation(at_hi, hi), reach = hi;
    for (const double step : {0.5 * grid_.h, grid_.h}) {
      const double t_beyond = hi + step;
      const ClosestPoint beyond = seg.probe(t_beyond);
      const double turn = seg.deviation(beyond, t_beyond);
      if (beyond.distance() >= seg.s.distance && turn > full) {
        full = turn;
        reach = t_beyond;
      }
    }
    threshold = std::max(options_.object_angle, 0.5 * full);
    if (threshold > options_.object_angle) {
      ClosestPoint ignored_lo = at_lo, ignored_hi = at_hi;
      if (!seg.passed(at_lo, lo, threshold))
        std::tie(lo, hi) = seg.bisect(lo, reach, threshold, &ignored_lo, &ignored_hi);
      else
        std::tie(lo, hi) = seg.bisect(0.0, lo, threshold, &ignored_lo, &ignored_hi);
    }
    return threshold;
  }

  // The candidate at the bracket's near end \p lo, past a turn of \p threshold, checked.
  std::optional<Candidate> candidate_at(Segment& seg, std::size_t vertex, double lo,
                                        double threshold, int* reason) const {
    // The centre is the bracket's near end m; its nearest point A is exact. The far
    // tangency B is the nearest point of m' = m pushed half a cell straight away from A,
    // across the sheet.
    const double t = lo;
    const Eigen::Vector3d m = seg.p + t * seg.dir;
    const ClosestPoint near = seg.probe(t);
    const double d = near.distance();
    // (a) before the sheet the direction has turned by less than 90 degrees, so the
    // distance has not decreased along the segment.
    if (!(d > 0.0) || !(d >= seg.s.distance + t * std::cos(threshold) - 2.0 * tolerance_)) {
      *reason = 1;
      return std::nullopt;
    }
    // (b) the centre is inside the solid.
    ++seg.count.winding;
    if (!(query_.winding_number(m) > 0.5)) {
      *reason = 1;
      return std::nullopt;
    }
    // (c) object angle: the angle between the spokes on the two sides of the sheet, m
    // to A and m' to B. (At a true medial point the two are the directions to its two
    // tangency points; measuring B's spoke from m itself would overstate the angle
    // wherever m is close to the surface.)
    const Eigen::Vector3d a = near.point - m;
    const Eigen::Vector3d pushed = m - (0.5 * grid_.h / d) * a;
    ++seg.count.closest;
    const ClosestPoint far = query_.closest_point(pushed, near.triangle);
    const Eigen::Vector3d b = far.point - pushed;
    const double na = a.norm(), nb = b.norm();
    const double angle =
        (na > 0.0 && nb > 0.0) ? std::acos(std::clamp(a.dot(b) / (na * nb), -1.0, 1.0)) : 0.0;
    if (!(angle >= options_.object_angle)) {
      *reason = 2;
      return std::nullopt;
    }
    Candidate out;
    out.centre = m;
    out.radius = d - shrink_;
    out.sample.near_point = near.point;
    out.sample.far_point = far.point;
    out.sample.object_angle = angle;
    out.vertex = vertex;
    if (!(out.radius > 0.0)) {
      *reason = 1;
      return std::nullopt;
    }
    return out;
  }

  // Step 3 for the starts of one slab, in parallel; results appended in start order.
  void search(const std::vector<Start>& starts, std::vector<Candidate>& found) {
    std::vector<std::optional<Candidate>> results(starts.size());
    std::vector<signed char> reasons(starts.size(), 0);
    const long long n = static_cast<long long>(starts.size());
    Counters total;
#pragma omp parallel num_threads(threads_)
    {
      Counters mine;
#pragma omp for schedule(dynamic, 4)
      for (long long i = 0; i < n; ++i) {
        int reason = 0;
        results[i] = search_from(starts[i], mine, &reason);
        reasons[i] = static_cast<signed char>(reason);
      }
#pragma omp critical
      total.add(mine);
    }
    counters_.add(total);
    for (std::size_t i = 0; i < results.size(); ++i) {
      if (results[i]) found.push_back(*results[i]);
      if (reasons[i] == 1) ++stats_.rejected_invalid;
      if (reasons[i] == 2) ++stats_.rejected_angle;
      if (results[i] || reasons[i] != 0) ++stats_.candidates;
    }
  }

  // Step 4: per cell, the candidate of largest radius (ties: lowest start vertex).
  BakeResult keep_one_per_cell(std::vector<Candidate> found) {
    for (Candidate& c : found) c.sample.cell = static_cast<int>(grid_.cell_of(c.centre));
    found.erase(std::remove_if(found.begin(), found.end(),
                               [](const Candidate& c) { return c.sample.cell < 0; }),
                found.end());
    std::sort(found.begin(), found.end(), [](const Candidate& a, const Candidate& b) {
      if (a.sample.cell != b.sample.cell) return a.sample.cell < b.sample.cell;
      if (a.radius != b.radius) return a.radius > b.radius;
      return a.vertex < b.vertex;
    });
    BakeResult r;
    for (std::size_t i = 0; i < found.size(); ++i) {
      if (i > 0 && found[i].sample.cell == found[i - 1].sample.cell) continue;
      r.spheres.spheres.push_back({found[i].centre, found[i].radius});
      r.samples.push_back(found[i].sample);
    }
    stats_.resolution = options_.resolution;
    stats_.cell_size = grid_.h;
    stats_.medial_tolerance = tolerance_;
    stats_.grid = grid_.cells;
    stats_.spheres = r.spheres.size();
    stats_.closest_point_queries = counters_.closest;
    stats_.winding_queries = counters_.winding;
    if (!r.spheres.empty()) {
      stats_.min_radius = std::numeric_limits<double>::infinity();
      for (const Sphere& s : r.spheres.spheres) {
        stats_.min_radius = std::min(stats_.min_radius, s.radius);
        stats_.max_radius = std::max(stats_.max_radius, s.radius);
      }
    }
    return r;
  }

  const MeshQuery& query_;
  BakeOptions options_;
  double cos_angle_;
  double longest_ = 0.0;
  Grid grid_;
  double tolerance_ = 0.0;
  double shrink_ = 0.0;  // step 5's radius shrink
  double gamma_ = 0.0;
  int threads_ = 1;
  bool closed_ = false;  // closed and consistently wound: integer winding numbers
  Counters counters_;
  BakeStats stats_;
};

}  // namespace

ToleranceRange medial_tolerance_range(double longest, int resolution) {
  return {kMinMedialTolerance * longest, longest / resolution};
}

std::optional<InputError> medial_tolerance_problem(double tolerance, double longest,
                                                   int resolution) {
  if (tolerance == 0.0) return std::nullopt;
  const ToleranceRange range = medial_tolerance_range(longest, resolution);
  if (tolerance >= range.lo && tolerance < range.hi) return std::nullopt;
  return out_of_range("medial_tolerance", number_text(tolerance),
                      "must be in [" + number_text(range.lo) + ", " + number_text(range.hi) +
                          ") at resolution " + std::to_string(resolution) +
                          ": from 1e-9 of the mesh's bounding box's largest side L = " +
                          number_text(longest) + " up to, not including, the cell size L / " +
                          std::to_string(resolution) + ", got " + number_text(tolerance));
}

std::optional<InputError> bake_options_problem(const BakeOptions& o) {
  if (o.resolution < kMinResolution || o.resolution > kMaxResolution)
    return out_of_range("resolution", std::to_string(o.resolution),
                        "must be in [" + std::to_string(kMinResolution) + ", " +
                            std::to_string(kMaxResolution) + "], got " +
                            std::to_string(o.resolution));
  if (!(o.object_angle > 0.0) || !(o.object_angle < kPi))
    return out_of_range("object_angle", number_text(o.object_angle),
                        "must be in (0, pi) radians, got " + number_text(o.object_angle));
  if (!(o.medial_tolerance >= 0.0) || !std::isfinite(o.medial_tolerance))
    return out_of_range(
        "medial_tolerance", number_text(o.medial_tolerance),
        "must be finite and >= 0 (0: the default), got " + number_text(o.medial_tolerance));
  if (std::string problem = threads_problem(o.threads); !problem.empty())
    return out_of_range("threads", std::to_string(o.threads), std::move(problem));
  return std::nullopt;
}

void validate_bake_options(const BakeOptions& o) {
  if (const auto p = bake_options_problem(o))
    throw std::invalid_argument(p->field() + " " + p->problem());
}

BakeResult bake(const MeshQuery& query, const BakeOptions& options) {
  validate_bake_options(options);
  return Baker(query, options).run();
}

BakeResult bake(const TriangleMesh& mesh, const BakeOptions& options) {
  validate_bake_options(options);
  MeshQueryOptions query_options;
  query_options.cap_holes = true;  // radii bounded by the holes of an open mesh too
  const MeshQuery query(mesh, query_options);
  return Baker(query, options).run();
}

namespace {

// Resolution search shared by the two modes. `low` says a resolution is on the
// coarse side of the boundary: within the sphere budget (an empty bake included), or
// missing the error target. `accept` says its bake may be the answer. When want_largest
// (a budget) the answer is the largest accepted resolution, on the low side; otherwise
// (a target) the smallest, on the high side. From the start resolution, doubling or
// halving moves toward the other side until the boundary is bracketed; bisection narrows
// it to adjacent resolutions; then windows of kResolutionSearchWindow resolutions past
// the boundary (above it for a budget, below for a target) are baked, moving to any
// accepted one, until a window holds none. Doubling also stops when `stalled(previous,
// next)` says a doubling changed nothing that matters: the medial surface is then
// resolved (the single centre of a ball, say) and higher resolutions only cost time.
// Each resolution is baked at most once; `steps` records them in order.
struct SearchOutcome {
  std::optional<BakeResult> best;
  std::vector<SearchStep> steps;
  std::optional<InputError> no_interior;  // the error of the last bake with no inside vertex
  bool any_interior = false;              // some bake had a grid vertex inside
};

template <typename Low, typename Accept, typename Stalled, typename Measure>
SearchOutcome search_resolution(const MeshQuery& query, const BakeOptions& options,
                                int max_resolution, bool want_largest, Low low, Accept accept,
                                Stalled stalled, Measure measure) {
  SearchOutcome out;
  std::map<int, bool> seen;  // resolution -> low
  BakeResult last;
  auto run = [&](int r) {
    if (auto it = seen.find(r); it != seen.end()) return it->second;
    BakeOptions o = options;
    o.resolution = r;
    // An ambiguous winding number (a triangle soup) throws here: it is an error at every
    // resolution. No inside vertex only makes this resolution too coarse.
    last = Baker(query, o).run(true);
    if (last.stats.inside_vertices == 0) {
      out.no_interior =
          InputError(ErrorKind::kNoInterior, "mesh",
                     "no grid vertex lies inside the solid at any resolution tried (up to " +
                         std::to_string(r) +
                         "): the mesh bounds no volume (a flat sheet or a triangle soup?), or "
                         "its parts are thinner than a grid cell");
    } else {
      out.any_interior = true;
    }
    const bool is_low = low(last);
    out.steps.push_back({r, last.spheres.size(), measure(last)});
    if (accept(last) && (!out.best || (want_largest ? r > out.best->stats.resolution
                                                    : r < out.best->stats.resolution)))
      out.best = last;
    seen.emplace(r, is_low);
    return is_low;
  };
  int r = std::clamp(options.resolution, kMinResolution, max_resolution);
  const bool g = run(r);
  const bool up = g;  // on the coarse side: go finer
  int other = -1;
  for (;;) {
    const int next = up ? std::min(2 * r, max_resolution) : std::max(r / 2, kMinResolution);
    if (next == r) break;  // reached a limit without finding the other side
    const BakeResult previous = last;
    if (run(next) != g) {
      other = next;
      break;
    }
    r = next;
    if (up && stalled(previous, last)) break;
  }
  if (other < 0) return out;
  int low_r = g ? r : other, high_r = g ? other : r;
  while (high_r - low_r > 1) {
    const int mid = low_r + (high_r - low_r) / 2;
    if (run(mid))
      low_r = mid;
    else
      high_r = mid;
  }
  // The windows past the boundary.
  int boundary = want_largest ? low_r : high_r;
  for (int k = 1; k <= kResolutionSearchWindow; ++k) {
    const int q = want_largest ? boundary + k : boundary - k;
    if (q < kMinResolution || q > max_resolution) break;
    run(q);
    if (out.best && out.best->stats.resolution == q) {
      boundary = q;  // accepted: a new window from here
      k = 0;
    }
  }
  return out;
}

void check_search(const MeshQuery& query, const BakeOptions& options, int max_resolution) {
  if (max_resolution < kMinResolution || max_resolution > kMaxResolution)
    throw std::invalid_argument("max resolution must be in [" + std::to_string(kMinResolution) +
                                ", " + std::to_string(kMaxResolution) + "], got " +
                                std::to_string(max_resolution));
  validate_bake_options(options);
  check_tolerance(options.medial_tolerance, query.mesh().bounds().sizes().maxCoeff(),
                  max_resolution);
}

// The search's details in the result's stats.
BakeResult finish(SearchOutcome&& found, std::chrono::steady_clock::time_point t0) {
  BakeResult result = std::move(*found.best);
  result.stats.search = std::move(found.steps);
  result.stats.total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace

BakeResult bake_max_spheres(const MeshQuery& query, std::size_t max_spheres,
                            const BakeOptions& options, int max_resolution) {
  const auto t0 = std::chrono::steady_clock::now();
  if (max_spheres < 1) throw std::invalid_argument("max spheres must be >= 1");
  check_search(query, options, max_resolution);
  SearchOutcome found = search_resolution(
      query, options, max_resolution, true,
      [&](const BakeResult& r) { return r.spheres.size() <= max_spheres; },
      [&](const BakeResult& r) { return !r.spheres.empty() && r.spheres.size() <= max_spheres; },
      [](const BakeResult& a, const BakeResult& b) {
        return !a.spheres.empty() && b.spheres.size() <= a.spheres.size();
      },
      [](const BakeResult&) { return std::numeric_limits<double>::quiet_NaN(); });
  if (!found.best) {
    if (!found.any_interior && found.no_interior) throw *found.no_interior;
    // The fewest spheres any resolution gave, and where.
    const SearchStep* fewest = nullptr;
    std::string tried;
    for (const SearchStep& s : found.steps) {
      if (s.spheres > 0 && (!fewest || s.spheres < fewest->spheres)) fewest = &s;
      tried += (tried.empty() ? "" : ", ") + std::to_string(s.resolution);
    }
    throw InputError::option(
        ErrorKind::kUnreachable, "max_spheres", std::to_string(max_spheres),
        "no resolution tried (" + tried + ") gives between 1 and " + std::to_string(max_spheres) +
            " spheres: " +
            (fewest ? "the fewest found is " + std::to_string(fewest->spheres) + " at resolution " +
                          std::to_string(fewest->resolution)
                    : std::string("none gave any sphere")));
  }
  return finish(std::move(found), t0);
}

BakeResult bake_target_error(const MeshQuery& query, double target, const ErrorFn& error,
                             const BakeOptions& options, int max_resolution) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!(target > 0.0) || !std::isfinite(target))
    throw std::invalid_argument("target error must be finite and > 0");
  if (!error) throw std::invalid_argument("bake_target_error needs an error function");
  check_search(query, options, max_resolution);
  double best_error = std::numeric_limits<double>::infinity();
  int highest = 0;
  std::map<int, double> errors;  // by resolution, so that no set is measured twice
  auto error_of = [&](const BakeResult& r) {
    if (r.spheres.empty()) return 1.0;  // misses the whole volume; never measured
    auto it = errors.find(r.stats.resolution);
    if (it == errors.end()) it = errors.emplace(r.stats.resolution, error(r.spheres)).first;
    return it->second;
  };
  auto meets = [&](const BakeResult& r) { return !r.spheres.empty() && error_of(r) <= target; };
  SearchOutcome found = search_resolution(
      query, options, max_resolution, false,
      [&](const BakeResult& r) {
        const double e = error_of(r);
        if (!r.spheres.empty()) best_error = std::min(best_error, e);
        highest = std::max(highest, r.stats.resolution);
        return !meets(r);
      },
      meets,
      [&](const BakeResult& a, const BakeResult& b) {
        return !a.spheres.empty() && !b.spheres.empty() && error_of(b) >= error_of(a);
      },
      error_of);
  if (!found.best) {
    if (!found.any_interior && found.no_interior) throw *found.no_interior;
    throw InputError::option(
        ErrorKind::kUnreachable, "target_error", number_text(target),
        "no resolution tried reaches the target error " + number_text(target) +
            ": the best error is " + number_text(best_error) + ", up to resolution " +
            std::to_string(highest) +
            (highest < max_resolution ? ", where doubling the resolution stopped reducing it"
                                      : ""));
  }
  return finish(std::move(found), t0);
}

}  // namespace medspheres
