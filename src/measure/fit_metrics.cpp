// Fit metrics of a sphere set against a mesh; see fit_metrics.h for the definitions.
#include "medspheres/measure/fit_metrics.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "medspheres/error.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/number_text.h"
#include "medspheres/threads.h"
#include "union_grid.h"

// The metrics and their derivations (fit_metrics.h states the contract).
// Fit metrics: how well a set of balls S approximates the solid Omega bounded by a
// triangle mesh. The paper's normalized volumetric error (section 4.1), exact or a lower
// bound, and beyond the paper a Monte-Carlo estimate of the true error that holds for any
// set, and how far the mesh surface lies outside the union (what a collision checker
// misses).
//
// Frames and units. The mesh and the balls share one frame M and one unit of length.
// Lengths are reported in that unit, volumes in units^3, areas in units^2. L denotes the
// largest side of the mesh's bounding box.
//
// The solid. The mesh is oriented first (orient_mesh on a copy: consistent winding,
// closed components turned outward), so a raw mesh is measured like a loaded one.
// - vol(Omega) = V is defined when every component is closed (see mesh_report.h): it is
//   the sum of the components' divergence-theorem volumes, each positive once oriented,
//   i.e. the integral of the winding number. That is the volume of the solid when the
//   surface does not intersect itself and components do not nest; a region inside two
//   components, or enclosed twice by a surface that passes through itself, is counted
//   twice (the Monte Carlo below measures how much, and FitReport::warnings says so). The
//   volume of an open mesh is not defined, and neither is nerr.
// - The mesh self-intersects when two of its triangles meet other than at the vertices and
//   edges they share (self_intersection.h; touching counts). FitEvaluator finds the pairs
//   once, at construction.
// - Inside means a generalized winding number > 0.5 (mesh_query.h). For a closed mesh
//   this is Omega; for an open one it is the solid its winding number defines, the solid
//   the baker fills, and the one the Monte-Carlo estimate measures.
//
// Protrusion of a ball (c, r): r - s d, with d the exact distance from c to the mesh and
// s = +1 when c is inside, -1 when not (a ball whose centre is outside protrudes by
// r + d). For a closed mesh it is <= 0 exactly when the ball lies in the closed solid.
// For an open mesh d is the distance to the mesh with its holes capped
// (MeshQueryOptions::cap_holes), so that a ball reaching out through a hole protrudes.
//
// nerr (paper section 4.1), with U = vol(S) exact (union_volume.h) and
// Err = vol(S \ Omega) + vol(Omega \ S):
// - kind "exact" when no protrusion exceeds the tolerance t = kProtrusionTolerance L:
//   nerr = (V - U) / V. A ball protruding by t_i <= t has its outside part in a shell of
//   thickness t_i, so 0 <= Err / V - nerr <= nerr_slack = 2 sum_i 4 pi r_i^2 max(t_i, 0)
//   / V, which VolumeError reports (0 for baked sets: their protrusions are negative);
// - kind "lower_bound" otherwise: nerr = |V - U| / V <= Err / V (Lemma 1);
// - kind "approximate" when the mesh self-intersects: nerr is the value of the two rules
//   above, but V may count the regions where parts of the surface overlap as often as they
//   are covered, so it is neither exact nor a bound (two parts that only touch leave V
//   exact; the pairs do not tell, the Monte-Carlo multiply covered volume does). A warning
//   names the number of intersecting pairs;
// - kind "undefined" when V is not defined or not positive: nerr is NaN.
// The kinds are decided in the order undefined, approximate, exact / lower_bound.
// The tolerance: the baker shrinks radii by 1e-12 L + 4 eps (X + L), X the largest
// |coordinate| of the box (bake.cpp), so its spheres protrude by about minus that, give
// or take the rounding of the distance (a few ulps of the coordinates).
// kProtrusionTolerance = 1e-9 also accepts sets rounded to 12 significant digits (for
// coordinates up to about 100 L from the origin); the error it can hide is bounded by
// nerr_slack <= 2 t A / V, A the balls' total sphere area, and is reported rather than
// assumed.
//
// Monte-Carlo error (any mesh, any set). N points uniform in the box B that bounds both
// the mesh and the balls; point i comes from a counter-based generator keyed by the seed
// and i, so the points do not depend on the thread count. Each point is classed as in
// Omega (winding number > 0.5) and in S (some closed ball). On a closed mesh two cases
// need no winding-number query, and get the exact winding number: a point in a ball of
// protrusion <= 0 whose centre has winding number 1 (the surface does not cross the
// ball), and a point in a cell of a grid over B whose centre is farther from the surface
// than the cell's half diagonal (the surface does not cross the cell, so the winding
// number, an integer, is the one at the centre; about one cell per 16 points). The
// fraction p^ of points in exactly one of Omega and S estimates p = Err / vol(B).
// - Closed mesh: estimate vol(B) p^ / V, with the 95% Wilson score interval for p scaled
//   the same way. Wilson, because p is small (the error is a thin layer of the solid):
//   the normal-approximation interval p^ +- 1.96 sigma then undercovers and shrinks to a
//   point when no point is hit, while Wilson's keeps close to 95% coverage for small p
//   and stays within [0, 1].
// - Open mesh: V is not defined, so the error is normalized by the volume of the winding
//   solid estimated from the same points. The estimate is a ratio of two means; its
//   interval is the estimate +- 1.96 sigma, sigma from the delta method.
// sigma, the standard error of the estimate, is reported with each interval.
//
// Coverage of the surface. sample_surface draws area-weighted points on the mesh (the
// same points for a seed) and appends every vertex used by a triangle; point_coverage
// gives, for each point, its distance to the union (0 when it lies in a ball). The max is
// over samples and vertices; the mean and the 95th percentile are over the area-weighted
// samples alone, where they estimate the mean and the percentile over the surface
// (vertices crowd where the tessellation is fine, which would bias them).
//
// Determinism. For given inputs and seed every number reported, except the timings, is
// bit-identical for every thread count: each point's work is independent, counts are
// integers, and sums run in index order.
//
// Errors. An empty ball list, or a ball with a non-finite coordinate, a radius not
// finite and > 0 or a bounding box that is not finite (validate_sphere_set), throws
// InputError with source "sphere set"; so does, in evaluate(), a set reaching so far
// that the box B has no finite volume. Subnormal radii are valid. Options out of range
// throw std::invalid_argument naming the option. A mesh without triangles, with non-finite
// coordinates or bad indices throws std::invalid_argument (as MeshQuery does).
//
// Thread safety: a FitEvaluator is immutable after construction; its const members may
// be called from several threads at once.

namespace medspheres {

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;
constexpr double kZ95 = 1.959963984540054;  // two-sided 95% quantile of the normal law

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void require_balls(const std::vector<Sphere>& balls) {
  if (balls.empty()) throw InputError("sphere set", "has no spheres");
  SphereSet set;
  set.spheres = balls;
  validate_sphere_set(set, "sphere set");
}

// Uniform numbers in [0, 1) indexed by a counter: number n is the n-th output of the
// SplitMix64 generator (Steele, Lea and Flood 2014) started from a key made of the seed and
// a stream, so any number can be drawn without the ones before it.
class CounterUniform {
 public:
  CounterUniform(std::uint64_t seed, std::uint64_t stream) : key_(mix(seed ^ mix(stream))) {}
  double operator()(std::uint64_t n) const {
    return static_cast<double>(mix(key_ + (n + 1) * kGamma) >> 11) * 0x1.0p-53;
  }

 private:
  static constexpr std::uint64_t kGamma = 0x9e3779b97f4a7c15ULL;
  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  std::uint64_t key_;
};

// Streams of CounterUniform, so that one seed draws unrelated volume and surface points.
constexpr std::uint64_t kVolumeStream = 1;
constexpr std::uint64_t kSurfaceStream = 2;

// The proportion hits / n with its 95% Wilson score interval, multiplied by scale.
Estimate95 wilson(std::size_t hits, std::size_t n, double scale) {
  const double N = static_cast<double>(n), p = static_cast<double>(hits) / N;
  const double z2 = kZ95 * kZ95, denominator = 1.0 + z2 / N;
  const double centre = (p + z2 / (2.0 * N)) / denominator;
  const double half = kZ95 / denominator * std::sqrt(p * (1.0 - p) / N + z2 / (4.0 * N * N));
  return {scale * p, scale * std::max(0.0, centre - half), scale * std::min(1.0, centre + half),
          scale * std::sqrt(p * (1.0 - p) / N)};
}

// The ratio mean(X) / mean(Y) of two indicators over the same n points, with x, y and xy
// points having X, Y and both; interval by the delta method.
Estimate95 ratio_estimate(std::size_t x, std::size_t y, std::size_t xy, std::size_t n) {
  if (y == 0) return {};
  const double N = static_cast<double>(n);
  const double px = static_cast<double>(x) / N, py = static_cast<double>(y) / N,
               pxy = static_cast<double>(xy) / N, r = px / py;
  const double variance =
      (px * (1.0 - px) - 2.0 * r * (pxy - px * py) + r * r * py * (1.0 - py)) / (N * py * py);
  const double sigma = std::sqrt(std::max(variance, 0.0));
  return {r, std::max(0.0, r - kZ95 * sigma), r + kZ95 * sigma, sigma};
}

std::vector<double> protrusions_of(const MeshQuery& query, const std::vector<Sphere>& balls,
                                   int threads) {
  std::vector<double> out(balls.size());
  const long long n = static_cast<long long>(balls.size());
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
  for (long long i = 0; i < n; ++i) {
    const Sphere& b = balls[static_cast<std::size_t>(i)];
    const double d = query.closest_point(b.center).distance();
    out[static_cast<std::size_t>(i)] = query.inside(b.center) ? b.radius - d : b.radius + d;
  }
  return out;
}

std::vector<PointCoverage> coverage_on(const detail::UnionGrid& grid,
                                       const std::vector<Eigen::Vector3d>& points, int threads) {
  std::vector<PointCoverage> out(points.size());
  const long long n = static_cast<long long>(points.size());
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads)
  for (long long i = 0; i < n; ++i) {
    const detail::UnionGrid::Nearest near = grid.nearest(points[static_cast<std::size_t>(i)]);
    out[static_cast<std::size_t>(i)] = {near.distance, near.ball};
  }
  return out;
}

// A grid over a box that knows the winding number of the cells the surface of a closed
// mesh does not reach, so that points there need no query. A cell whose centre q is
// farther from the surface than the cell's half diagonal (plus a margin for the rounding
// of a point to its cell) lies in a ball the surface does not cross; the winding number of
// a closed mesh is an integer constant there, read at q.
class WindingCells {
 public:
  // About \p cells cubic cells over \p box; none (every cell unknown) when cells is 0.
  WindingCells(const MeshQuery& query, const Eigen::AlignedBox3d& box, std::size_t cells,
               int threads)
      : origin_(box.min()) {
    if (cells == 0) return;
    const Eigen::Vector3d size = box.sizes();
    h_ = std::cbrt(size.prod() / static_cast<double>(cells));
    for (int k = 0; k < 3; ++k) dims_[k] = std::max(1, static_cast<int>(std::ceil(size[k] / h_)));
    const double margin = 64.0 * std::numeric_limits<double>::epsilon() *
                          (box.min().cwiseAbs().cwiseMax(box.max().cwiseAbs()).maxCoeff() + h_);
    const double half_diagonal = 0.5 * std::sqrt(3.0) * h_ + margin;
    winding_.assign(static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2], kUnknown);
    const long long n = static_cast<long long>(winding_.size());
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads)
    for (long long c = 0; c < n; ++c) {
      const long long x = c / (static_cast<long long>(dims_[1]) * dims_[2]);
      const long long y = (c / dims_[2]) % dims_[1], z = c % dims_[2];
      const Eigen::Vector3d q = origin_ + h_ * Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5);
      if (query.closest_point(q).distance() > half_diagonal)
        winding_[static_cast<std::size_t>(c)] =
            static_cast<std::int8_t>(std::clamp(std::lround(query.winding_number(q)), -127L, 127L));
    }
  }

  // The winding number at p: its cell's, or a query when the cell is unknown.
  double winding(const MeshQuery& query, const Eigen::Vector3d& p) const {
    if (!winding_.empty()) {
      std::array<long long, 3> c{};
      bool in_grid = true;
      for (int k = 0; k < 3; ++k) {
        c[k] = static_cast<long long>(std::floor((p[k] - origin_[k]) / h_));
        in_grid = in_grid && c[k] >= 0 && c[k] < dims_[k];
      }
      if (in_grid) {
        const std::int8_t w =
            winding_[static_cast<std::size_t>((c[0] * dims_[1] + c[1]) * dims_[2] + c[2])];
        if (w != kUnknown) return w;
      }
    }
    return query.winding_number(p);
  }

 private:
  static constexpr std::int8_t kUnknown = std::numeric_limits<std::int8_t>::min();
  Eigen::Vector3d origin_;
  double h_ = 1.0;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::int8_t> winding_;
};

// WindingCells holds one cell per this many Monte-Carlo points: classifying a cell costs
// about two point queries, and most points then need none.
constexpr std::size_t kPointsPerWindingCell = 16;

// The Monte-Carlo error. On a closed mesh a point in a ball of protrusion <= 0 whose centre
// has winding number 1 has winding number 1 without a query: the ball lies in the closed
// solid, where the surface does not cross it.
MonteCarloError monte_carlo(const MeshQuery& query, bool closed, const detail::UnionGrid& grid,
                            const std::vector<Sphere>& balls, const VolumeError& volume_error,
                            const FitOptions& options, int threads) {
  const long long nballs = static_cast<long long>(balls.size());
  std::vector<char> simple(balls.size(), 0);
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
  for (long long i = 0; i < nballs; ++i) {
    const std::size_t b = static_cast<std::size_t>(i);
    simple[b] = closed && volume_error.protrusions[b] <= 0.0 &&
                std::lround(query.winding_number(balls[b].center)) == 1;
  }
  MonteCarloError mc;
  mc.samples = options.volume_samples;
  mc.seed = options.seed;
  mc.box = query.mesh().bounds();
  for (const Sphere& b : balls) {
    mc.box.extend(b.center - Eigen::Vector3d::Constant(b.radius));
    mc.box.extend(b.center + Eigen::Vector3d::Constant(b.radius));
  }
  const WindingCells cells(query, mc.box,
                           closed ? options.volume_samples / kPointsPerWindingCell : 0, threads);
  const Eigen::Vector3d lo = mc.box.min(), size = mc.box.sizes();
  const CounterUniform u(options.seed, kVolumeStream);
  unsigned long long in_solid = 0, outside = 0, uncovered = 0, excess = 0, excess2 = 0;
  const long long n = static_cast<long long>(options.volume_samples);
#pragma omp parallel for schedule(dynamic, 1024) num_threads(threads) \
    reduction(+ : in_solid, outside, uncovered, excess, excess2)
  for (long long i = 0; i < n; ++i) {
    const std::uint64_t k = 3 * static_cast<std::uint64_t>(i);
    const Eigen::Vector3d p = lo + Eigen::Vector3d(u(k), u(k + 1), u(k + 2)).cwiseProduct(size);
    const int ball = grid.containing(p);
    const bool in_union = ball >= 0;
    const double w =
        in_union && simple[static_cast<std::size_t>(ball)] ? 1.0 : cells.winding(query, p);
    const bool in_omega = w > 0.5;
    in_solid += in_omega;
    outside += in_union && !in_omega;
    uncovered += in_omega && !in_union;
    if (closed && w > 1.5) {
      const unsigned long long extra = static_cast<unsigned long long>(std::lround(w) - 1);
      excess += extra;
      excess2 += extra * extra;
    }
  }
  mc.in_solid = in_solid;
  mc.outside_solid = outside;
  mc.uncovered = uncovered;
  const double box_volume = size.prod(), N = static_cast<double>(n);
  mc.outside_volume = box_volume * static_cast<double>(outside) / N;
  mc.uncovered_volume = box_volume * static_cast<double>(uncovered) / N;
  mc.solid_volume = wilson(mc.in_solid, mc.samples, box_volume);
  const double mean = static_cast<double>(excess) / N;
  mc.multiple_volume = box_volume * mean;
  mc.multiple_volume_sigma =
      box_volume * std::sqrt(std::max(0.0, static_cast<double>(excess2) / N - mean * mean) / N);
  mc.normalized_by_volume = volume_error.mesh_volume.has_value();
  mc.error = mc.normalized_by_volume ? wilson(mc.outside_solid + mc.uncovered, mc.samples,
                                              box_volume / *volume_error.mesh_volume)
                                     : ratio_estimate(mc.outside_solid + mc.uncovered, mc.in_solid,
                                                      mc.uncovered, mc.samples);
  return mc;
}

TriangleMesh oriented(const TriangleMesh& mesh) {
  TriangleMesh copy = mesh;
  orient_mesh(copy);
  return copy;
}

// V from the report of an oriented mesh (see solid_volume).
std::optional<double> volume_of(const MeshReport& report) {
  if (!report.closed) return std::nullopt;
  double v = 0.0;
  for (const ComponentReport& c : report.component_reports) v += c.signed_volume;
  if (!(v > 0.0)) return std::nullopt;
  return v;
}

}  // namespace

const char* to_string(NerrKind kind) {
  switch (kind) {
    case NerrKind::kExact:
      return "exact";
    case NerrKind::kLowerBound:
      return "lower_bound";
    case NerrKind::kApproximate:
      return "approximate";
    case NerrKind::kUndefined:
      return "undefined";
  }
  return "undefined";
}

std::optional<double> solid_volume(const TriangleMesh& mesh) {
  return volume_of(analyze_mesh(oriented(mesh)));
}

std::vector<double> sphere_protrusions(const MeshQuery& query, const std::vector<Sphere>& balls,
                                       int threads) {
  require_balls(balls);
  return protrusions_of(query, balls, thread_count(threads));
}

SurfaceSamples sample_surface(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed) {
  const std::size_t nt = mesh.triangles.size();
  std::vector<double> cumulative(nt);
  double total = 0.0;
  for (std::size_t t = 0; t < nt; ++t) {
    const Eigen::Vector3d &a = mesh.corner(t, 0), &b = mesh.corner(t, 1), &c = mesh.corner(t, 2);
    total += 0.5 * (b - a).cross(c - a).norm();
    cumulative[t] = total;
  }
  if (count > 0 && !(total > 0.0))
    throw std::invalid_argument("sample_surface: the mesh has zero area");
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const auto& tri : mesh.triangles)
    for (const int v : tri) used[static_cast<std::size_t>(v)] = 1;

  SurfaceSamples out;
  out.area_samples = count;
  out.points.reserve(count + static_cast<std::size_t>(std::count(used.begin(), used.end(), 1)));
  const CounterUniform u(seed, kSurfaceStream);
  // The last triangle of positive area, for a target that rounds up to the total.
  const std::size_t last = static_cast<std::size_t>(
      std::lower_bound(cumulative.begin(), cumulative.end(), total) - cumulative.begin());
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint64_t k = 3 * static_cast<std::uint64_t>(i);
    const double target = u(k) * total;
    const std::size_t t = std::min(
        last,
        static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), target) -
                                 cumulative.begin()));
    // sqrt of a uniform number along the median, a uniform one across: uniform in the triangle.
    const double s = std::sqrt(u(k + 1)), w = u(k + 2);
    const Eigen::Vector3d &a = mesh.corner(t, 0), &b = mesh.corner(t, 1), &c = mesh.corner(t, 2);
    out.points.push_back(a + s * (1.0 - w) * (b - a) + s * w * (c - a));
  }
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) out.points.push_back(mesh.vertices[v]);
  return out;
}

std::vector<PointCoverage> point_coverage(const std::vector<Sphere>& balls,
                                          const std::vector<Eigen::Vector3d>& points, int threads) {
  require_balls(balls);
  const int nt = thread_count(threads);
  return coverage_on(detail::UnionGrid(balls), points, nt);
}

CoverageStats summarize_coverage(const SurfaceSamples& samples,
                                 const std::vector<PointCoverage>& coverage) {
  if (coverage.size() != samples.points.size() || samples.area_samples > samples.points.size())
    throw std::invalid_argument("summarize_coverage: one coverage entry per sample point needed");
  CoverageStats s;
  s.area_samples = samples.area_samples;
  s.vertices = samples.points.size() - samples.area_samples;
  for (std::size_t i = 0; i < coverage.size(); ++i)
    if (i == 0 || coverage[i].outside > s.max) {
      s.max = coverage[i].outside;
      s.max_at = samples.points[i];
    }
  if (s.area_samples == 0) return s;
  std::vector<double> outside(s.area_samples);
  double sum = 0.0;
  for (std::size_t i = 0; i < s.area_samples; ++i) {
    outside[i] = coverage[i].outside;
    sum += outside[i];
  }
  s.mean = sum / static_cast<double>(s.area_samples);
  const std::size_t rank = (95 * s.area_samples + 99) / 100 - 1;  // ceil(0.95 n) - 1
  std::nth_element(outside.begin(), outside.begin() + static_cast<std::ptrdiff_t>(rank),
                   outside.end());
  s.p95 = outside[rank];
  return s;
}

struct FitEvaluator::Solid {
  TriangleMesh mesh;
  MeshReport report;
  SelfIntersections self_intersections;
};

// The report and the self-intersections of the oriented copy are found before the copy
// moves into the MeshQuery: their temporaries (an edge table, the triangles' boxes) then
// never take memory while the hierarchy is held.
FitEvaluator::Solid FitEvaluator::prepare(const TriangleMesh& mesh, int threads) {
  Solid s;
  s.mesh = oriented(mesh);
  s.report = analyze_mesh(s.mesh);
  s.self_intersections = find_self_intersections(s.mesh, threads);
  return s;
}

FitEvaluator::FitEvaluator(const TriangleMesh& mesh, int threads)
    : FitEvaluator(prepare(mesh, threads)) {}

FitEvaluator::FitEvaluator(Solid solid)
    : query_(std::move(solid.mesh),
             [] {
               MeshQueryOptions o;
               o.cap_holes = true;  // distances to the solid's boundary, holes included
               return o;
             }()),
      closed_(solid.report.closed),
      tolerance_(kProtrusionTolerance * solid.report.largest_side()),
      self_intersections_(std::move(solid.self_intersections)) {
  volume_ = volume_of(solid.report);
}

VolumeError FitEvaluator::combine(const std::vector<Sphere>& balls, UnionMeasures measures,
                                  std::vector<double> protrusions) const {
  VolumeError e;
  e.mesh_volume = volume_;
  e.union_measures = std::move(measures);
  e.protrusions = std::move(protrusions);
  e.protrusion_tolerance = tolerance_;
  e.self_intersecting_pairs = self_intersections_.count();
  double slack = 0.0;
  for (std::size_t i = 0; i < e.protrusions.size(); ++i) {
    const double p = e.protrusions[i];
    if (i == 0 || p > e.max_protrusion) {
      e.max_protrusion = p;
      e.max_protrusion_ball = static_cast<int>(i);
    }
    if (p > tolerance_) ++e.protruding;
    if (p > 0.0) slack += 8.0 * kPi * balls[i].radius * balls[i].radius * p;
  }
  if (!volume_) return e;
  const double v = *volume_, u = e.union_measures.volume;
  if (e.protruding == 0) {
    e.kind = NerrKind::kExact;
    e.nerr = (v - u) / v;
    e.nerr_slack = slack / v;
  } else {
    e.kind = NerrKind::kLowerBound;
    e.nerr = std::abs(v - u) / v;
  }
  if (self_intersections_.any()) {  // V may count overlaps more than once: no guarantee left
    e.kind = NerrKind::kApproximate;
    e.nerr_slack = 0.0;
  }
  return e;
}

VolumeError FitEvaluator::volume_error(const std::vector<Sphere>& balls, int threads) const {
  require_balls(balls);
  const int nt = thread_count(threads);
  return combine(balls, measure_union(balls), protrusions_of(query_, balls, nt));
}

FitReport FitEvaluator::evaluate(const std::vector<Sphere>& balls,
                                 const FitOptions& options) const {
  const auto start = Clock::now();
  if (options.volume_samples < 1) throw std::invalid_argument("volume_samples must be >= 1");
  if (options.surface_samples < 1) throw std::invalid_argument("surface_samples must be >= 1");
  const int nt = thread_count(options.threads);
  require_balls(balls);
  // The Monte-Carlo box B holds the mesh and the balls; its volume must be finite.
  Eigen::AlignedBox3d reach = query_.mesh().bounds();
  for (const Sphere& b : balls) {
    reach.extend(b.center - Eigen::Vector3d::Constant(b.radius));
    reach.extend(b.center + Eigen::Vector3d::Constant(b.radius));
  }
  if (!std::isfinite(reach.sizes().prod()))
    throw InputError("sphere set",
                     "the spheres reach so far that the box holding them and the mesh has no "
                     "finite volume (the Monte-Carlo error samples that box)");

  FitReport r;
  r.balls = balls.size();
  r.mesh_closed = closed_;
  auto t = Clock::now();
  UnionMeasures measures = measure_union(balls);
  r.seconds.union_volume = seconds_since(t);
  t = Clock::now();
  std::vector<double> protrusions = protrusions_of(query_, balls, nt);
  r.seconds.protrusion = seconds_since(t);
  r.volume = combine(balls, std::move(measures), std::move(protrusions));

  t = Clock::now();
  const detail::UnionGrid grid(balls);
  r.seconds.grid = seconds_since(t);
  t = Clock::now();
  r.monte_carlo = monte_carlo(query_, closed_, grid, balls, r.volume, options, nt);
  r.seconds.monte_carlo = seconds_since(t);
  t = Clock::now();
  const SurfaceSamples samples =
      sample_surface(query_.mesh(), options.surface_samples, options.seed);
  r.coverage = summarize_coverage(samples, coverage_on(grid, samples.points, nt));
  r.seconds.coverage = seconds_since(t);

  if (!closed_) {
    r.warnings.push_back(
        "the mesh is open: its volume and nerr are not defined; the Monte-Carlo error is "
        "measured against the solid its winding number defines and normalized by that "
        "solid's estimated volume");
  } else {
    if (r.volume.kind == NerrKind::kApproximate)
      r.warnings.push_back(
          "the mesh self-intersects: " + count_text(self_intersections_.count(), "pair") +
          " of triangles " + (self_intersections_.count() == 1 ? "meets" : "meet") +
          " other than at a shared vertex or edge, so the mesh "
          "volume may count the regions where its parts overlap more than once, and nerr is "
          "approximate");
    if (r.monte_carlo.multiple_volume > 0.0) {
      const MonteCarloError& mc = r.monte_carlo;
      r.warnings.push_back(
          "components of the mesh overlap or nest: a volume of about " +
          number_text(mc.multiple_volume) + " +- " + number_text(mc.multiple_volume_sigma) +
          " (Monte Carlo) lies in more than one of them, and the mesh volume counts it as often; "
          "nerr, which divides by the mesh volume, is off by about that over the volume");
    }
  }
  r.seconds.total = seconds_since(start);
  return r;
}

FitReport evaluate_fit(const TriangleMesh& mesh, const std::vector<Sphere>& balls,
                       const FitOptions& options) {
  return FitEvaluator(mesh).evaluate(balls, options);
}

}  // namespace medspheres
