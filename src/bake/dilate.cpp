#include "medspheres/bake/dilate.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>

#include "medspheres/error.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/measure/union_volume.h"
#include "medspheres/threads.h"

// The steps (dilate.h states the contract).
// Conservative dilation (Stolpner, Kry and Siddiqi, section 5.1): grow and add spheres
// so that a set of internal medial spheres S_D hugs the surface of the solid, giving
// S+. Distance queries between objects need S+: the union of internal spheres lies
// inside the object, so distances between such unions are too large.
//
// The steps, on the union's dual complex (union_volume.h):
// 1. v-points. For each triangle (i, j, k) of the dual complex, the points where
//    spheres i, j and k meet on the boundary of the union. For each v-point v, with m
//    the nearest mesh point to v, every sphere of its triangle grows until it covers m.
//    Beyond the paper, `max_protrusion` caps this: a sphere grows for m only if, grown,
//    it would stick out of the solid by at most that much (its radius minus the exact
//    distance from its centre to the mesh); a point m that no sphere of its triangle
//    may cover joins the vertices of step 3, which gets a small sphere added there.
// 2. Lone edges. For each edge (i, j) of the dual complex in no triangle, two points
//    drawn at random (seeded) on the circle where spheres i and j meet are treated
//    like v-points of spheres i and j.
// 3. Vertex spheres. Each mesh vertex u (and each point m left by the cap of step 1)
//    whose nearest point t on the union is farther than `vertex_tolerance` gets a new
//    sphere with r = |t - u| / 2 centred at
//    u + r (t - u) / |t - u|, which touches both. Vertices are visited in order of
//    decreasing distance (ties: lower index), each against the union as it stands, so
//    a new sphere that covers later vertices spares them theirs. (Candidates are made
//    64 vertices at a time, in parallel, with t taken on the spheres present before
//    this step; each is added only if its vertex is still uncovered when its turn
//    comes, so the result does not depend on the thread count.)
// 4. Optional, beyond the paper (`cover_tolerance` >= 0): rounds of fresh surface
//    samples (area-weighted, plus every vertex), each sample farther than the tolerance
//    outside the union getting a sphere as in step 3, cap included, that comes within
//    half the tolerance of it (so that the samples around it are covered too), until a
//    round finds none or the caps are hit. The largest uncovered distance of the last
//    round is reported. It bounds the samples of that round only: a denser sampling
//    finds somewhat larger gaps (bench_dilate measures 10^5 fresh samples).
//
// Spheres only grow or are added: S_D is contained in S+, so every distance between
// two sphere sets built this way is at most the distance between their S_D. The order
// of S+ is: the spheres of S_D (grown) in their order, then the added spheres in the
// order they were added. Deterministic for given input and options, whatever the
// thread count.

namespace medspheres {

namespace {

constexpr double kPi = 3.14159265358979323846;

void validate(const DilateOptions& o) {
  if (!(o.vertex_tolerance >= 0.0) || !std::isfinite(o.vertex_tolerance))
    throw std::invalid_argument("vertex tolerance must be finite and >= 0 (0: default)");
  if (!(o.max_protrusion >= 0.0))
    throw std::invalid_argument("max protrusion must be >= 0 (infinite: no cap)");
  if (!std::isfinite(o.cover_tolerance))
    throw std::invalid_argument("cover tolerance must be finite (< 0: off)");
  if (o.cover_tolerance >= 0.0) {
    if (o.cover_samples < 1) throw std::invalid_argument("cover samples must be >= 1");
    if (o.cover_max_rounds < 1) throw std::invalid_argument("cover rounds must be >= 1");
    if (!(o.cover_max_added > 0.0) || !std::isfinite(o.cover_max_added))
      throw std::invalid_argument("cover added-sphere cap must be finite and > 0");
  }
  check_threads(o.threads);
}

// A unit vector perpendicular to the unit vector n, the same for the same n.
Eigen::Vector3d perpendicular(const Eigen::Vector3d& n) {
  int axis;
  n.cwiseAbs().minCoeff(&axis);
  return n.cross(Eigen::Vector3d::Unit(axis)).normalized();
}

// The sphere added for a point u of the surface whose nearest point on the union is t.
// Without a protrusion cap it is the paper's, Fig. 4(b): diameter from u to t, centre
// (u + t) / 2. Under a cap it is the largest of three candidates that stick out of the
// solid by at most the cap and come within the tolerance of u: the paper's sphere when
// it keeps to the cap, and the largest sphere on each of two rays from u into the solid
// that sticks out by exactly the cap. (The largest, because the paper's sphere is tiny
// when u is only a little farther than the tolerance from the union, and such spheres
// would have to be added by the thousand.) On a ray c(s) = u + s d, with D the signed
// distance to the mesh (positive inside), such a sphere has radius D(c) + cap and misses
// u by f(s) = s - D(c(s)) - cap; D is 1-Lipschitz, so f is nondecreasing, f(0) <= 0 for u
// on the surface, and bisection finds the largest s with f(s) <= tolerance. The rays: toward
// t, and along the inward normal of the triangle nearest u, along which D grows fastest.
// Either may reach the medial surface, at most a bounding-box diagonal away.
class SphereMaker {
 public:
  SphereMaker(const MeshQuery& query, double cap, double tolerance)
      : query_(query), cap_(cap), tolerance_(tolerance) {}

  Sphere make(const Eigen::Vector3d& u, const Eigen::Vector3d& t) const {
    const Sphere paper{0.5 * (u + t), 0.5 * (t - u).norm()};
    if (!std::isfinite(cap_)) return paper;
    Sphere best = along(u, (t - u) / (2.0 * paper.radius), diagonal_);
    if (paper.radius - depth(paper.center) <= cap_ && paper.radius > best.radius) best = paper;
    const std::array<Eigen::Vector3d, 3> tri =
        query_.triangle_corners(query_.closest_point(u).triangle);
    const Eigen::Vector3d n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
    if (n.squaredNorm() > 0.0) {
      const Sphere inward = along(u, -n.normalized(), diagonal_);
      if (inward.radius > best.radius) best = inward;
    }
    return best;
  }

 private:
  // The largest sphere on the ray u + s dir, s in [0, reach], to within 2% of `step` in s,
  // step = cap + tolerance (at least 1e-6 reach). f(0) <= tolerance, so s doubles from
  // step while f stays within the tolerance, then bisection narrows the last bracket.
  // Evaluations of f (a closest point and a winding number each): a doubling that stops
  // at 2^J step leaves a bracket of 2^(J-1) step, which J + 5 halvings take down to 2% of
  // step, so 2J + 6 in all (7 for J = 0). The spheres are mostly small beside the
  // diagonal (J of 1 or 2): about ten evaluations instead of the 24 of a bisection over
  // [0, reach]. The worst case is a step at its floor of 1e-6 reach and a sphere about as
  // large as the reach: 21 evaluations doubling up to the reach, then 25 halvings of a
  // bracket of about half the reach, 46 in all (and one more for the radius).
  Sphere along(const Eigen::Vector3d& u, const Eigen::Vector3d& dir, double reach) const {
    const auto f = [&](double s) { return s - depth(u + s * dir) - cap_; };
    const double step = std::max(cap_ + tolerance_, 1e-6 * reach);
    double lo = 0.0, hi = std::min(step, reach);
    while (hi < reach && f(hi) <= tolerance_) {
      lo = hi;
      hi = std::min(2.0 * hi, reach);
    }
    if (hi == reach && f(hi) <= tolerance_) lo = hi;
    while (hi - lo > 0.02 * step) {
      const double mid = 0.5 * (lo + hi);
      (f(mid) <= tolerance_ ? lo : hi) = mid;
    }
    const Eigen::Vector3d c = u + lo * dir;
    return {c, std::max(depth(c) + cap_, 0.0)};
  }

  // Signed distance to the mesh, positive inside.
  double depth(const Eigen::Vector3d& p) const {
    const double d = query_.closest_point(p).distance();
    return query_.winding_number(p) > 0.5 ? d : -d;
  }

  const MeshQuery& query_;
  double cap_;
  double tolerance_;
  double diagonal_ = query_.mesh().bounds().sizes().norm();
};

// Adds spheres until every point is within `tolerance` of the union of `spheres`, or
// `cap` spheres were added. `coverage` holds each point's distance to the union of the
// first `base` spheres. Points are visited farthest first (ties: lower index); a point
// still farther than the tolerance from the union as it stands gets the sphere
// SphereMaker gives for it, so a sphere added for one point can spare the next. The
// candidates of the next 64 points still uncovered are computed in parallel, then added
// in order, each only if its point is still uncovered: the result does not depend on
// the thread count. Returns the number of spheres added.
std::size_t add_touching_spheres(std::vector<Sphere>& spheres, std::size_t base,
                                 const std::vector<Eigen::Vector3d>& points,
                                 const std::vector<PointCoverage>& coverage, double tolerance,
                                 std::size_t cap, const SphereMaker& maker, int threads) {
  const int nt = thread_count(threads);
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (coverage[i].outside > tolerance) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (coverage[a].outside != coverage[b].outside)
      return coverage[a].outside > coverage[b].outside;
    return a < b;
  });
  // Distance from point i to the union as it stands (at most its precomputed one).
  auto outside = [&](std::size_t i) {
    double best = coverage[i].outside;
    for (std::size_t j = base; j < spheres.size() && best > tolerance; ++j)
      best = std::min(best, (points[i] - spheres[j].center).norm() - spheres[j].radius);
    return best;
  };
  const std::size_t before = spheres.size();
  constexpr std::size_t kBatch = 64;
  std::vector<std::size_t> batch;
  std::vector<Sphere> candidate;
  for (std::size_t next = 0; next < order.size() && spheres.size() - before < cap;) {
    batch.clear();
    while (next < order.size() && batch.size() < kBatch) {
      const std::size_t i = order[next++];
      if (outside(i) > tolerance) batch.push_back(i);
    }
    candidate.assign(batch.size(), Sphere{});
    const long long n = static_cast<long long>(batch.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(nt)
    for (long long k = 0; k < n; ++k) {
      const std::size_t i = batch[static_cast<std::size_t>(k)];
      const Sphere& s = spheres[static_cast<std::size_t>(coverage[i].ball)];
      const Eigen::Vector3d out = points[i] - s.center;
      // A point outside the union is not a centre, so out is not zero.
      candidate[static_cast<std::size_t>(k)] =
          maker.make(points[i], s.center + (s.radius / out.norm()) * out);
    }
    for (std::size_t k = 0; k < batch.size() && spheres.size() - before < cap; ++k)
      if (candidate[k].radius > 0.0 && outside(batch[k]) > tolerance)
        spheres.push_back(candidate[k]);
  }
  return spheres.size() - before;
}

// A point steps 1 and 2 cover, with the balls that made it (count of them: 3 or 2).
struct Target {
  Eigen::Vector3d point;
  std::array<int, 3> balls;
  int count;
};

// Steps 1 and 2: the v-points of the union, then two seeded random points on each lone
// edge's circle.
std::vector<Target> union_targets(const std::vector<Sphere>& spheres, std::uint64_t seed,
                                  DilateStats& st) {
  std::vector<Target> targets;
  const UnionOfBalls u(spheres);
  for (const VPoint& v : u.v_points()) targets.push_back({v.position, v.balls, 3});
  st.v_points = targets.size();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi);
  for (const EdgeCircle& c : u.lone_edge_circles()) {
    const Eigen::Vector3d a = perpendicular(c.normal), b = c.normal.cross(a);
    for (int k = 0; k < 2; ++k) {
      const double phi = angle(rng);
      targets.push_back({c.center + c.radius * (std::cos(phi) * a + std::sin(phi) * b),
                         {c.balls[0], c.balls[1], -1},
                         2});
    }
  }
  st.edge_points = targets.size() - st.v_points;
  return targets;
}

// Steps 1 and 2: grows the spheres of each target to its nearest mesh point m, within the
// cap; returns the points m no sphere of their target may cover.
std::vector<Eigen::Vector3d> grow_to_targets(const MeshQuery& query, std::vector<Sphere>& spheres,
                                             const std::vector<Target>& targets,
                                             const DilateOptions& options, DilateStats& st) {
  std::vector<Eigen::Vector3d> where(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i) where[i] = targets[i].point;
  const std::vector<ClosestPoint> nearest = query.closest_points(where, options.threads);
  // With a cap, a sphere may grow to radius r only while r - D(c) <= cap, D(c) the
  // exact distance from its centre to the mesh.
  std::vector<double> limit(spheres.size(), std::numeric_limits<double>::infinity());
  if (std::isfinite(options.max_protrusion)) {
    // Protrusion r - D(c), so the largest radius within the cap is r - protrusion + cap.
    const std::vector<double> protrusion = sphere_protrusions(query, spheres, options.threads);
    for (std::size_t i = 0; i < spheres.size(); ++i)
      limit[i] = spheres[i].radius - protrusion[i] + options.max_protrusion;
  }
  std::vector<double> radius(spheres.size());
  for (std::size_t i = 0; i < spheres.size(); ++i) radius[i] = spheres[i].radius;
  std::vector<Eigen::Vector3d> left;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    bool covered = false;
    for (int k = 0; k < targets[i].count; ++k) {
      const std::size_t b = static_cast<std::size_t>(targets[i].balls[static_cast<std::size_t>(k)]);
      const double need = (nearest[i].point - spheres[b].center).norm();
      if (need > limit[b]) continue;
      radius[b] = std::max(radius[b], need);
      covered = true;
    }
    if (!covered) left.push_back(nearest[i].point);
  }
  st.capped_points = left.size();
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const double growth = radius[i] - spheres[i].radius;
    if (growth > 0.0) {
      ++st.grown;
      st.max_growth = std::max(st.max_growth, growth);
      spheres[i].radius = radius[i];
    }
  }
  return left;
}

// Step 3: spheres at the mesh vertices (and the points \p left by the cap) the union misses.
void add_vertex_spheres(const MeshQuery& query, std::vector<Sphere>& spheres,
                        const std::vector<Eigen::Vector3d>& left, const DilateOptions& options,
                        DilateStats& st) {
  const TriangleMesh& mesh = query.mesh();
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const auto& t : mesh.triangles)
    for (int k : t) used[static_cast<std::size_t>(k)] = 1;
  std::vector<Eigen::Vector3d> vertices;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) vertices.push_back(mesh.vertices[v]);
  vertices.insert(vertices.end(), left.begin(), left.end());
  const std::size_t base = spheres.size();
  const std::vector<PointCoverage> cov = point_coverage(spheres, vertices, options.threads);
  const SphereMaker maker(query, options.max_protrusion, st.vertex_tolerance);
  st.added_vertex = add_touching_spheres(spheres, base, vertices, cov, st.vertex_tolerance,
                                         vertices.size(), maker, options.threads);
}

// Step 4: rounds of fresh surface samples until one finds nothing to cover or a cap
// (rounds, or spheres added as a multiple of the \p internal_size spheres of S_D) is hit.
void cover_surface(const MeshQuery& query, std::vector<Sphere>& spheres, std::size_t internal_size,
                   const DilateOptions& options, DilateStats& st) {
  const auto cap =
      static_cast<std::size_t>(options.cover_max_added * static_cast<double>(internal_size));
  for (int round = 0;; ++round) {
    const SurfaceSamples samples = sample_surface(
        query.mesh(), options.cover_samples, options.seed + 1 + static_cast<std::uint64_t>(round));
    const std::vector<PointCoverage> cov = point_coverage(spheres, samples.points, options.threads);
    double worst = 0.0;
    for (const PointCoverage& c : cov) worst = std::max(worst, c.outside);
    st.uncovered_max = worst;
    st.cover_rounds = round;
    if (worst <= options.cover_tolerance) {
      st.cover_reached = true;
      break;
    }
    if (round == options.cover_max_rounds || st.added_cover >= cap) break;
    const SphereMaker maker(query, options.max_protrusion, 0.5 * options.cover_tolerance);
    st.added_cover +=
        add_touching_spheres(spheres, spheres.size(), samples.points, cov, options.cover_tolerance,
                             cap - st.added_cover, maker, options.threads);
  }
}

}  // namespace

DilateResult dilate(const MeshQuery& query, const SphereSet& internal,
                    const DilateOptions& options) {
  validate(options);
  validate_sphere_set(internal, "sphere set");
  if (internal.empty()) throw InputError("sphere set", "there is no sphere to dilate");
  const auto t0 = std::chrono::steady_clock::now();
  const double longest = query.mesh().bounds().sizes().maxCoeff();

  DilateResult result;
  DilateStats& st = result.stats;
  st.input_spheres = internal.size();
  st.vertex_tolerance = options.vertex_tolerance > 0.0 ? options.vertex_tolerance : 0.005 * longest;
  std::vector<Sphere> spheres = internal.spheres;
  const std::vector<Target> targets = union_targets(spheres, options.seed, st);
  const std::vector<Eigen::Vector3d> left = grow_to_targets(query, spheres, targets, options, st);
  add_vertex_spheres(query, spheres, left, options, st);
  if (options.cover_tolerance >= 0.0) cover_surface(query, spheres, internal.size(), options, st);

  result.spheres.spheres = std::move(spheres);
  result.spheres.metadata_json = internal.metadata_json;
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace medspheres
