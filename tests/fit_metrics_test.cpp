// Fit metrics against closed forms, brute force and the exact union volume.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/bake/bake.h"
#include "medspheres/error.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "support/ball_formulas.h"
#include "support/sanitizer_build.h"
#include "support/shared_meshes.h"

using namespace medspheres;
using Catch::Matchers::Contains;
using Eigen::Vector3d;

namespace {

using test::ball_volume;
using test::cap_volume;
using test::kPi;
constexpr double kEps = std::numeric_limits<double>::epsilon();

FitOptions quick(std::size_t volume_samples = 200000, std::size_t surface_samples = 20000) {
  FitOptions o;
  o.volume_samples = volume_samples;
  o.surface_samples = surface_samples;
  o.seed = 7;
  return o;
}

// |estimate - exact| in units of the estimate's standard error.
double sigmas_off(const Estimate95& e, double exact) {
  return std::abs(e.estimate - exact) / e.sigma;
}

// Distance from p to the union of the balls by brute force, and whether p is in a ball.
double brute_outside(const std::vector<Sphere>& balls, const Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Sphere& b : balls) {
    const double d2 = (p - b.center).squaredNorm();
    best = std::min(best, d2 <= b.radius * b.radius ? 0.0 : std::sqrt(d2) - b.radius);
  }
  return best;
}

// A box with every triangle of its last face removed, or its winding reversed.
TriangleMesh without_last_triangle(TriangleMesh m) {
  m.triangles.pop_back();
  return m;
}
TriangleMesh reversed(TriangleMesh m) {
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

void check_same(const FitReport& a, const FitReport& b) {
  CHECK(a.volume.union_measures.volume == b.volume.union_measures.volume);
  CHECK(a.volume.protrusions == b.volume.protrusions);
  CHECK(a.volume.nerr == b.volume.nerr);
  CHECK(a.monte_carlo.in_solid == b.monte_carlo.in_solid);
  CHECK(a.monte_carlo.outside_solid == b.monte_carlo.outside_solid);
  CHECK(a.monte_carlo.uncovered == b.monte_carlo.uncovered);
  CHECK(a.monte_carlo.error.estimate == b.monte_carlo.error.estimate);
  CHECK(a.monte_carlo.error.lo == b.monte_carlo.error.lo);
  CHECK(a.monte_carlo.error.hi == b.monte_carlo.error.hi);
  CHECK(a.coverage.max == b.coverage.max);
  CHECK(a.coverage.max_at == b.coverage.max_at);
  CHECK(a.coverage.mean == b.coverage.mean);
  CHECK(a.coverage.p95 == b.coverage.p95);
}

// For a set baked from a closed mesh: nerr is exact (approximate when the mesh intersects
// itself) and the Monte-Carlo error agrees. When components overlap, V counts the shared
// volume M twice and the true error is that of nerr less M / V; M is itself estimated from
// the same points, so its error adds to the bound.
void check_baked(const TriangleMesh& mesh, const FitOptions& options) {
  const FitEvaluator fit(mesh);
  const BakeResult baked = bake(fit.query());
  const FitReport r = fit.evaluate(baked.spheres.spheres, options);
  const bool self_intersecting = fit.self_intersections().any();
  REQUIRE(r.volume.kind == (self_intersecting ? NerrKind::kApproximate : NerrKind::kExact));
  CHECK(r.volume.max_protrusion <= 0.0);
  CHECK(r.volume.nerr_slack == 0.0);
  CHECK(r.volume.nerr > 0.0);
  CHECK(r.monte_carlo.normalized_by_volume);
  const MonteCarloError& mc = r.monte_carlo;
  const double v = *r.volume.mesh_volume;
  INFO("nerr " << r.volume.nerr << ", Monte Carlo " << mc.error.estimate << " +- " << mc.error.sigma
               << ", multiply covered " << mc.multiple_volume << " +- "
               << mc.multiple_volume_sigma);
  CHECK(std::abs(r.volume.nerr - mc.multiple_volume / v - mc.error.estimate) <=
        4.0 * (mc.error.sigma + mc.multiple_volume_sigma / v));
  CHECK(r.warnings.size() == (self_intersecting ? 1u : 0u) + (mc.multiple_volume > 0.0 ? 1u : 0u));
}

}  // namespace

TEST_CASE("solid volume: divergence theorem per closed component, orientation fixed",
          "[fit_metrics]") {
  const TriangleMesh box = make_box({1.0, 1.5, 2.0}, 2);
  REQUIRE(solid_volume(box).has_value());
  CHECK(*solid_volume(box) == Approx(24.0).epsilon(1e-14));
  CHECK(*solid_volume(reversed(box)) == Approx(24.0).epsilon(1e-14));
  TriangleMesh mixed = box;  // every other triangle flipped: inconsistent winding
  for (std::size_t t = 0; t < mixed.triangles.size(); t += 2)
    std::swap(mixed.triangles[t][1], mixed.triangles[t][2]);
  CHECK(*solid_volume(mixed) == Approx(24.0).epsilon(1e-14));

  // Two components, one of them inward: the volumes add.
  TriangleMesh two = make_box({1.0, 1.0, 1.0});
  const TriangleMesh far = reversed(make_box({0.5, 0.5, 0.5}));
  const int base = static_cast<int>(two.vertices.size());
  for (const Vector3d& v : far.vertices) two.vertices.push_back(v + Vector3d(5, 0, 0));
  for (const auto& t : far.triangles)
    two.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  CHECK(*solid_volume(two) == Approx(9.0).epsilon(1e-14));

  CHECK_FALSE(solid_volume(without_last_triangle(box)).has_value());
  CHECK(FitEvaluator(box).closed());
  CHECK_FALSE(FitEvaluator(without_last_triangle(box)).closed());
}

TEST_CASE("one ball inside a box: exact nerr is 1 - vol(ball) / vol(box)", "[fit_metrics]") {
  const TriangleMesh box = make_box({1.0, 1.5, 2.0}, 2);  // volume 2 * 3 * 4
  const std::vector<Sphere> balls = {{Vector3d(0.1, -0.2, 0.3), 0.5}};
  const FitReport r = evaluate_fit(box, balls, quick());
  REQUIRE(r.volume.mesh_volume.has_value());
  CHECK(*r.volume.mesh_volume == Approx(24.0).epsilon(1e-14));
  CHECK(r.volume.union_measures.volume == Approx(ball_volume(0.5)).epsilon(1e-14));
  // The nearest face is x = 1, 0.9 from the centre.
  REQUIRE(r.volume.protrusions.size() == 1);
  CHECK(r.volume.protrusions[0] == Approx(0.5 - 0.9).epsilon(1e-14));
  CHECK(r.volume.max_protrusion_ball == 0);
  CHECK(r.volume.protruding == 0);
  CHECK(r.volume.kind == NerrKind::kExact);
  CHECK(r.volume.nerr == Approx(1.0 - ball_volume(0.5) / 24.0).epsilon(1e-14));
  CHECK(r.volume.nerr_slack == 0.0);
  CHECK(r.volume.protrusion_tolerance == Approx(kProtrusionTolerance * 4.0));
  CHECK(sigmas_off(r.monte_carlo.error, r.volume.nerr) <= 4.0);
  CHECK(r.monte_carlo.error.lo <= r.monte_carlo.error.estimate);
  CHECK(r.monte_carlo.error.estimate <= r.monte_carlo.error.hi);
  CHECK(r.monte_carlo.box.volume() == Approx(24.0).epsilon(1e-14));  // the box is B
  CHECK(r.monte_carlo.in_solid == r.monte_carlo.samples);
  CHECK(r.warnings.empty());
}

TEST_CASE("balls poking out of a box: protrusion in closed form, nerr a lower bound",
          "[fit_metrics]") {
  const TriangleMesh box = make_box({1.0, 1.0, 1.0}, 3);
  // Disjoint balls: inside (0.2 from the face x = -1), poking out of x = 1 by 0.3, and
  // centred outside, 0.3 beyond the face x = 1, so protruding by 0.3 + 0.1.
  const std::vector<Sphere> balls = {{Vector3d(-0.5, 0.0, 0.0), 0.3},
                                     {Vector3d(0.8, 0.0, 0.0), 0.5},
                                     {Vector3d(1.3, 0.0, 0.5), 0.1}};
  const FitEvaluator fit(box);
  const VolumeError e = fit.volume_error(balls);
  REQUIRE(e.protrusions.size() == 3);
  CHECK(e.protrusions[0] == Approx(-0.2).epsilon(1e-14));
  CHECK(e.protrusions[1] == Approx(0.3).epsilon(1e-14));
  CHECK(e.protrusions[2] == Approx(0.4).epsilon(1e-14));
  CHECK(e.max_protrusion == e.protrusions[2]);
  CHECK(e.max_protrusion_ball == 2);
  CHECK(e.protruding == 2);
  CHECK(e.kind == NerrKind::kLowerBound);
  const double u = ball_volume(0.3) + ball_volume(0.5) + ball_volume(0.1);
  CHECK(e.union_measures.volume == Approx(u).epsilon(1e-14));
  CHECK(e.nerr == Approx((8.0 - u) / 8.0).epsilon(1e-14));
  CHECK(sphere_protrusions(fit.query(), balls) == e.protrusions);

  // A protrusion within the tolerance still counts as none, and the slack says how much
  // the exact formula may then miss by: 2 * 4 pi r^2 t / V.
  const double t = 0.5 * fit.protrusion_tolerance();
  const VolumeError tangent = fit.volume_error({{Vector3d(0.5, 0.0, 0.0), 0.5 + t}});
  CHECK(tangent.kind == NerrKind::kExact);
  CHECK(tangent.nerr_slack == Approx(8.0 * kPi * 0.25 * t / 8.0).epsilon(1e-6));
  const VolumeError beyond = fit.volume_error({{Vector3d(0.5, 0.0, 0.0), 0.5 + 4.0 * t}});
  CHECK(beyond.kind == NerrKind::kLowerBound);
}

TEST_CASE("Monte Carlo agrees with the exact symmetric difference of a ball and a box",
          "[fit_metrics]") {
  const TriangleMesh box = make_box({1.0, 1.0, 1.0}, 2);
  SECTION("a ball through one face: one cap outside") {
    const double r = 0.5, cap = cap_volume(r, 0.3);  // centre 0.2 inside the face x = 1
    const FitReport f = evaluate_fit(box, {{Vector3d(0.8, 0.0, 0.0), r}}, quick());
    const double err = cap + (8.0 - (ball_volume(r) - cap));
    CHECK(sigmas_off(f.monte_carlo.error, err / 8.0) <= 4.0);
    CHECK(f.volume.nerr < err / 8.0);  // Lemma 1: a lower bound
    CHECK(f.volume.nerr == Approx((8.0 - ball_volume(r)) / 8.0).epsilon(1e-14));
    const double box_volume = f.monte_carlo.box.volume();
    CHECK(box_volume == Approx(2.3 * 2.0 * 2.0).epsilon(1e-14));
    const double p = cap / box_volume;
    const double sigma = box_volume * std::sqrt(p * (1.0 - p) / f.monte_carlo.samples);
    CHECK(std::abs(f.monte_carlo.outside_volume - cap) <= 4.0 * sigma);
  }
  SECTION("a ball larger than the box's inscribed ball: six caps outside") {
    const double r = 1.2, caps = 6.0 * cap_volume(r, 0.2);  // the caps do not meet: r^2 < 2
    const FitReport f = evaluate_fit(box, {{Vector3d::Zero(), r}}, quick());
    const double err = caps + (8.0 - (ball_volume(r) - caps));
    CHECK(sigmas_off(f.monte_carlo.error, err / 8.0) <= 4.0);
    CHECK(f.monte_carlo.error.lo <= f.monte_carlo.error.estimate);
    CHECK(f.monte_carlo.error.hi >= f.monte_carlo.error.estimate);
    CHECK(f.volume.protrusions[0] == Approx(0.2).epsilon(1e-14));
    CHECK(f.volume.kind == NerrKind::kLowerBound);
  }
}

TEST_CASE("coverage of a box's vertices by eight balls, in closed form", "[fit_metrics]") {
  const TriangleMesh box = make_box({1.0, 1.0, 1.0});
  // Ball k sits at the centre of octant k (signs from its bits), radius 0.3 + 0.03 k. The
  // vertex of that octant is sqrt(0.75) from its centre and farther from every other ball.
  std::vector<Sphere> balls;
  auto octant = [](const Vector3d& p) {
    return (p.x() > 0 ? 1 : 0) + (p.y() > 0 ? 2 : 0) + (p.z() > 0 ? 4 : 0);
  };
  for (int k = 0; k < 8; ++k)
    balls.push_back(
        {0.5 * Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1), 0.3 + 0.03 * k});
  const std::vector<PointCoverage> c = point_coverage(balls, box.vertices);
  REQUIRE(c.size() == box.vertices.size());
  for (std::size_t v = 0; v < box.vertices.size(); ++v) {
    const int k = octant(box.vertices[v]);
    CHECK(c[v].ball == k);
    CHECK(c[v].outside == Approx(std::sqrt(0.75) - (0.3 + 0.03 * k)).epsilon(1e-14));
  }
  // Through the sampler: the vertices come last, in index order; the worst is a vertex of
  // the octant with the smallest ball, unless some sample is worse (brute force decides).
  const SurfaceSamples s = sample_surface(box, 2000, 3);
  REQUIRE(s.points.size() == 2008);
  for (std::size_t v = 0; v < 8; ++v) CHECK(s.points[2000 + v] == box.vertices[v]);
  const CoverageStats stats = summarize_coverage(s, point_coverage(balls, s.points));
  double worst = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    const double d = brute_outside(balls, s.points[i]);
    worst = std::max(worst, d);
    if (i < 2000) sum += d;
  }
  CHECK(stats.max == Approx(worst).epsilon(1e-14));
  CHECK(stats.max >= std::sqrt(0.75) - 0.3 - 1e-15);
  CHECK(stats.mean == Approx(sum / 2000.0).epsilon(1e-12));
  CHECK(stats.area_samples == 2000);
  CHECK(stats.vertices == 8);
}

TEST_CASE("point coverage agrees with brute force, near and far", "[fit_metrics]") {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const int n : {1, 7, 300}) {
    std::vector<Sphere> balls;
    for (int i = 0; i < n; ++i) {
      // Radii from 0.001 to 1 (log-uniform), so that cells hold very different balls.
      const double r = std::pow(10.0, -3.0 * 0.5 * (u(rng) + 1.0));
      balls.push_back({Vector3d(u(rng), u(rng), u(rng)), r});
    }
    std::vector<Vector3d> points;
    for (int i = 0; i < 3000; ++i) {
      const double scale = i % 3 == 0 ? 1.5 : (i % 3 == 1 ? 10.0 : 1e4);
      points.push_back(scale * Vector3d(u(rng), u(rng), u(rng)));
    }
    for (const Sphere& b : balls) {  // points on and next to the spheres
      points.push_back(b.center + b.radius * Vector3d::UnitX());
      points.push_back(b.center + 1.001 * b.radius * Vector3d::UnitY());
      points.push_back(b.center);
    }
    const std::vector<PointCoverage> c = point_coverage(balls, points, 2);
    for (std::size_t i = 0; i < points.size(); ++i) {
      INFO("n = " << n << ", point " << i);
      const double exact = brute_outside(balls, points[i]);
      // Rounding of |p - c| - r: a few eps of the coordinates' magnitude.
      const double tol = 8.0 * kEps * (points[i].norm() + 2.0);
      CHECK(std::abs(c[i].outside - exact) <= tol);
      CHECK((c[i].outside == 0.0) == (exact == 0.0));
      REQUIRE(c[i].ball >= 0);
      const Sphere& b = balls[static_cast<std::size_t>(c[i].ball)];
      CHECK(std::abs(std::max(0.0, (points[i] - b.center).norm() - b.radius) - c[i].outside) <=
            tol);
    }
  }
}

TEST_CASE("point coverage copes with any finite radii: subnormal, tiny and huge", "[fit_metrics]") {
  // A cell size taken from the median radius alone would be subnormal here, with 1 / h
  // infinite and the cell indices garbage. Any valid set must work, and agree with brute
  // force.
  const double sub = 1e-320, tiny = 1e-300, huge = 1e300;
  const std::vector<std::vector<Sphere>> sets = {
      {{Vector3d::Zero(), sub}},
      {{Vector3d(1, 1, 1), sub}},
      {{Vector3d(1, 1, 1), sub}, {Vector3d(1, 1, 1 + 1e-12), sub}},
      {{Vector3d(0.1, 0, 0), sub}, {Vector3d::Zero(), 0.2}},
      {{Vector3d(1e6, -1e6, 3), tiny}, {Vector3d(1e6, -1e6, 4), 0.5}},
      {{Vector3d::Zero(), huge}, {Vector3d(1, 2, 3), 1.0}},
  };
  const std::vector<Vector3d> points = {
      Vector3d::Zero(),       Vector3d(1, 1, 1),    Vector3d(0.1, 0, 0),   Vector3d(0.3, 0, 0),
      Vector3d(1e6, -1e6, 3), Vector3d(5, -7, 2e5), Vector3d(1e300, 0, 0), Vector3d(-1e299, 1, 1)};
  for (std::size_t k = 0; k < sets.size(); ++k) {
    const std::vector<PointCoverage> c = point_coverage(sets[k], points, 1);
    for (std::size_t i = 0; i < points.size(); ++i) {
      INFO("set " << k << ", point " << i);
      const double exact = brute_outside(sets[k], points[i]);
      // (Both overflow to infinity for the points 1e300 away from small balls.)
      CHECK((c[i].outside == exact ||
             std::abs(c[i].outside - exact) <= 8.0 * kEps * (points[i].norm() + exact + 2.0)));
      CHECK((c[i].outside == 0.0) == (exact == 0.0));
    }
  }
  // And the whole evaluation of a set with a subnormal radius.
  const TriangleMesh box = make_box({1.0, 1.0, 1.0});
  const FitReport r =
      FitEvaluator(box).evaluate({{Vector3d::Zero(), sub}, {Vector3d(0.5, 0, 0), 0.25}}, quick());
  CHECK(r.volume.kind == NerrKind::kExact);
  CHECK(r.volume.nerr == Approx(1.0 - 4.0 / 3.0 * kPi * 0.25 * 0.25 * 0.25 / 8.0).epsilon(1e-12));
}

TEST_CASE("surface samples are area-weighted, on the surface and seeded", "[fit_metrics]") {
  const Vector3d h(1.0, 2.0, 3.0);
  const TriangleMesh box = make_box(h, 2);
  const std::size_t n = 60000;
  const SurfaceSamples s = sample_surface(box, n, 11);
  REQUIRE(s.area_samples == n);
  REQUIRE(s.points.size() == n + box.vertices.size());
  // Faces normal to x, y, z have areas 4 h_y h_z, 4 h_x h_z, 4 h_x h_y (two of each).
  const double area[3] = {8.0 * h.y() * h.z(), 8.0 * h.x() * h.z(), 8.0 * h.x() * h.y()};
  const double total = area[0] + area[1] + area[2];
  std::size_t count[3] = {0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    const Vector3d& p = s.points[i];
    int on = -1;  // every corner of a face has the same coordinate: samples lie exactly on it
    for (int k = 0; k < 3; ++k)
      if (std::abs(p[k]) == h[k]) on = k;
    REQUIRE(on >= 0);
    CHECK((p.cwiseAbs().array() <= h.array()).all());
    ++count[on];
  }
  for (int k = 0; k < 3; ++k) {
    const double f = area[k] / total;
    CHECK(std::abs(static_cast<double>(count[k]) - f * n) <= 4.0 * std::sqrt(n * f * (1.0 - f)));
  }
  CHECK(sample_surface(box, n, 11).points == s.points);
  CHECK(sample_surface(box, 10, 12).points[0] != s.points[0]);
  CHECK(sample_surface(box, 0, 11).points.size() == box.vertices.size());

  TriangleMesh flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.triangles = {{0, 1, 2}};
  CHECK_THROWS_AS(sample_surface(flat, 5, 1), std::invalid_argument);
  CHECK(sample_surface(flat, 0, 1).points.size() == 3);
}

TEST_CASE("coverage statistics: max over every point, mean and nearest-rank p95 over samples",
          "[fit_metrics]") {
  SurfaceSamples s;
  std::vector<PointCoverage> c;
  std::vector<int> values(100);
  std::iota(values.begin(), values.end(), 1);
  std::shuffle(values.begin(), values.end(), std::mt19937_64(4));
  for (const int v : values) {
    s.points.push_back(Vector3d(v, 0, 0));
    c.push_back({static_cast<double>(v), 0});
  }
  s.area_samples = 100;
  s.points.push_back(Vector3d(0, 0, 7));  // a vertex, far out: counts in the max only
  c.push_back({1000.0, 0});
  const CoverageStats st = summarize_coverage(s, c);
  CHECK(st.max == 1000.0);
  CHECK(st.max_at == Vector3d(0, 0, 7));
  CHECK(st.mean == Approx(50.5).epsilon(1e-15));
  CHECK(st.p95 == 95.0);  // 95 of the 100 values are <= 95, 94 are <= 94

  s.points.resize(20);
  c.resize(20);
  s.area_samples = 20;
  std::vector<double> first(20);
  for (int i = 0; i < 20; ++i) first[i] = c[i].outside;
  std::sort(first.begin(), first.end());
  CHECK(summarize_coverage(s, c).p95 == first[18]);  // ceil(0.95 * 20) = 19th smallest
  c.pop_back();
  CHECK_THROWS_AS(summarize_coverage(s, c), std::invalid_argument);
}

TEST_CASE("sets baked from generated closed meshes: nerr is exact and Monte Carlo agrees",
          "[fit_metrics]") {
  check_baked(make_box({1.0, 0.6, 0.3}, 2), quick());
  check_baked(make_icosphere(1.0, 3), quick());
  check_baked(make_torus(1.0, 0.3, 48, 16), quick());
  check_baked(make_capsule(0.4, 0.8, 24, 8), quick());
}

TEST_CASE("every number but the timings is the same for every thread count", "[fit_metrics]") {
  const TriangleMesh torus = make_torus(1.0, 0.3, 48, 16);
  const FitEvaluator fit(torus);
  std::vector<Sphere> balls = bake(fit.query()).spheres.spheres;
  for (std::size_t i = 0; i < balls.size(); i += 3) balls[i].radius *= 1.3;  // some stick out
  FitOptions o = quick(100000, 10000);
  o.threads = 1;
  const FitReport one = fit.evaluate(balls, o);
  CHECK(one.volume.kind == NerrKind::kLowerBound);
  for (const int threads : {2, 3}) {
    o.threads = threads;
    check_same(one, fit.evaluate(balls, o));
  }
  o.seed = 8;
  CHECK(fit.evaluate(balls, o).monte_carlo.in_solid != one.monte_carlo.in_solid);
}

TEST_CASE("an open mesh: no volume, no nerr, Monte Carlo against the winding solid",
          "[fit_metrics]") {
  const TriangleMesh open = without_last_triangle(make_box({1.0, 1.0, 1.0}, 4));
  const FitReport r = evaluate_fit(open, {{Vector3d::Zero(), 0.8}}, quick());
  CHECK_FALSE(r.mesh_closed);
  CHECK_FALSE(r.volume.mesh_volume.has_value());
  CHECK(r.volume.kind == NerrKind::kUndefined);
  CHECK(std::isnan(r.volume.nerr));
  CHECK_FALSE(r.monte_carlo.normalized_by_volume);
  REQUIRE(r.warnings.size() == 1);
  CHECK_THAT(r.warnings[0], Contains("open"));
  // A 0.125-area hole in a 24-area surface leaves the winding solid close to the box.
  CHECK(r.monte_carlo.solid_volume.estimate == Approx(8.0).epsilon(0.02));
  const double closed_error = 1.0 - ball_volume(0.8) / 8.0;
  CHECK(r.monte_carlo.error.estimate == Approx(closed_error).epsilon(0.03));
  CHECK(r.monte_carlo.error.sigma > 0.0);
  CHECK(r.monte_carlo.error.lo < r.monte_carlo.error.estimate);
  CHECK(r.monte_carlo.error.hi > r.monte_carlo.error.estimate);
}

TEST_CASE("overlapping closed components: V counts the overlap twice, and a warning says so",
          "[fit_metrics]") {
  TriangleMesh two = make_box({1.0, 1.0, 1.0}, 2);
  const TriangleMesh second = two;
  const int base = static_cast<int>(two.vertices.size());
  for (const Vector3d& v : second.vertices) two.vertices.push_back(v + Vector3d(1, 0, 0));
  for (const auto& t : second.triangles)
    two.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  const FitReport r = evaluate_fit(two, {{Vector3d(0.5, 0, 0), 0.5}}, quick());
  CHECK(*r.volume.mesh_volume == Approx(16.0).epsilon(1e-14));
  // B is the union of the boxes, so every point is in the solid; a third is in both.
  CHECK(r.monte_carlo.box.volume() == Approx(12.0).epsilon(1e-14));
  CHECK(r.monte_carlo.in_solid == r.monte_carlo.samples);
  CHECK(std::abs(r.monte_carlo.multiple_volume - 4.0) <= 4.0 * r.monte_carlo.multiple_volume_sigma);
  // The faces cross: nerr is approximate, and a warning names the pairs; another gives the
  // size of the overlap.
  const std::size_t pairs = find_self_intersections(two).count();
  CHECK(pairs > 0);
  CHECK(r.volume.kind == NerrKind::kApproximate);
  CHECK(r.volume.self_intersecting_pairs == pairs);
  CHECK(r.volume.nerr == Approx((16.0 - r.volume.union_measures.volume) / 16.0).epsilon(1e-14));
  REQUIRE(r.warnings.size() == 2);
  CHECK_THAT(r.warnings[0],
             Contains("self-intersects") && Contains(std::to_string(pairs) + " pair"));
  CHECK_THAT(r.warnings[1], Contains("overlap"));
}

TEST_CASE("nerr kinds in order: undefined, approximate, then exact or lower bound",
          "[fit_metrics]") {
  // Two boxes glued face to face, the shared face triangulated alike: no pair, V exact.
  TriangleMesh glued = make_box({1.0, 1.0, 1.0});
  const TriangleMesh copy = glued;
  const int base = static_cast<int>(glued.vertices.size());
  for (const Vector3d& v : copy.vertices) glued.vertices.push_back(v + Vector3d(2, 0, 0));
  for (const auto& t : copy.triangles)
    glued.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  const FitEvaluator glued_fit(glued);
  CHECK_FALSE(glued_fit.self_intersections().any());
  CHECK(glued_fit.volume_error({{Vector3d(0, 0, 0), 0.5}}).kind == NerrKind::kExact);

  // The second box moved 0.5 into the first: their faces cross.
  TriangleMesh crossing = glued;
  for (std::size_t v = static_cast<std::size_t>(base); v < crossing.vertices.size(); ++v)
    crossing.vertices[v].x() -= 0.5;
  const FitEvaluator fit(crossing, 2);
  REQUIRE(fit.self_intersections().any());
  const VolumeError inside = fit.volume_error({{Vector3d(0, 0, 0), 0.5}});
  CHECK(inside.kind == NerrKind::kApproximate);
  CHECK(inside.nerr == Approx((16.0 - inside.union_measures.volume) / 16.0).epsilon(1e-14));
  CHECK(inside.nerr_slack == 0.0);
  // Sticking out: still approximate (V is off, so Lemma 1 gives no bound), value |V - U| / V.
  const VolumeError out = fit.volume_error({{Vector3d(0, 0, 0), 3.0}});
  CHECK(out.protruding == 1);
  CHECK(out.kind == NerrKind::kApproximate);
  CHECK(out.nerr == Approx(std::abs(16.0 - out.union_measures.volume) / 16.0).epsilon(1e-14));
  // Open: undefined, whatever the pairs.
  TriangleMesh open = crossing;
  open.triangles.pop_back();
  const VolumeError undefined = FitEvaluator(open).volume_error({{Vector3d(0, 0, 0), 0.5}});
  CHECK(undefined.kind == NerrKind::kUndefined);
  CHECK(undefined.self_intersecting_pairs > 0);
  CHECK(std::string(to_string(NerrKind::kApproximate)) == "approximate");
  CHECK_THROWS_AS(FitEvaluator(crossing, -1), std::invalid_argument);
}

TEST_CASE("bad input is rejected by name", "[fit_metrics]") {
  const TriangleMesh box = make_box({1.0, 1.0, 1.0});
  const FitEvaluator fit(box);
  const std::vector<Sphere> one = {{Vector3d::Zero(), 0.5}};
  CHECK_THROWS_WITH(fit.evaluate({}, quick()), Contains("sphere set") && Contains("no spheres"));
  CHECK_THROWS_AS(fit.volume_error({}), InputError);
  CHECK_THROWS_WITH(fit.evaluate({{Vector3d::Zero(), 0.5}, {Vector3d::Zero(), 0.0}}, quick()),
                    Contains("sphere 1"));
  CHECK_THROWS_AS(fit.evaluate({{Vector3d(std::nan(""), 0, 0), 0.5}}, quick()), InputError);
  CHECK_THROWS_AS(point_coverage({}, box.vertices), InputError);
  CHECK_THROWS_AS(sphere_protrusions(fit.query(), {}), InputError);
  CHECK_THROWS_WITH(fit.evaluate(one, quick(0)), Contains("volume_samples"));
  CHECK_THROWS_WITH(fit.evaluate(one, quick(10, 0)), Contains("surface_samples"));
  FitOptions o = quick();
  o.threads = -1;
  CHECK_THROWS_WITH(fit.evaluate(one, o), Contains("threads"));
  CHECK_THROWS_AS(fit.volume_error(one, -2), std::invalid_argument);
  // Thread counts are capped (threads.h): asking OpenMP for 100000 threads crashes it.
  for (const int threads : {kMaxThreads + 1, 100000}) {
    o.threads = threads;
    CHECK_THROWS_WITH(fit.evaluate(one, o), Contains("threads") && Contains("1024"));
    CHECK_THROWS_AS(fit.volume_error(one, threads), std::invalid_argument);
    CHECK_THROWS_AS(point_coverage(one, box.vertices, threads), std::invalid_argument);
    CHECK_THROWS_AS(sphere_protrusions(fit.query(), one, threads), std::invalid_argument);
  }
  // A set whose box with the mesh has no finite volume cannot be sampled.
  CHECK_THROWS_WITH(fit.evaluate({{Vector3d::Zero(), 1e103}}, quick()),
                    Contains("sphere set") && Contains("finite volume"));
  CHECK_THROWS_AS(FitEvaluator(TriangleMesh{}), std::invalid_argument);
}

#ifdef MEDSPHERES_SHARED_MESHES
TEST_CASE(
    "sets baked from every closed shared mesh: nerr exact (approximate if it self-intersects), "
    "Monte Carlo agrees",
    "[fit_metrics][shared]") {
  // A quarter of the samples in the sanitizer builds (the 4-sigma checks scale with them).
  const FitOptions samples = test::kSanitizerBuild ? quick(50000, 5000) : quick();
  for (const auto& row : test::shared_meshes()) {
    if (!row.closed) continue;
    INFO(row.file);
    check_baked(load_mesh(row.path).mesh, samples);
  }
}
#endif
