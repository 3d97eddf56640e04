#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/measure/union_volume.h"
#include "support/ball_formulas.h"

using Catch::Matchers::Contains;
using Eigen::Vector3d;
using medspheres::Sphere;
using medspheres::UnionMeasures;
using medspheres::UnionOfBalls;

namespace {

using medspheres::test::ball_volume;
using medspheres::test::cap_area;
using medspheres::test::kPi;
using medspheres::test::lens_volume;
using medspheres::test::sphere_area;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// Rounding bound of the inclusion-exclusion sum. The measure of a k-simplex of K is a sum
// of k + 1 sphere terms r^3 Omega / 3 (area: r^2 Omega), |Omega| <= 4 pi, and of edge and
// face terms no larger, each evaluated through about a dozen roundings that no
// cancellation amplifies (see ball_intersection.h): 16 eps per unit of magnitude. With
// r_max the largest radius, the error is below
//   16 eps (4 pi r_max^p) sum over K of (dim + 1),  p = 3 for the volume, 2 for the area.
double rounding_bound(const UnionOfBalls& u, const std::vector<Sphere>& balls, int power) {
  double rmax = 0.0;
  for (const Sphere& b : balls) rmax = std::max(rmax, b.radius);
  const UnionMeasures& m = u.measures();
  const double weight =
      static_cast<double>(m.vertices + 2 * m.edges + 3 * m.triangles + 4 * m.tetrahedra);
  return 16.0 * kEps * 4.0 * kPi * std::pow(rmax, power) * weight;
}
double volume_rounding(const UnionOfBalls& u, const std::vector<Sphere>& balls) {
  return rounding_bound(u, balls, 3);
}
double area_rounding(const UnionOfBalls& u, const std::vector<Sphere>& balls) {
  return rounding_bound(u, balls, 2);
}

// ---------------------------------------------------------------------------------------
// Oracle 1: slice integration. vol = integral over z of the area of the union of the
// discs cut by the plane at height z; area = integral of sum_i r_i (exposed angle of
// circle i) (a sphere's zone between z and z + dz has area 2 pi r dz). The union of discs
// is measured exactly by its exposed arcs (Green's theorem). Between consecutive events
// (poles, extremes of the circles where two spheres meet, triple points) the integrands
// are smooth except for square-root ends, which z = mid - half cos(theta) smooths, so
// Gauss-Legendre in theta converges quickly. It shares nothing with the power diagram.

void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(n, 0.0);
  w.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p1 = 1.0, p2 = 0.0;
      for (int j = 1; j <= n; ++j) {
        const double p3 = p2;
        p2 = p1;
        p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
      }
      dp = n * (z * p1 - p2) / (z * z - 1.0);
      const double step = p1 / dp;
      z -= step;
      if (std::abs(step) < 1e-16) break;
    }
    x[i] = z;
    w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

struct Measures {
  double volume = 0.0;
  double area = 0.0;
};

Measures slice(const std::vector<Sphere>& balls, const Vector3d& origin, double z) {
  struct Disc {
    double x, y, rho, r;
    int id;
  };
  std::vector<Disc> discs;
  for (int i = 0; i < static_cast<int>(balls.size()); ++i) {
    const double dz = z - balls[i].center.z(), r = balls[i].radius;
    if (std::abs(dz) >= r) continue;
    discs.push_back({balls[i].center.x() - origin.x(), balls[i].center.y() - origin.y(),
                     std::sqrt((r - dz) * (r + dz)), r, i});
  }
  Measures m;
  std::vector<std::pair<double, double>> covered;
  for (const Disc& a : discs) {
    covered.clear();
    bool hidden = false;
    for (const Disc& o : discs) {
      if (o.id == a.id) continue;
      const double dx = o.x - a.x, dy = o.y - a.y, d = std::hypot(dx, dy);
      if (d >= a.rho + o.rho || d + o.rho <= a.rho) continue;
      if (d + a.rho <= o.rho) {
        hidden = true;
        break;
      }
      const double c = (d * d + a.rho * a.rho - o.rho * o.rho) / (2.0 * d * a.rho);
      const double half = std::acos(std::max(-1.0, std::min(1.0, c)));
      double s = std::atan2(dy, dx) - half, e = s + 2.0 * half;
      if (s < 0.0) {
        s += 2.0 * kPi;
        e += 2.0 * kPi;
      }
      if (e > 2.0 * kPi) {
        covered.push_back({s, 2.0 * kPi});
        covered.push_back({0.0, e - 2.0 * kPi});
      } else {
        covered.push_back({s, e});
      }
    }
    if (hidden) continue;
    std::sort(covered.begin(), covered.end());
    auto exposed = [&](double t1, double t2) {
      if (t2 <= t1) return;
      m.volume += 0.5 * (a.rho * a.rho * (t2 - t1) + a.rho * (a.x * (std::sin(t2) - std::sin(t1)) -
                                                              a.y * (std::cos(t2) - std::cos(t1))));
      m.area += a.r * (t2 - t1);
    };
    double at = 0.0;
    for (const auto& iv : covered) {
      exposed(at, iv.first);
      at = std::max(at, iv.second);
    }
    exposed(at, 2.0 * kPi);
  }
  return m;
}

// The points where three spheres meet (none, or two, possibly equal).
std::vector<Vector3d> triple_points(const Sphere& a, const Sphere& b, const Sphere& c) {
  // |x - c_i|^2 = r_i^2; differences give two planes; their line meets sphere a.
  const Vector3d n1 = 2.0 * (b.center - a.center), n2 = 2.0 * (c.center - a.center);
  const double k1 =
      b.center.squaredNorm() - a.center.squaredNorm() - b.radius * b.radius + a.radius * a.radius;
  const double k2 =
      c.center.squaredNorm() - a.center.squaredNorm() - c.radius * c.radius + a.radius * a.radius;
  const Vector3d dir = n1.cross(n2);
  if (dir.squaredNorm() == 0.0) return {};
  // A point of the line: the combination of n1 and n2 satisfying both plane equations.
  const double g11 = n1.dot(n1), g12 = n1.dot(n2), g22 = n2.dot(n2), det = g11 * g22 - g12 * g12;
  const Vector3d p0 = ((k1 * g22 - k2 * g12) * n1 + (k2 * g11 - k1 * g12) * n2) / det;
  const Vector3d u = dir.normalized();
  const Vector3d q = p0 - a.center;
  const double half_b = q.dot(u), cc = q.squaredNorm() - a.radius * a.radius;
  const double disc = half_b * half_b - cc;
  if (disc < 0.0) return {};
  return {p0 + (-half_b + std::sqrt(disc)) * u, p0 + (-half_b - std::sqrt(disc)) * u};
}

Measures slice_oracle(const std::vector<Sphere>& balls, int nodes) {
  Measures total;
  if (balls.empty()) return total;
  Vector3d origin = Vector3d::Zero();
  for (const Sphere& b : balls) origin += b.center;
  origin /= static_cast<double>(balls.size());
  std::vector<double> events;
  const int n = static_cast<int>(balls.size());
  for (const Sphere& b : balls) {
    events.push_back(b.center.z() - b.radius);
    events.push_back(b.center.z() + b.radius);
  }
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const Vector3d e = balls[j].center - balls[i].center;
      const double d = e.norm(), ri = balls[i].radius, rj = balls[j].radius;
      if (!(d < ri + rj && d > std::abs(ri - rj))) continue;
      const double a = (d * d + ri * ri - rj * rj) / (2.0 * d);
      const Vector3d u = e / d, m = balls[i].center + a * u;
      const double extent =
          std::sqrt(std::max(0.0, ri * ri - a * a)) * std::sqrt(std::max(0.0, 1.0 - u.z() * u.z()));
      events.push_back(m.z() - extent);
      events.push_back(m.z() + extent);
      for (int k = j + 1; k < n; ++k)
        for (const Vector3d& p : triple_points(balls[i], balls[j], balls[k]))
          events.push_back(p.z());
    }
  }
  std::sort(events.begin(), events.end());
  events.erase(std::unique(events.begin(), events.end()), events.end());
  std::vector<double> gx, gw;
  gauss_legendre(nodes, gx, gw);
  for (std::size_t q = 0; q + 1 < events.size(); ++q) {
    const double mid = 0.5 * (events[q] + events[q + 1]), half = 0.5 * (events[q + 1] - events[q]);
    for (int k = 0; k < nodes; ++k) {
      const double theta = 0.5 * kPi * (gx[k] + 1.0), weight = 0.5 * kPi * gw[k];
      const Measures s = slice(balls, origin, mid - half * std::cos(theta));
      total.volume += weight * half * std::sin(theta) * s.volume;
      total.area += weight * half * std::sin(theta) * s.area;
    }
  }
  return total;
}

// Compares UnionOfBalls with the slice oracle. The oracle's own error is taken as the
// change of its result when the number of nodes doubles (it converges geometrically, so
// the finer result is far more accurate than that change); it must be small for the
// comparison to mean anything.
void check_against_slices(const std::vector<Sphere>& balls) {
  const UnionOfBalls u(balls);
  const Measures coarse = slice_oracle(balls, 64), fine = slice_oracle(balls, 128);
  const double oracle_volume_error = std::abs(fine.volume - coarse.volume);
  const double oracle_area_error = std::abs(fine.area - coarse.area);
  REQUIRE(oracle_volume_error <= 1e-10 * fine.volume);
  REQUIRE(oracle_area_error <= 1e-10 * fine.area);
  // Errors over allowances (printed legibly on failure, unlike differences near 1e-13).
  CHECK(std::abs(u.measures().volume - fine.volume) /
            (volume_rounding(u, balls) + oracle_volume_error) <=
        1.0);
  CHECK(std::abs(u.measures().area - fine.area) / (area_rounding(u, balls) + oracle_area_error) <=
        1.0);
}

// ---------------------------------------------------------------------------------------
// Oracle 2: Monte Carlo, with a uniform grid to find the balls near a point.

class BallGrid {
 public:
  explicit BallGrid(const std::vector<Sphere>& balls) : balls_(balls) {
    box_ = Eigen::AlignedBox3d();
    double rmax = 0.0;
    for (const Sphere& b : balls) {
      box_.extend(b.center - Vector3d::Constant(b.radius));
      box_.extend(b.center + Vector3d::Constant(b.radius));
      rmax = std::max(rmax, b.radius);
    }
    cell_ = 2.0 * rmax;
    for (int k = 0; k < 3; ++k)
      dims_[k] = std::max(1, static_cast<int>(std::ceil(box_.sizes()[k] / cell_)));
    cells_.assign(static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2], {});
    for (int i = 0; i < static_cast<int>(balls.size()); ++i) {
      const auto lo = index(balls[i].center - Vector3d::Constant(balls[i].radius));
      const auto hi = index(balls[i].center + Vector3d::Constant(balls[i].radius));
      for (int x = lo[0]; x <= hi[0]; ++x)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int z = lo[2]; z <= hi[2]; ++z) cells_[flat({x, y, z})].push_back(i);
    }
  }
  const Eigen::AlignedBox3d& box() const { return box_; }

  // True when p lies in the interior of some ball other than \p except.
  bool inside(const Vector3d& p, int except = -1) const {
    for (const int i : cells_[flat(index(p))]) {
      if (i == except) continue;
      if ((p - balls_[i].center).squaredNorm() < balls_[i].radius * balls_[i].radius) return true;
    }
    return false;
  }

 private:
  std::array<int, 3> index(const Vector3d& p) const {
    std::array<int, 3> c{};
    for (int k = 0; k < 3; ++k)
      c[k] = std::min(dims_[k] - 1, std::max(0, static_cast<int>((p[k] - box_.min()[k]) / cell_)));
    return c;
  }
  std::size_t flat(const std::array<int, 3>& c) const {
    return (static_cast<std::size_t>(c[0]) * dims_[1] + c[1]) * dims_[2] + c[2];
  }

  const std::vector<Sphere>& balls_;
  Eigen::AlignedBox3d box_;
  double cell_ = 1.0;
  std::array<int, 3> dims_{};
  std::vector<std::vector<int>> cells_;
};

struct Estimate {
  double value = 0.0;
  double sigma = 0.0;  // standard error
};

// Uniform points in the bounding box; the fraction inside is binomial.
Estimate mc_volume(const std::vector<Sphere>& balls, int samples, unsigned seed) {
  const BallGrid grid(balls);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const Vector3d lo = grid.box().min(), size = grid.box().sizes();
  int hits = 0;
  for (int s = 0; s < samples; ++s) {
    const Vector3d p = lo + Vector3d(u01(rng), u01(rng), u01(rng)).cwiseProduct(size);
    hits += grid.inside(p) ? 1 : 0;
  }
  const double f = static_cast<double>(hits) / samples, box = size.prod();
  return {f * box, box * std::sqrt(f * (1.0 - f) / samples)};
}

// Uniform points on each sphere; those in no other ball are on the boundary of the union.
Estimate mc_area(const std::vector<Sphere>& balls, int samples_per_sphere, unsigned seed) {
  const BallGrid grid(balls);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Estimate e;
  double variance = 0.0;
  for (int i = 0; i < static_cast<int>(balls.size()); ++i) {
    int exposed = 0;
    for (int s = 0; s < samples_per_sphere; ++s) {
      const Vector3d dir = Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
      exposed += grid.inside(balls[i].center + balls[i].radius * dir, i) ? 0 : 1;
    }
    const double f = static_cast<double>(exposed) / samples_per_sphere;
    const double a = sphere_area(balls[i].radius);
    e.value += a * f;
    variance += a * a * f * (1.0 - f) / samples_per_sphere;
  }
  e.sigma = std::sqrt(variance);
  return e;
}

// Centres uniform in a cube at one per unit volume, radii uniform in [0.8 m, 1.2 m].
std::vector<Sphere> random_balls(int n, double mean_radius, unsigned seed) {
  std::mt19937_64 rng(seed);
  const double side = std::cbrt(static_cast<double>(n));
  std::uniform_real_distribution<double> pos(0.0, side), rad(0.8 * mean_radius, 1.2 * mean_radius);
  std::vector<Sphere> balls(n);
  for (Sphere& b : balls) {
    b.center = {pos(rng), pos(rng), pos(rng)};
    b.radius = rad(rng);
  }
  return balls;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Closed forms

TEST_CASE("empty input has volume 0 and an empty complex", "[union_volume]") {
  const UnionOfBalls u({});
  CHECK(u.measures().volume == 0.0);
  CHECK(u.measures().area == 0.0);
  CHECK(u.measures().dimension == -1);
  CHECK(u.complex_vertices().empty());
  CHECK(u.v_points().empty());
  CHECK(u.measures().hidden.empty());
}

TEST_CASE("one ball: volume 4/3 pi r^3 and area 4 pi r^2", "[union_volume]") {
  const std::vector<Sphere> balls{{{1.0, -2.0, 3.5}, 0.75}};
  const UnionOfBalls u(balls);
  // One term, a few roundings: 4 eps relative.
  CHECK(u.measures().volume == Approx(ball_volume(0.75)).epsilon(4 * kEps).margin(0));
  CHECK(u.measures().area == Approx(sphere_area(0.75)).epsilon(4 * kEps).margin(0));
  CHECK(u.measures().dimension == 0);
  CHECK(u.complex_vertices() == std::vector<int>{0});
  CHECK(u.complex_edges().empty());
}

TEST_CASE("two balls: disjoint, touching, lens and nested", "[union_volume]") {
  const double r1 = 1.0,
               r2 = 0.75;  // squares exact in binary: tangency is exact for the predicates
  auto pair = [&](double d) {
    return std::vector<Sphere>{{{0.0, 0.0, 0.0}, r1}, {{d, 0.0, 0.0}, r2}};
  };
  // Tolerances: a handful of terms, each with a few dozen roundings (64 eps relative).
  const double tol = 64 * kEps;

  SECTION("disjoint") {
    const UnionOfBalls u(pair(2.0));
    CHECK(u.measures().volume == Approx(ball_volume(r1) + ball_volume(r2)).epsilon(tol).margin(0));
    CHECK(u.measures().area == Approx(sphere_area(r1) + sphere_area(r2)).epsilon(tol).margin(0));
    CHECK(u.complex_edges().empty());
  }
  SECTION("touching: the edge is in K with a circle of radius 0 at the contact") {
    const UnionOfBalls u(pair(r1 + r2));
    CHECK(u.measures().volume == Approx(ball_volume(r1) + ball_volume(r2)).epsilon(tol).margin(0));
    CHECK(u.measures().area == Approx(sphere_area(r1) + sphere_area(r2)).epsilon(tol).margin(0));
    REQUIRE(u.lone_edge_circles().size() == 1);
    CHECK(u.lone_edge_circles()[0].radius == 0.0);
    CHECK((u.lone_edge_circles()[0].center - Vector3d(r1, 0, 0)).norm() <= 4 * kEps);
  }
  SECTION("lens") {
    const double d = 1.1;
    const UnionOfBalls u(pair(d));
    CHECK(
        u.measures().volume ==
        Approx(ball_volume(r1) + ball_volume(r2) - lens_volume(r1, r2, d)).epsilon(tol).margin(0));
    CHECK(u.measures().area ==
          Approx(sphere_area(r1) + sphere_area(r2) - cap_area(r1, r2, d) - cap_area(r2, r1, d))
              .epsilon(tol)
              .margin(0));
    REQUIRE(u.lone_edge_circles().size() == 1);
    const medspheres::EdgeCircle& c = u.lone_edge_circles()[0];
    const double a = (d * d + r1 * r1 - r2 * r2) / (2 * d);
    CHECK(c.center.x() == Approx(a).epsilon(tol));
    CHECK(c.normal == Vector3d(1, 0, 0));
    CHECK(c.radius == Approx(std::sqrt(r1 * r1 - a * a)).epsilon(tol));
    CHECK(c.balls == std::array<int, 2>{0, 1});
  }
  SECTION("nested: the inner ball is hidden") {
    const UnionOfBalls u(pair(0.2));
    CHECK(u.measures().volume == Approx(ball_volume(r1)).epsilon(tol).margin(0));
    CHECK(u.measures().area == Approx(sphere_area(r1)).epsilon(tol).margin(0));
    CHECK(u.measures().hidden == std::vector<int>{1});
    CHECK(u.complex_vertices() == std::vector<int>{0});
  }
  SECTION("nested and touching from inside: no volume, no area") {
    const UnionOfBalls u(pair(r1 - r2));
    CHECK(u.measures().volume == Approx(ball_volume(r1)).epsilon(tol).margin(0));
    CHECK(u.measures().area == Approx(sphere_area(r1)).epsilon(tol).margin(0));
  }
}

TEST_CASE("duplicates are dropped and reported, the first index kept", "[union_volume]") {
  const Sphere a{{0, 0, 0}, 1.0}, b{{1.2, 0, 0}, 0.8};
  const UnionOfBalls ref({a, b});
  const UnionOfBalls u({a, b, a, b, a});
  CHECK(u.measures().duplicates == std::vector<int>{2, 3, 4});
  CHECK(u.measures().hidden.empty());
  CHECK(u.measures().volume == ref.measures().volume);
  CHECK(u.measures().area == ref.measures().area);
  CHECK(u.complex_edges() == std::vector<std::array<int, 2>>{{0, 1}});

  // One distinct ball: a triangulation of dimension 0.
  const UnionOfBalls same({b, b, b});
  CHECK(same.measures().dimension == 0);
  CHECK(same.measures().duplicates == std::vector<int>{1, 2});
  CHECK(same.measures().volume == Approx(ball_volume(0.8)).epsilon(4 * kEps).margin(0));
  const UnionOfBalls concentric({{{0, 0, 0}, 0.5}, a});
  CHECK(concentric.measures().dimension == 0);
  CHECK(concentric.measures().hidden == std::vector<int>{0});
  CHECK(concentric.measures().volume == Approx(ball_volume(1.0)).epsilon(4 * kEps).margin(0));
}

TEST_CASE("hidden balls: inside one ball, at a shared centre, inside the union of two",
          "[union_volume]") {
  const Sphere a{{-0.5, 0, 0}, 1.0}, b{{0.5, 0, 0}, 1.0};
  const double expected = 2 * ball_volume(1.0) - lens_volume(1.0, 1.0, 1.0);
  // c: same centre as a, smaller. d: inside a alone. e: inside a u b but in neither
  // (its points with x <= 0 are within 0.95 of a's centre, the others within 0.95 of b's).
  const Sphere c{{-0.5, 0, 0}, 0.5}, d{{-0.9, 0.1, 0}, 0.3}, e{{0, 0.5, 0}, 0.3};
  const UnionOfBalls u({c, a, d, b, e});
  CHECK(u.measures().hidden == std::vector<int>{0, 2, 4});
  CHECK(u.complex_vertices() == std::vector<int>{1, 3});
  const UnionOfBalls ref({a, b});
  CHECK(u.measures().volume == Approx(expected).epsilon(64 * kEps).margin(0));
  CHECK(u.measures().area == Approx(ref.measures().area).epsilon(64 * kEps).margin(0));
}

TEST_CASE("collinear centres: a triangulation of dimension 1", "[union_volume]") {
  SECTION("consecutive overlaps, the last pair touching") {
    const std::vector<Sphere> balls{
        {{0, 0, 0}, 0.7}, {{2, 0, 0}, 0.6}, {{1, 0, 0}, 0.8}, {{3.5, 0, 0}, 0.9}};
    const UnionOfBalls u(balls);
    CHECK(u.measures().dimension == 1);
    const double expected = ball_volume(0.7) + ball_volume(0.8) + ball_volume(0.6) +
                            ball_volume(0.9) - lens_volume(0.7, 0.8, 1.0) -
                            lens_volume(0.8, 0.6, 1.0);
    CHECK(u.measures().volume == Approx(expected).epsilon(64 * kEps).margin(0));
    CHECK(u.complex_edges() == std::vector<std::array<int, 2>>{{0, 2}, {1, 2}, {1, 3}});
    check_against_slices(balls);
  }
  SECTION("the outer balls overlap inside the middle one: their edge is not in K") {
    const std::vector<Sphere> balls{{{0, 0, 0}, 1.2}, {{1, 0, 0}, 1.5}, {{2, 0, 0}, 1.2}};
    const UnionOfBalls u(balls);
    const double expected =
        2 * ball_volume(1.2) + ball_volume(1.5) - 2 * lens_volume(1.2, 1.5, 1.0);
    CHECK(u.measures().volume == Approx(expected).epsilon(64 * kEps).margin(0));
    CHECK(u.complex_edges() == std::vector<std::array<int, 2>>{{0, 1}, {1, 2}});
    CHECK(u.complex_triangles().empty());
  }
}

TEST_CASE("coplanar centres: a triangulation of dimension 2", "[union_volume]") {
  SECTION("square of four balls, cocircular, neighbours overlapping") {
    const double r = 0.6;
    const std::vector<Sphere> balls{{{0, 0, 0}, r}, {{1, 0, 0}, r}, {{1, 1, 0}, r}, {{0, 1, 0}, r}};
    const UnionOfBalls u(balls);
    CHECK(u.measures().dimension == 2);
    CHECK(u.measures().volume ==
          Approx(4 * ball_volume(r) - 4 * lens_volume(r, r, 1.0)).epsilon(64 * kEps).margin(0));
    CHECK(u.complex_edges().size() == 4);
  }
  SECTION("square of four balls with diagonal overlaps") {
    const double r = 0.75;
    check_against_slices(
        {{{0, 0, 0}, r}, {{1, 0, 0}, r}, {{1, 1, 0}, r}, {{0, 1, 0}, r}, {{0.5, 0.5, 0}, 0.3}});
  }
  SECTION("random discs in a plane") {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> pos(0.0, 2.0), rad(0.3, 0.7);
    std::vector<Sphere> balls(9);
    for (Sphere& b : balls) b = {{pos(rng), pos(rng), 0.25}, rad(rng)};
    CHECK(UnionOfBalls(balls).measures().dimension == 2);
    check_against_slices(balls);
  }
}

TEST_CASE("three and four balls against slice integration", "[union_volume]") {
  SECTION("equilateral triangle of equal balls") {
    const double h = std::sqrt(3.0) / 2;
    for (const double r : {0.55, 0.7, 1.0, 1.6})
      check_against_slices({{{0, 0, 0}, r}, {{1, 0, 0}, r}, {{0.5, h, 0}, r}});
  }
  SECTION("regular tetrahedron of equal balls") {
    const std::vector<Vector3d> c{{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    for (const double r : {1.5, 1.8, 2.2, 3.0}) {
      std::vector<Sphere> balls;
      for (const Vector3d& p : c) balls.push_back({p, r});
      const UnionOfBalls u(balls);
      if (r >= 1.8) CHECK(u.complex_tetrahedra().size() == 1);  // r > circumradius sqrt(3)
      check_against_slices(balls);
    }
  }
  SECTION("random triples and quadruples, seeded") {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> pos(-1.0, 1.0), rad(0.4, 1.4);
    for (int trial = 0; trial < 12; ++trial) {
      std::vector<Sphere> balls(3 + trial % 2);
      for (Sphere& b : balls) b = {{pos(rng), pos(rng), pos(rng)}, rad(rng)};
      check_against_slices(balls);
    }
  }
  SECTION("cube corners: cospherical centres") {
    for (const double r : {0.6, 0.8, 0.9}) {
      std::vector<Sphere> balls;
      for (int k = 0; k < 8; ++k)
        balls.push_back({{double(k & 1), double(k >> 1 & 1), double(k >> 2)}, r});
      if (r == 0.6) {
        // Only the 12 cube edges overlap: a closed form.
        CHECK(
            UnionOfBalls(balls).measures().volume ==
            Approx(8 * ball_volume(r) - 12 * lens_volume(r, r, 1.0)).epsilon(64 * kEps).margin(0));
      }
      check_against_slices(balls);
    }
  }
  SECTION("three spheres through one point") {
    // Unit balls centred on the unit circle about the origin: every sphere passes
    // through the origin, and the three meet only there.
    const double deg = kPi / 180;
    auto at = [&](double a) { return Vector3d(std::cos(a * deg), std::sin(a * deg), 0); };
    check_against_slices({{at(0), 1}, {at(40), 1}, {at(75), 1}});
    check_against_slices({{at(0), 1}, {at(120), 1}, {at(240), 1}});
  }
  SECTION("two spheres (almost) tangent where a third sphere passes") {
    // Dyadic data, so that the tangencies are exact for the predicates: the contact point
    // (1, 0, 0) or (0, 0, 0) lies on the third sphere, |(0, 0.375, 0.5)| = 0.625.
    for (const double gap : {0x1p-8, 0x1p-30, 0x1p-45, 0.0}) {
      CAPTURE(gap);
      const std::vector<Sphere> inner{
          {{0.625, 0, 0}, 0.375 + gap}, {{0, 0, 0}, 1.0}, {{1, 0.375, 0.5}, 0.625}};
      const UnionOfBalls u(inner);
      CHECK(u.complex_triangles().size() == 1);
      check_against_slices(inner);
      const std::vector<Sphere> outer{
          {{-1, 0, 0}, 1.0}, {{1, 0, 0}, 1.0 + gap}, {{0, 0.375, 0.5}, 0.625}};
      CHECK(UnionOfBalls(outer).complex_triangles().size() == 1);
      check_against_slices(outer);
    }
  }
}

TEST_CASE("grid of equal balls: massively cospherical", "[union_volume]") {
  std::vector<Sphere> balls;
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y)
      for (int z = 0; z < 2; ++z) balls.push_back({{double(x), double(y), double(z)}, 0.8});
  check_against_slices(balls);
}

// ---------------------------------------------------------------------------------------
// Monte Carlo

TEST_CASE("random sets of 10 to 1000 balls agree with Monte Carlo within 4 sigma",
          "[union_volume]") {
  struct Case {
    int n;
    double mean_radius;  // at one centre per unit volume: ~8 and ~40 overlapping neighbours
    int volume_samples;
    int area_samples;  // per sphere
  };
  for (const Case& c :
       {Case{10, 0.8, 400000, 20000}, Case{100, 0.62, 400000, 4000}, Case{100, 1.05, 400000, 4000},
        Case{1000, 0.62, 400000, 400}, Case{1000, 1.05, 400000, 400}}) {
    CAPTURE(c.n, c.mean_radius);
    const std::vector<Sphere> balls = random_balls(c.n, c.mean_radius, 1000u + c.n);
    const UnionOfBalls u(balls);
    const Estimate v = mc_volume(balls, c.volume_samples, 7u + c.n);
    const Estimate a = mc_area(balls, c.area_samples, 9u + c.n);
    CAPTURE(u.measures().volume, v.value, v.sigma, u.measures().area, a.value, a.sigma);
    CHECK(std::abs(u.measures().volume - v.value) <= 4 * v.sigma);
    CHECK(std::abs(u.measures().area - a.value) <= 4 * a.sigma);
  }
}

// ---------------------------------------------------------------------------------------
// Invariance

TEST_CASE("invariant under translation, rotation, scaling and permutation", "[union_volume]") {
  const std::vector<Sphere> balls = random_balls(200, 1.05, 77);
  const UnionOfBalls ref(balls);
  const double v0 = ref.measures().volume, a0 = ref.measures().area;
  double cmax = 0.0;
  for (const Sphere& b : balls) cmax = std::max(cmax, b.center.cwiseAbs().maxCoeff());
  // Both runs round independently: twice the rounding bound. Moving the input also rounds
  // every coordinate, by at most eps |x| per unit of magnitude; the volume moves by at
  // most the area times that displacement (sqrt(3) for the three coordinates).
  auto volume_tol = [&](double displacement) {
    return 2 * volume_rounding(ref, balls) + a0 * std::sqrt(3.0) * displacement;
  };
  auto area_tol = [&](double displacement, double rmin) {
    // The area moves by at most (2 / r) area per unit of displacement (mean curvature).
    return 2 * area_rounding(ref, balls) + 2 * a0 / rmin * std::sqrt(3.0) * displacement;
  };
  double rmin = std::numeric_limits<double>::infinity();
  for (const Sphere& b : balls) rmin = std::min(rmin, b.radius);

  SECTION("translation") {
    const Vector3d t(1000.3, -2000.7, 500.1);
    std::vector<Sphere> moved = balls;
    for (Sphere& b : moved) b.center += t;
    const UnionOfBalls u(moved);
    const double displacement = kEps * (t.cwiseAbs().maxCoeff() + cmax);
    CHECK(std::abs(u.measures().volume - v0) / volume_tol(displacement) <= 1.0);
    CHECK(std::abs(u.measures().area - a0) / area_tol(displacement, rmin) <= 1.0);
    CHECK(u.complex_tetrahedra() == ref.complex_tetrahedra());
  }
  SECTION("rotation") {
    const Eigen::Matrix3d rot =
        Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    std::vector<Sphere> moved = balls;
    for (Sphere& b : moved) b.center = rot * b.center;
    const UnionOfBalls u(moved);
    const double displacement = 4 * kEps * cmax;  // three products and two sums per coordinate
    CHECK(std::abs(u.measures().volume - v0) / volume_tol(displacement) <= 1.0);
    CHECK(std::abs(u.measures().area - a0) / area_tol(displacement, rmin) <= 1.0);
  }
  SECTION("scaling by a power of two is exact; by 3 the volume scales as 27, the area as 9") {
    std::vector<Sphere> twice = balls, thrice = balls;
    for (Sphere& b : twice) {
      b.center *= 2;
      b.radius *= 2;
    }
    for (Sphere& b : thrice) {
      b.center *= 3;
      b.radius *= 3;
    }
    CHECK(UnionOfBalls(twice).measures().volume == 8 * v0);
    CHECK(UnionOfBalls(twice).measures().area == 4 * a0);
    const UnionOfBalls u(thrice);
    // Scaling by 3 rounds each input by eps/2 relative: a displacement of eps/2 (3 cmax).
    const double displacement = 0.5 * kEps * 3 * cmax;
    CHECK(std::abs(u.measures().volume - 27 * v0) / (27 * volume_tol(displacement / 3)) <= 1.0);
    CHECK(std::abs(u.measures().area - 9 * a0) / (9 * area_tol(displacement / 3, rmin)) <= 1.0);
  }
  SECTION("permutation: same measures, the same complex up to relabelling") {
    std::vector<int> perm(balls.size());
    std::iota(perm.begin(), perm.end(), 0);
    std::shuffle(perm.begin(), perm.end(), std::mt19937_64(3));
    std::vector<Sphere> shuffled(balls.size());
    for (std::size_t i = 0; i < balls.size(); ++i) shuffled[i] = balls[perm[i]];
    const UnionOfBalls u(shuffled);
    CHECK(std::abs(u.measures().volume - v0) / volume_tol(0.0) <= 1.0);
    CHECK(std::abs(u.measures().area - a0) / area_tol(0.0, rmin) <= 1.0);
    std::vector<std::array<int, 4>> relabelled;
    for (const auto& t : u.complex_tetrahedra()) {
      std::array<int, 4> r{perm[t[0]], perm[t[1]], perm[t[2]], perm[t[3]]};
      std::sort(r.begin(), r.end());
      relabelled.push_back(r);
    }
    std::sort(relabelled.begin(), relabelled.end());
    CHECK(relabelled == ref.complex_tetrahedra());
    CHECK(u.v_points().size() == ref.v_points().size());
  }
}

// ---------------------------------------------------------------------------------------
// The dual complex, v-points and lone-edge circles

TEST_CASE("the complex is closed under faces and accounts for every ball", "[union_volume]") {
  const std::vector<Sphere> balls = random_balls(300, 1.05, 5);
  const UnionOfBalls u(balls);
  const std::set<int> verts(u.complex_vertices().begin(), u.complex_vertices().end());
  const std::set<std::array<int, 2>> edges(u.complex_edges().begin(), u.complex_edges().end());
  const std::set<std::array<int, 3>> tris(u.complex_triangles().begin(),
                                          u.complex_triangles().end());
  for (const auto& e : u.complex_edges()) CHECK((verts.count(e[0]) && verts.count(e[1])));
  for (const auto& t : u.complex_triangles()) {
    CHECK(edges.count({t[0], t[1]}) == 1);
    CHECK(edges.count({t[0], t[2]}) == 1);
    CHECK(edges.count({t[1], t[2]}) == 1);
  }
  for (const auto& t : u.complex_tetrahedra())
    for (int q = 0; q < 4; ++q) {
      std::array<int, 3> f{};
      for (int k = 0, m = 0; k < 4; ++k)
        if (k != q) f[m++] = t[k];
      CHECK(tris.count(f) == 1);
    }
  CHECK(std::is_sorted(u.complex_edges().begin(), u.complex_edges().end()));
  CHECK(std::is_sorted(u.complex_triangles().begin(), u.complex_triangles().end()));
  // Every ball is a vertex, hidden or a duplicate, exactly once.
  std::vector<int> all = u.complex_vertices();
  all.insert(all.end(), u.measures().hidden.begin(), u.measures().hidden.end());
  all.insert(all.end(), u.measures().duplicates.begin(), u.measures().duplicates.end());
  std::sort(all.begin(), all.end());
  std::vector<int> expected(balls.size());
  std::iota(expected.begin(), expected.end(), 0);
  CHECK(all == expected);
  // A hidden ball lies in the union of the others: sample it.
  const BallGrid grid(balls);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u11(-1.0, 1.0);
  REQUIRE_FALSE(u.measures().hidden.empty());
  for (const int h : u.measures().hidden) {
    for (int s = 0; s < 200; ++s) {
      Vector3d d(u11(rng), u11(rng), u11(rng));
      if (d.squaredNorm() > 1.0) continue;
      CHECK(grid.inside(balls[h].center + 0.999 * balls[h].radius * d, h));
    }
  }
}

TEST_CASE("v-points: the two points of a triangle, one of them covered", "[union_volume]") {
  const double h = std::sqrt(3.0) / 2, t = std::sqrt(2.0 / 3.0);
  const Vector3d centroid(0.5, h / 3, 0);
  std::vector<Sphere> balls{{{0, 0, 0}, 1}, {{1, 0, 0}, 1}, {{0.5, h, 0}, 1}};
  {
    const UnionOfBalls u(balls);
    REQUIRE(u.v_points().size() == 2);
    CHECK((u.v_points()[0].position - (centroid + Vector3d(0, 0, t))).norm() <= 8 * kEps);
    CHECK((u.v_points()[1].position - (centroid - Vector3d(0, 0, t))).norm() <= 8 * kEps);
    CHECK(u.v_points()[0].balls == std::array<int, 3>{0, 1, 2});
    CHECK(u.lone_edge_circles().empty());
  }
  // A small ball over the upper point covers it.
  balls.push_back({centroid + Vector3d(0, 0, 0.85), 0.2});
  const UnionOfBalls u(balls);
  int from_triangle = 0;
  for (const medspheres::VPoint& p : u.v_points())
    if (p.balls == std::array<int, 3>{0, 1, 2}) {
      ++from_triangle;
      CHECK((p.position - (centroid - Vector3d(0, 0, t))).norm() <= 8 * kEps);
    }
  CHECK(from_triangle == 1);
}

TEST_CASE("v-points: four spheres through one point", "[union_volume]") {
  // Each centre c has |c| = r exactly (dyadic Pythagorean triples), so all four spheres
  // pass through the origin; the power centre of the tetrahedron is the origin and its
  // power radius is exactly 0. The first three spheres meet again at p = (7/12)(1, 1, 1),
  // strictly inside the fourth ball: the triangle keeps the origin only.
  const std::vector<Sphere> balls{{{0.375, 0.5, 0}, 0.625},
                                  {{0, 0.375, 0.5}, 0.625},
                                  {{0.5, 0, 0.375}, 0.625},
                                  {{0.25, 0.375, 0.75}, 0.875}};
  const Vector3d p = Vector3d::Constant(7.0 / 12.0);
  REQUIRE((p - balls[3].center).norm() < balls[3].radius);
  const UnionOfBalls u(balls);
  REQUIRE(u.complex_tetrahedra().size() == 1);
  std::vector<Vector3d> kept;
  for (const medspheres::VPoint& v : u.v_points())
    if (v.balls == std::array<int, 3>{0, 1, 2}) kept.push_back(v.position);
  REQUIRE(kept.size() == 1);
  CHECK(kept[0].norm() <= 8 * kEps);
}

TEST_CASE("v-points and lone circles match a brute-force search", "[union_volume]") {
  for (const unsigned seed : {21u, 22u, 23u}) {
    const std::vector<Sphere> balls = random_balls(40, seed == 23u ? 1.05 : 0.62, seed);
    const UnionOfBalls u(balls);
    double rmax = 0.0;
    for (const Sphere& b : balls) rmax = std::max(rmax, b.radius);
    // Points are computed to ~eps rmax; classify only those clear of every other sphere
    // by far more than that.
    const double margin = 1e-9 * rmax;
    auto clearance = [&](const Vector3d& p, int i, int j, int k) {
      double c = std::numeric_limits<double>::infinity();
      for (int m = 0; m < static_cast<int>(balls.size()); ++m)
        if (m != i && m != j && m != k)
          c = std::min(c, (p - balls[m].center).norm() - balls[m].radius);
      return c;
    };
    // Every reported v-point is on its three spheres and in no ball's interior.
    for (const medspheres::VPoint& p : u.v_points()) {
      for (const int i : p.balls)
        CHECK(std::abs((p.position - balls[i].center).norm() - balls[i].radius) <=
              64 * kEps * rmax);
      CHECK(clearance(p.position, p.balls[0], p.balls[1], p.balls[2]) >= -margin);
    }
    // Every triple point clearly on the boundary is reported; none clearly inside is.
    const int n = static_cast<int>(balls.size());
    std::size_t found = 0;
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        for (int k = j + 1; k < n; ++k)
          for (const Vector3d& q : triple_points(balls[i], balls[j], balls[k])) {
            const double c = clearance(q, i, j, k);
            if (std::abs(c) <= margin) continue;
            const bool reported =
                std::any_of(u.v_points().begin(), u.v_points().end(), [&](const auto& p) {
                  return p.balls == std::array<int, 3>{i, j, k} &&
                         (p.position - q).norm() <= margin;
                });
            CHECK(reported == (c > 0));
            found += reported ? 1 : 0;
          }
    CHECK(found == u.v_points().size());
    // A lone circle lies on both spheres and entirely on the boundary of the union.
    for (const medspheres::EdgeCircle& c : u.lone_edge_circles()) {
      const Vector3d a = c.normal.unitOrthogonal(), b = c.normal.cross(a);
      for (int s = 0; s < 16; ++s) {
        const double phi = 2 * kPi * s / 16;
        const Vector3d p = c.center + c.radius * (std::cos(phi) * a + std::sin(phi) * b);
        for (const int i : c.balls)
          CHECK(std::abs((p - balls[i].center).norm() - balls[i].radius) <= 64 * kEps * rmax);
        CHECK(clearance(p, c.balls[0], c.balls[1], -1) >= -margin);
      }
    }
  }
}

TEST_CASE("bad input is rejected with the index of the ball", "[union_volume]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto message = [](const std::vector<Sphere>& balls) {
    try {
      UnionOfBalls u(balls);
    } catch (const medspheres::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const Sphere ok{{0, 0, 0}, 1};
  CHECK_THAT(message({ok, {{nan, 0, 0}, 1}}), Contains("sphere 1") && Contains("non-finite"));
  CHECK_THAT(message({ok, {{0, inf, 0}, 1}}), Contains("sphere 1"));
  CHECK_THAT(message({ok, ok, {{0, 0, 0}, 0}}), Contains("sphere 2 has radius 0"));
  CHECK_THAT(message({{{0, 0, 0}, -1}}), Contains("sphere 0 has radius -1"));
  CHECK_THAT(message({{{0, 0, 0}, nan}}), Contains("sphere 0"));
  CHECK_THAT(message({{{0, 0, 0}, inf}}), Contains("sphere 0"));
}
