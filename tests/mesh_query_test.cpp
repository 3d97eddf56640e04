#include <cmath>
#include <limits>
#include <random>

#include <catch2/catch.hpp>

#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/point_triangle.h"
#include "medspheres/sphere_tree.h"
#include "medspheres/triangle_tree.h"
#include "support/point_triangle_oracle.h"
#include "support/random_points.h"
#include "support/sanitizer_build.h"
#include "support/shared_meshes.h"

using namespace medspheres;

namespace {

// The accuracy MeshQuery promises (medspheres/point_triangle.h): the distance, and the
// returned point's distance to its triangle, are within kTolerance u S, with u = 2^-53
// and S = |p| + |p - a| + L for the nearest triangle (a a corner, L its longest edge).
// The library measures a few u S (at most ~13 u S, near the degenerate threshold); 32
// leaves room and still catches a face point taken from barycentric coordinates, whose
// error reaches 1e10 u S and more on slivers. The oracle is test::oracle_distance: 113-bit
// arithmetic and a different construction (support/point_triangle_oracle.h).
constexpr double kU = 0x1p-53;
constexpr double kTolerance = 32.0;

// For a mesh: |p - a| + L <= distance + 2 L, and L is at most the bounding box's diagonal.
double mesh_scale(const TriangleMesh& m, const Eigen::Vector3d& p, double distance) {
  return p.norm() + distance + 2.0 * m.bounds().sizes().norm();
}

// Query points of three kinds: uniform in the (enlarged) box, near the surface, far.
std::vector<Eigen::Vector3d> query_points(const TriangleMesh& m, std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  const Eigen::AlignedBox3d box = m.bounds();
  const Eigen::Vector3d c = box.center(), h = box.sizes() / 2;
  const double size = box.sizes().maxCoeff();
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<std::size_t> pick(0, m.triangles.size() - 1);
  std::vector<Eigen::Vector3d> pts;
  for (std::size_t i = 0; i < n; ++i) {
    const int kind = static_cast<int>(i % 3);
    if (kind == 0) {
      pts.push_back(c + 1.5 * Eigen::Vector3d(u(rng) * h.x(), u(rng) * h.y(), u(rng) * h.z()));
    } else if (kind == 1) {
      const std::size_t t = pick(rng);
      const Eigen::Vector3d on =
          test::random_point_on_triangle(m.corner(t, 0), m.corner(t, 1), m.corner(t, 2), rng);
      pts.push_back(on + 1e-3 * size * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    } else {
      pts.push_back(c + 20.0 * size * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    }
  }
  return pts;
}

// \p count random slivers (a, a + d, a + 0.37 d + w e, widths w from 1e-4 down to 1e-16),
// every eighth exactly collinear (w = 0) when \p collinear.
TriangleMesh random_slivers(int count, unsigned seed, bool collinear) {
  TriangleMesh m;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d a(u(rng), u(rng), u(rng)), d(u(rng), u(rng), u(rng)),
        e(u(rng), u(rng), u(rng));
    const double w = collinear && i % 8 == 7 ? 0.0 : std::pow(10.0, -4.0 - 12.0 * (i % 7) / 6.0);
    const int base = static_cast<int>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {a, a + d, a + 0.37 * d + w * e});
    m.triangles.push_back({base, base + 1, base + 2});
  }
  return m;
}

void check_closest_points(const TriangleMesh& m, std::size_t n, unsigned seed) {
  const MeshQuery q(m);
  const test::OracleMesh oracle(m);
  for (const Eigen::Vector3d& p : query_points(m, n, seed)) {
    const ClosestPoint cp = q.closest_point(p);
    const double want = oracle.distance(p);
    const double tolerance = kTolerance * kU * mesh_scale(m, p, want);
    REQUIRE(std::abs(cp.distance() - want) <= tolerance);
    // The returned point lies on the returned triangle, at the returned distance.
    REQUIRE(cp.triangle >= 0);
    REQUIRE(cp.triangle < static_cast<int>(m.triangles.size()));
    const std::size_t t = static_cast<std::size_t>(cp.triangle);
    REQUIRE(test::oracle_distance(cp.point, m.corner(t, 0), m.corner(t, 1), m.corner(t, 2)) <=
            tolerance);
    REQUIRE((p - cp.point).squaredNorm() == cp.squared_distance);
    REQUIRE(cp.distance() == std::sqrt(cp.squared_distance));
  }
}

}  // namespace

TEST_CASE("closest points agree with brute force on generated closed meshes", "[mesh_query]") {
  check_closest_points(make_torus(1.0, 0.3, 40, 20), 600, 1);
  check_closest_points(make_box({1.0, 0.2, 3.0}, 3), 600, 2);
  check_closest_points(make_icosphere(2.0, 3), 600, 3);
  check_closest_points(make_capsule(0.4, 1.5, 24, 6), 600, 4);
  // Far from the origin: the float boxes are relative to the mesh's centre.
  TriangleMesh shifted = make_torus(1.0, 0.3, 30, 12);
  for (auto& v : shifted.vertices) v += Eigen::Vector3d(1e6, -2e6, 3e5);
  check_closest_points(shifted, 300, 5);
}

namespace {

// MeshQuery and TriangleTree share one point-triangle kernel, so they agree to the bit:
// on the triangle MeshQuery returns, TriangleTree's leaf test gives the same distance
// and closest_point_on_triangle the same point; and TriangleTree's own search (a sphere
// tree of one tiny ball at p) ends on a triangle at exactly MeshQuery's distance.
void check_same_as_triangle_tree(const TriangleMesh& m, std::size_t n, unsigned seed) {
  const MeshQuery q(m);
  const TriangleTree tree(m);
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  const auto leaf = [](int t) {
    TargetNode node;
    node.is_leaf = true;
    node.primitive = t;
    return node;
  };
  for (const Eigen::Vector3d& p : query_points(m, n, seed)) {
    const ClosestPoint cp = q.closest_point(p);
    const std::size_t t = static_cast<std::size_t>(cp.triangle);
    INFO("p = " << p.transpose() << ", triangle " << t);
    REQUIRE(closest_point_on_triangle(p, m.corner(t, 0), m.corner(t, 1), m.corner(t, 2)) ==
            cp.point);
    REQUIRE(tree.ball_proximity(leaf(cp.triangle), p, 0.0).distance == cp.distance());
    // A radius far below every distance's ulp: |q - p| - r rounds to |q - p|.
    SphereSet one;
    one.spheres.push_back({p, 1e-300});
    const TreeDistance d = distance(SphereTree(one), I, tree, I);
    REQUIRE(d.found());
    CHECK(tree.ball_proximity(leaf(static_cast<int>(d.primitive_b)), p, 0.0).distance ==
          cp.distance());
  }
}

}  // namespace

TEST_CASE("MeshQuery and TriangleTree give identical closest points", "[mesh_query]") {
  check_same_as_triangle_tree(make_torus(1.0, 0.3, 40, 20), 300, 21);
  check_same_as_triangle_tree(make_icosphere(2.0, 3), 300, 22);
  TriangleMesh shifted = make_capsule(0.4, 1.5, 24, 6);
  for (auto& v : shifted.vertices) v += Eigen::Vector3d(1e6, -2e6, 3e5);
  check_same_as_triangle_tree(shifted, 300, 23);
  // Slivers and degenerate triangles take the kernel's other paths.
  check_same_as_triangle_tree(random_slivers(120, 24, true), 300, 25);
}

TEST_CASE("closest points on degenerate and single triangles", "[mesh_query]") {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 0, 1}, {5, 5, 5}};
  m.triangles = {{0, 1, 2},   // collinear: a segment from 0 to 2
                 {3, 3, 4},   // repeated vertex: a segment from 3 to 4
                 {5, 5, 5}};  // a point
  check_closest_points(m, 300, 6);
  const MeshQuery q(m);
  const ClosestPoint c = q.closest_point({1.5, 1.0, 0.0});
  CHECK(c.triangle == 0);
  CHECK(c.point.isApprox(Eigen::Vector3d(1.5, 0, 0)));
  CHECK(q.closest_point({5, 5, 6}).squared_distance == 1.0);

  // Slivers: nearly collinear corners make the computed normal ill-conditioned, which
  // the plane bound used for pruning must survive.
  check_closest_points(random_slivers(200, 8, false), 600, 9);

  TriangleMesh one;
  one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  one.triangles = {{0, 1, 2}};
  check_closest_points(one, 200, 7);
  const MeshQuery q1(one);
  CHECK(q1.stats().nodes == 1);
}

namespace {

// A random rotation.
Eigen::Matrix3d random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

// Compares MeshQuery on its one triangle (a, b, c) with the oracle at p, within
// kTolerance u S (see the top of this file).
void check_one_triangle(const MeshQuery& q, const Eigen::Vector3d& p) {
  const TriangleMesh& m = q.mesh();
  const Eigen::Vector3d &a = m.corner(0, 0), &b = m.corner(0, 1), &c = m.corner(0, 2);
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  const double scale = kU * (p.norm() + (p - a).norm() + longest);
  const ClosestPoint cp = q.closest_point(p);
  const double want = test::oracle_distance(p, a, b, c);
  const double off = test::oracle_distance(cp.point, a, b, c);  // 0 if on the triangle
  INFO("p = " << p.transpose() << ", distance " << cp.distance() << ", oracle " << want);
  CHECK(std::abs(cp.distance() - want) <= kTolerance * scale);
  CHECK(off <= kTolerance * scale);
}

}  // namespace

TEST_CASE("closest points on slivers and needles match the 113-bit oracle", "[mesh_query]") {
  // Points exactly in the plane of a sliver, inside it: a face point from barycentric
  // coordinates would be 6.5e-12 (w = 1e-3) to 6.5e-6 (w = 1e-6) away from them.
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  for (const double w : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9}) {
    TriangleMesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, w, 0}};
    m.triangles = {{0, 1, 2}};
    const MeshQuery q(m);
    for (int i = 0; i < 200; ++i) {
      // In the plane, inside up to rounding.
      const Eigen::Vector3d p =
          test::random_point_on_triangle(m.vertices[0], m.vertices[1], m.vertices[2], rng);
      const double d = q.closest_point(p).distance();
      INFO("w = " << w << ", p = " << p.transpose() << ", distance " << d);
      CHECK(d <= kTolerance * kU * (2.0 * p.norm() + 1.0));  // S = |p| + |p - a| + L, a = 0
    }
  }

  // Random slivers (a third corner at height w over the long edge) and needles (a short
  // edge of length w), widths 1e-2 .. 1e-9, in random orientations and positions; query
  // points on them, near them (near edges and corners too) and far from them.
  for (int i = 0; i < 480; ++i) {
    const double w = std::pow(10.0, -2.0 - 7.0 * (i % 8) / 7.0);
    const Eigen::Matrix3d rot = random_rotation(rng);
    const Eigen::Vector3d shift =
        (i % 3 == 0 ? 0.0 : 100.0) * Eigen::Vector3d(u(rng), u(rng), u(rng));
    Eigen::Vector3d c;
    if (i % 2 == 0)
      c = Eigen::Vector3d(1.2 * u01(rng) - 0.1, w, 0.0);  // a cap, or an obtuse sliver
    else
      c = Eigen::Vector3d(1.0 + w * u(rng), w * u01(rng), 0.0);  // a needle at b
    TriangleMesh m;
    m.vertices = {rot * Eigen::Vector3d(0, 0, 0) + shift, rot * Eigen::Vector3d(1, 0, 0) + shift,
                  rot * c + shift};
    m.triangles = {
        {static_cast<int>(i % 3), static_cast<int>((i + 1) % 3), static_cast<int>((i + 2) % 3)}};
    const MeshQuery q(m);
    const Eigen::Vector3d v[3] = {m.vertices[0], m.vertices[1], m.vertices[2]};
    const Eigen::Vector3d normal = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
    for (int j = 0; j < 24; ++j) {
      Eigen::Vector3d p = test::random_point_on_triangle(v[0], v[1], v[2], rng);  // on, to rounding
      const Eigen::Vector3d random(u(rng), u(rng), u(rng));
      const double tiny = std::pow(10.0, -16.0 + 8.0 * u01(rng));
      const int e = j % 3;
      switch (j % 6) {
        case 1:
          p += 1e-6 * random;
          break;
        case 2:
          p += 1e-3 * u(rng) * normal + 1e-12 * random;
          break;
        case 3:
          p = v[e] + u01(rng) * (v[(e + 1) % 3] - v[e]) + tiny * random;
          break;
        case 4:
          p = v[e] + tiny * random;
          break;
        case 5:
          p += 10.0 * random;
          break;
        default:
          break;
      }
      check_one_triangle(q, p);
    }
  }
}

TEST_CASE("closest points far from the mesh are finite and exact", "[mesh_query]") {
  // Float box distances overflow beyond 1.8e19 from the mesh, and squared distances
  // beyond 1.3e154; the search must still return a triangle (not prune every box or
  // triangle and leave triangle -1) and the exact distance.
  TriangleMesh tetra;
  tetra.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const TriangleMesh& m : {tetra, make_torus(1.0, 0.3, 40, 20)}) {
    const MeshQuery q(m);
    std::vector<Eigen::Vector3d> pts = {{2e19, 0, 0},    {1e20, 0, 0},           {-1e20, 3, 0},
                                        {1e39, 0, 0},    {0, 1e154, 0},          {0, 0, 1e160},
                                        {1e300, 0, 0},   {-1e300, 0, 0},         {0, 1e300, -1e300},
                                        {1.7e308, 0, 0}, {-1e308, 8e307, -9e307}};
    for (int e = 15; e <= 305; e += 10)
      pts.push_back(std::pow(10.0, e) * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    for (const Eigen::Vector3d& p : pts) {
      INFO("p = " << p.transpose());
      const ClosestPoint cp = q.closest_point(p);
      REQUIRE(cp.triangle >= 0);
      REQUIRE(cp.triangle < static_cast<int>(m.triangles.size()));
      REQUIRE(std::isfinite(cp.distance()));
      const double want = test::oracle_mesh_distance(m, p);
      const double tolerance = kTolerance * kU * mesh_scale(m, p, want);
      CHECK(std::abs(cp.distance() - want) <= tolerance);
      const std::size_t t = static_cast<std::size_t>(cp.triangle);
      CHECK(test::oracle_distance(cp.point, m.corner(t, 0), m.corner(t, 1), m.corner(t, 2)) <=
            tolerance);
      // squared_distance is |p - point|^2, +infinity once that overflows.
      CHECK(cp.squared_distance == (p - cp.point).squaredNorm());
      CHECK(q.closest_point(p, 0).distance() == cp.distance());
      CHECK(q.closest_points({p}, 1)[0].distance() == cp.distance());
    }
  }
  // Beyond 2^200 from the mesh's centre the search is brute force in scaled coordinates:
  // a tiny mesh seen from afar (its squared edges underflow there), and a mesh so large
  // that every query takes that path, even those near it.
  TriangleMesh tiny = make_torus(1.0, 0.3, 20, 10), huge = tiny;
  for (auto& v : tiny.vertices) v *= 1e-50;
  for (auto& v : huge.vertices) v *= 1e70;
  const MeshQuery q_tiny(tiny);
  for (int e = 200; e <= 300; e += 20) {
    const Eigen::Vector3d p = std::pow(10.0, e) * Eigen::Vector3d(u(rng), u(rng), u(rng));
    const double want = test::oracle_mesh_distance(tiny, p);
    CHECK(std::abs(q_tiny.closest_point(p).distance() - want) <=
          kTolerance * kU * mesh_scale(tiny, p, want));
  }
  check_closest_points(huge, 300, 42);

  const MeshQuery q(tetra);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(q.closest_point({nan, 0, 0}), std::invalid_argument);
  CHECK_THROWS_AS(q.closest_point({0, inf, 0}, 1), std::invalid_argument);
  CHECK_THROWS_AS(q.closest_points({{0, 0, 0}, {0, 0, -inf}}), std::invalid_argument);
}

TEST_CASE("closest points on tiny and huge meshes", "[mesh_query]") {
  // The float boxes are scaled to the mesh's size, so that they neither underflow on a
  // tiny mesh (which would stop all pruning) nor overflow on a huge one. Scaling the mesh
  // and the queries by a power of two scales every answer exactly and leaves the
  // traversal's work unchanged.
  const TriangleMesh unit = make_torus(1.0, 0.3, 40, 20);
  const std::vector<Eigen::Vector3d> pts = query_points(unit, 300, 51);
  const MeshQuery q(unit);
  for (const int e : {-120, -60, 60, 120}) {
    INFO("scale 2^" << e);
    TriangleMesh scaled = unit;
    for (auto& v : scaled.vertices) v *= std::ldexp(1.0, e);
    const MeshQuery qs(scaled);
    for (const Eigen::Vector3d& p : pts) {
      QueryCounters c1, c2;
      const ClosestPoint a = q.closest_point(p, &c1);
      const ClosestPoint b = qs.closest_point(std::ldexp(1.0, e) * p, &c2);
      CHECK(b.distance() == std::ldexp(a.distance(), e));
      CHECK(b.triangle == a.triangle);
      CHECK(c2.nodes_visited == c1.nodes_visited);
      CHECK(c2.triangles_tested == c1.triangles_tested);
    }
    check_closest_points(scaled, 150, 52);
  }
}

TEST_CASE("points exactly on the surface are at distance zero", "[mesh_query]") {
  const TriangleMesh m = make_torus(1.0, 0.25, 32, 16);
  const MeshQuery q(m);
  for (std::size_t t = 0; t < m.triangles.size(); t += 7) {
    for (int k = 0; k < 3; ++k) CHECK(q.closest_point(m.corner(t, k)).squared_distance == 0.0);
    const Eigen::Vector3d mid = 0.5 * (m.corner(t, 0) + m.corner(t, 1));
    CHECK(q.closest_point(mid).distance() <= 4e-16 * (1.0 + mid.norm()));
    const Eigen::Vector3d centroid = (m.corner(t, 0) + m.corner(t, 1) + m.corner(t, 2)) / 3.0;
    CHECK(q.closest_point(centroid).distance() <= 4e-16 * (1.0 + centroid.norm()));
  }
}

TEST_CASE("a hint changes the work, never the distance", "[mesh_query]") {
  const TriangleMesh m = make_icosphere(1.0, 4);
  const MeshQuery q(m);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(m.triangles.size()) - 1);
  QueryCounters plain, hinted;
  for (const Eigen::Vector3d& p : query_points(m, 300, 12)) {
    const ClosestPoint a = q.closest_point(p, &plain);
    const ClosestPoint b = q.closest_point(p, a.triangle, &hinted);
    const ClosestPoint c = q.closest_point(p, pick(rng));
    CHECK(b.squared_distance == a.squared_distance);
    CHECK(c.squared_distance == a.squared_distance);
  }
  CHECK(hinted.nodes_visited <= plain.nodes_visited);
  CHECK_THROWS_AS(q.closest_point({0, 0, 0}, -1), std::invalid_argument);
  CHECK_THROWS_AS(q.closest_point({0, 0, 0}, static_cast<int>(m.triangles.size())),
                  std::invalid_argument);
}

TEST_CASE("batch queries match single queries for every thread count", "[mesh_query]") {
  const TriangleMesh m = make_torus(1.0, 0.4, 48, 24);
  const MeshQuery q(m);
  const std::vector<Eigen::Vector3d> pts = query_points(m, 2000, 13);
  const std::vector<ClosestPoint> one = q.closest_points(pts, 1);
  const std::vector<double> w1 = q.winding_numbers(pts, 1);
  for (int threads : {2, 3, 0}) {
    const std::vector<ClosestPoint> many = q.closest_points(pts, threads);
    const std::vector<double> wn = q.winding_numbers(pts, threads);
    REQUIRE(many.size() == pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      CHECK(many[i].squared_distance == one[i].squared_distance);
      CHECK(many[i].triangle == one[i].triangle);
      CHECK(wn[i] == w1[i]);
    }
  }
  for (std::size_t i = 0; i < pts.size(); i += 97)
    CHECK(one[i].squared_distance == q.closest_point(pts[i]).squared_distance);
  CHECK_THROWS_AS(q.closest_points(pts, -1), std::invalid_argument);
}

TEST_CASE("winding numbers: hierarchical against exact, and exact against geometry",
          "[mesh_query]") {
  const double R = 1.0, r = 0.35;
  const TriangleMesh m = make_torus(R, r, 96, 48);
  const MeshQuery q(m);
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  int inside = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), 0.5 * u(rng));
    const double exact = q.winding_number_exact(p);
    const double fast = q.winding_number(p);
    // The default beta = 2 keeps the total error within 1e-2 (see mesh_query.h), which
    // still separates 0 from 1 by a wide margin.
    CHECK(std::abs(fast - exact) < 1e-2);
    // The inscribed polygonal torus differs from the ideal one by at most the sagitta
    // of its facets; away from that band the ideal inside test is the truth.
    const double tube = std::hypot(std::hypot(p.x(), p.y()) - R, p.z()) - r;
    const double band =
        r * (1 - std::cos(3.14159265 / 48)) + R * (1 - std::cos(3.14159265 / 96)) + 1e-9;
    if (std::abs(tube) > band) {
      const bool truth = tube < 0;
      CHECK(q.inside(p) == truth);
      CHECK(std::abs(exact - (truth ? 1.0 : 0.0)) < 1e-9);
      inside += truth;
    }
  }
  CHECK(inside > 100);  // the sample really probes the interior
}

TEST_CASE("winding numbers stay sensible on open and inward meshes", "[mesh_query]") {
  TriangleMesh open = make_icosphere(1.0, 3);
  open.triangles.resize(open.triangles.size() - 8);  // punch a small hole
  const MeshQuery q(open);
  const double centre = q.winding_number({0, 0, 0});
  CHECK(centre > 0.9);
  CHECK(centre < 1.0);
  CHECK(q.inside({0.1, -0.2, 0.3}));
  CHECK_FALSE(q.inside({3, 0, 0}));
  CHECK(std::abs(q.winding_number({0, 0, 0}) - q.winding_number_exact({0, 0, 0})) < 1e-2);

  TriangleMesh inward = make_icosphere(1.0, 2);
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  CHECK(MeshQuery(inward).winding_number({0, 0, 0}) == Approx(-1.0).margin(1e-2));
}

TEST_CASE("MeshQuery rejects unusable meshes and options", "[mesh_query]") {
  CHECK_THROWS_AS(MeshQuery(TriangleMesh{}), std::invalid_argument);
  TriangleMesh m = make_box({1, 1, 1});
  MeshQueryOptions o;
  o.winding_beta = 0.5;
  CHECK_THROWS_AS(MeshQuery(m, o), std::invalid_argument);
  m.vertices[0].x() = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(MeshQuery(m), std::invalid_argument);
  m = make_box({1, 1, 1});
  m.triangles[3][0] = 100;
  CHECK_THROWS_AS(MeshQuery(m), std::invalid_argument);
}

TEST_CASE("hierarchy statistics describe a real 4-wide tree", "[mesh_query]") {
  const TriangleMesh m = make_torus(1.0, 0.3, 100, 50);  // 10,000 triangles
  const MeshBvhStats s = MeshQuery(m).stats();
  CHECK(s.triangles == 10000);
  CHECK(s.nodes >= 10000 / 4);
  CHECK(s.nodes < 10000);
  CHECK(s.depth >= 7);  // ceil(log4(10000))
  CHECK(s.depth < 40);
  CHECK(s.bytes > s.nodes * 128);
}

#ifdef MEDSPHERES_SHARED_MESHES
TEST_CASE("points on the slivers of a CAD mesh are at distance zero to rounding",
          "[mesh_query][shared]") {
  // quartet/block.obj has slivers (kappa up to 1e4 and more) and zero-area triangles;
  // points sampled on its triangles came back up to 1.5e-7 from the surface.
  const test::SharedMesh* row = nullptr;
  for (const auto& r : test::shared_meshes())
    if (r.file == "quartet/block.obj") row = &r;
  REQUIRE(row != nullptr);
  const TriangleMesh m = load_mesh(row->path).mesh;
  const MeshQuery q(m);
  std::mt19937_64 rng(61);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double size = m.bounds().sizes().maxCoeff();
  const test::OracleMesh oracle(m);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Eigen::Vector3d &a = m.corner(t, 0), &b = m.corner(t, 1), &c = m.corner(t, 2);
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d p = test::random_point_on_triangle(a, b, c, rng);  // on, to rounding
      if (k == 2) p += 1e-6 * size * Eigen::Vector3d(u(rng), u(rng), u(rng));
      const ClosestPoint cp = q.closest_point(p);
      const double want = oracle.distance(p);
      const double scale = kU * mesh_scale(m, p, want);
      INFO("triangle " << t << ", p = " << p.transpose());
      CHECK(std::abs(cp.distance() - want) <= kTolerance * scale);
      if (k < 2) CHECK(cp.distance() <= kTolerance * scale);
    }
  }
}

TEST_CASE("closest points and inside tests on every closed shared mesh", "[mesh_query][shared]") {
  for (const auto& row : test::shared_meshes()) {
    if (!row.closed) continue;
    INFO(row.file);
    const LoadedMesh loaded = load_mesh(row.path);
    // Brute force costs points x triangles; keep it to a few million pair tests (one
    // million in the sanitizer builds).
    const std::size_t pair_tests = test::kSanitizerBuild ? 1000000 : 3000000;
    const std::size_t n = std::max<std::size_t>(30, pair_tests / loaded.mesh.triangles.size());
    check_closest_points(loaded.mesh, n, 99);
    const MeshQuery q(loaded.mesh);
    std::size_t agree = 0, total = 0;
    for (const Eigen::Vector3d& p : query_points(loaded.mesh, 60, 7)) {
      const double exact = q.winding_number_exact(p);
      CHECK(std::abs(q.winding_number(p) - exact) < 2e-2);
      if (std::abs(exact - 0.5) > 0.25) {
        ++total;
        agree += q.inside(p) == (exact > 0.5);
      }
    }
    CHECK(agree == total);
  }
}
#endif

TEST_CASE("cap_holes: boundary chains get fans, and closest points include them", "[mesh]") {
  // The unit cube [-1, 1]^3 without its top face (z = 1): one boundary loop of four
  // edges, wound as the walls' triangles run.
  TriangleMesh open = make_box(Eigen::Vector3d(1, 1, 1), 1);
  std::vector<std::array<int, 3>> kept;
  for (std::size_t t = 0; t < open.triangles.size(); ++t) {
    bool top = true;
    for (int k = 0; k < 3; ++k) top = top && open.corner(t, k).z() == 1.0;
    if (!top) kept.push_back(open.triangles[t]);
  }
  REQUIRE(kept.size() == 10);
  open.triangles = kept;
  const std::vector<std::vector<int>> loops = boundary_loops(open);
  REQUIRE(loops.size() == 1);
  REQUIRE(loops[0].size() == 4);
  for (int v : loops[0]) CHECK(open.vertices[static_cast<std::size_t>(v)].z() == 1.0);
  // Each loop edge a -> b runs as in the one triangle that uses it.
  for (std::size_t k = 0; k < 4; ++k) {
    const int a = loops[0][k], b = loops[0][(k + 1) % 4];
    int uses = 0;
    for (const auto& t : open.triangles)
      for (int j = 0; j < 3; ++j) uses += t[j] == a && t[(j + 1) % 3] == b;
    CHECK(uses == 1);
  }
  CHECK(boundary_loops(make_box(Eigen::Vector3d(1, 1, 1), 2)).empty());

  MeshQueryOptions capped;
  capped.cap_holes = true;
  const MeshQuery plain(open), with_caps(open, capped);
  CHECK(plain.cap_mesh().triangles.empty());
  REQUIRE(with_caps.cap_mesh().triangles.size() == 4);
  CHECK(with_caps.stats().cap_triangles == 4);
  // Just below the missing face: 0.1 from the hole, 0.6 from the nearest wall.
  const Eigen::Vector3d p(0.4, 0.1, 0.9);
  CHECK(plain.closest_point(p).distance() == Approx(0.6));
  const ClosestPoint c = with_caps.closest_point(p);
  CHECK(c.distance() == Approx(0.1));
  CHECK(c.point.isApprox(Eigen::Vector3d(0.4, 0.1, 1.0)));
  REQUIRE(c.triangle >= 10);
  const std::array<Eigen::Vector3d, 3> corners = with_caps.triangle_corners(c.triangle);
  for (const Eigen::Vector3d& x : corners) CHECK(x.z() == 1.0);
  // A hint on a cap triangle or a wall gives the same distance.
  CHECK(with_caps.closest_point(p, c.triangle).distance() == c.distance());
  CHECK(with_caps.closest_point(p, 0).distance() == c.distance());
  CHECK_THROWS_AS(with_caps.closest_point(p, 14), std::invalid_argument);
  CHECK_THROWS_AS(with_caps.triangle_corners(14), std::out_of_range);
  // The winding number is the open mesh's, caps or not.
  for (const Eigen::Vector3d& q : {p, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 2)})
    CHECK(with_caps.winding_number(q) == plain.winding_number(q));
  // Against brute force over walls and caps together, on random points.
  TriangleMesh both = open;
  const TriangleMesh& caps = with_caps.cap_mesh();
  const int base = static_cast<int>(both.vertices.size());
  both.vertices.insert(both.vertices.end(), caps.vertices.begin(), caps.vertices.end());
  for (const auto& t : caps.triangles)
    both.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  const MeshQuery oracle(both);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int k = 0; k < 500; ++k) {
    const Eigen::Vector3d q(u(rng), u(rng), u(rng));
    CHECK(with_caps.closest_point(q).distance() == oracle.closest_point(q).distance());
  }
  // A closed mesh has no caps: the same answers either way.
  const TriangleMesh closed = make_torus(1.0, 0.3, 24, 12);
  const MeshQuery a(closed), b(closed, capped);
  CHECK(b.cap_mesh().triangles.empty());
  for (int k = 0; k < 100; ++k) {
    const Eigen::Vector3d q(u(rng), u(rng), u(rng));
    CHECK(a.closest_point(q).distance() == b.closest_point(q).distance());
  }
}

TEST_CASE("a MeshQuery that takes over its mesh answers as one that copies it", "[mesh_query]") {
  // An open torus (a ring of its triangles removed), so that the caps are built too.
  TriangleMesh open = make_torus(1.0, 0.3, 24, 12);
  open.triangles.erase(open.triangles.begin(), open.triangles.begin() + 24);
  MeshQueryOptions capped;
  capped.cap_holes = true;
  const MeshQuery copied(open, capped);
  TriangleMesh moved_mesh = open;
  const MeshQuery moved(std::move(moved_mesh), capped);
  CHECK(moved.mesh().triangles == open.triangles);
  CHECK(moved.mesh().vertices == open.vertices);
  CHECK(moved.cap_mesh().triangles.size() == copied.cap_mesh().triangles.size());
  CHECK_FALSE(moved.cap_mesh().triangles.empty());
  CHECK(moved.stats().nodes == copied.stats().nodes);
  CHECK(moved.stats().bytes == copied.stats().bytes);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d q(u(rng), u(rng), u(rng));
    const ClosestPoint a = copied.closest_point(q), b = moved.closest_point(q);
    CHECK(a.distance() == b.distance());
    CHECK(a.triangle == b.triangle);
    CHECK(copied.winding_number(q) == moved.winding_number(q));
  }
  TriangleMesh bad = open;
  bad.triangles[0][0] = -1;
  CHECK_THROWS_AS(MeshQuery(std::move(bad), capped), std::invalid_argument);
}
