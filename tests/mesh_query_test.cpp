#include <cmath>
#include <limits>
#include <random>

#include <catch2/catch.hpp>

#include "medspheres/mesh_generators.h"
#include "medspheres/mesh_io.h"
#include "medspheres/mesh_query.h"
#include "support/shared_meshes.h"

using namespace medspheres;

namespace {

// Oracle for the closest point on one triangle, by a different construction than the
// library's Voronoi-region walk: project onto the plane; if the projection is inside
// (all three edge tests agree) it is the answer, otherwise the nearest of the three
// edge segments is.
Eigen::Vector3d oracle_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double dd = d.squaredNorm();
  if (dd == 0.0) return a;
  const double t = std::min(1.0, std::max(0.0, (p - a).dot(d) / dd));
  return a + t * d;
}

Eigen::Vector3d oracle_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  if (n.squaredNorm() > 0.0) {
    const Eigen::Vector3d q = p - n * (n.dot(p - a) / n.squaredNorm());
    const bool in = n.dot((b - a).cross(q - a)) >= 0 && n.dot((c - b).cross(q - b)) >= 0 &&
                    n.dot((a - c).cross(q - c)) >= 0;
    if (in) return q;
  }
  const Eigen::Vector3d s[3] = {oracle_segment(p, a, b), oracle_segment(p, b, c),
                                oracle_segment(p, c, a)};
  int best = 0;
  for (int k = 1; k < 3; ++k)
    if ((p - s[k]).squaredNorm() < (p - s[best]).squaredNorm()) best = k;
  return s[best];
}

double brute_force_distance2(const TriangleMesh& m, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    best = std::min(
        best,
        (p - oracle_triangle(p, m.corner(t, 0), m.corner(t, 1), m.corner(t, 2))).squaredNorm());
  return best;
}

// Query points of three kinds: uniform in the (enlarged) box, near the surface, far.
std::vector<Eigen::Vector3d> query_points(const TriangleMesh& m, std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  const Eigen::AlignedBox3d box = m.bounds();
  const Eigen::Vector3d c = box.center(), h = box.sizes() / 2;
  const double size = box.sizes().maxCoeff();
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  std::uniform_int_distribution<std::size_t> pick(0, m.triangles.size() - 1);
  std::vector<Eigen::Vector3d> pts;
  for (std::size_t i = 0; i < n; ++i) {
    const int kind = static_cast<int>(i % 3);
    if (kind == 0) {
      pts.push_back(c + 1.5 * Eigen::Vector3d(u(rng) * h.x(), u(rng) * h.y(), u(rng) * h.z()));
    } else if (kind == 1) {
      const std::size_t t = pick(rng);
      double s = u01(rng), r = u01(rng);
      if (s + r > 1) {
        s = 1 - s;
        r = 1 - r;
      }
      const Eigen::Vector3d on = m.corner(t, 0) + s * (m.corner(t, 1) - m.corner(t, 0)) +
                                 r * (m.corner(t, 2) - m.corner(t, 0));
      pts.push_back(on + 1e-3 * size * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    } else {
      pts.push_back(c + 20.0 * size * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    }
  }
  return pts;
}

void check_closest_points(const TriangleMesh& m, std::size_t n, unsigned seed) {
  const MeshQuery q(m);
  for (const Eigen::Vector3d& p : query_points(m, n, seed)) {
    const ClosestPoint cp = q.closest_point(p);
    const double want = std::sqrt(brute_force_distance2(m, p));
    // The library and the oracle reach the same point by different arithmetic. Each
    // rounds the point's coordinates, so the distances may differ by a few ulps of the
    // coordinates' magnitude (|p| plus the mesh's extent), not of the distance.
    const double scale = p.norm() + m.bounds().sizes().norm();
    REQUIRE(std::abs(cp.distance() - want) <= 64 * std::numeric_limits<double>::epsilon() * scale);
    // The returned point lies on the returned triangle, at the returned distance. The
    // oracle's projection is itself ill-conditioned on slivers (its normal loses
    // 1/sin(angle) digits), so the on-triangle check is made where sin(angle) > 1e-3.
    const Eigen::Vector3d &a = m.corner(cp.triangle, 0), &b = m.corner(cp.triangle, 1),
                          &c = m.corner(cp.triangle, 2);
    if ((b - a).cross(c - a).norm() > 1e-3 * (b - a).norm() * (c - a).norm()) {
      const Eigen::Vector3d on = oracle_triangle(cp.point, a, b, c);
      REQUIRE((on - cp.point).norm() <= 1e-12 * (1.0 + p.norm()));
    }
    REQUIRE((p - cp.point).squaredNorm() == cp.squared_distance);
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
  TriangleMesh slivers;
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d a(u(rng), u(rng), u(rng)), d(u(rng), u(rng), u(rng)),
        e(u(rng), u(rng), u(rng));
    const double thin = std::pow(10.0, -4.0 - 12.0 * (i % 7) / 6.0);  // 1e-4 .. 1e-16
    const int base = static_cast<int>(slivers.vertices.size());
    slivers.vertices.push_back(a);
    slivers.vertices.push_back(a + d);
    slivers.vertices.push_back(a + 0.37 * d + thin * e);
    slivers.triangles.push_back({base, base + 1, base + 2});
  }
  check_closest_points(slivers, 600, 9);

  TriangleMesh one;
  one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  one.triangles = {{0, 1, 2}};
  check_closest_points(one, 200, 7);
  const MeshQuery q1(one);
  CHECK(q1.stats().nodes == 1);
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
    // The default beta = 3 keeps the total error within 1e-2 (see mesh_query.h), which
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
TEST_CASE("closest points and inside tests on every closed shared mesh", "[mesh_query][shared]") {
  for (const auto& row : test::shared_meshes()) {
    if (!row.closed) continue;
    INFO(row.file);
    const LoadedMesh loaded = load_mesh(row.path);
    // Brute force costs points x triangles; keep it to a few million pair tests.
    const std::size_t n = std::max<std::size_t>(30, 3000000 / loaded.mesh.triangles.size());
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
