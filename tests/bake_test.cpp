#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include <catch2/catch.hpp>

#include "medspheres/bake.h"
#include "medspheres/error.h"
#include "medspheres/mesh_generators.h"
#include "medspheres/mesh_io.h"
#include "medspheres/mesh_query.h"
#include "support/shared_meshes.h"

using namespace medspheres;
using Catch::Matchers::Contains;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Distance from p to the mesh by brute force over all triangles, through a
// construction independent of the library's (projection, else nearest edge).
double brute_distance(const TriangleMesh& m, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  auto seg = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d d = b - a;
    const double dd = d.squaredNorm();
    const double t = dd > 0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
    return (p - (a + t * d)).norm();
  };
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Eigen::Vector3d &a = m.corner(t, 0), &b = m.corner(t, 1), &c = m.corner(t, 2);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    double d = std::min({seg(a, b), seg(b, c), seg(c, a)});
    if (n.squaredNorm() > 0) {
      const Eigen::Vector3d q = p - n * (n.dot(p - a) / n.squaredNorm());
      if (n.dot((b - a).cross(q - a)) >= 0 && n.dot((c - b).cross(q - b)) >= 0 &&
          n.dot((a - c).cross(q - c)) >= 0)
        d = std::min(d, (p - q).norm());
    }
    best = std::min(best, d);
  }
  return best;
}

// Every sphere lies inside the solid: centre inside (exact winding number), radius at
// most the brute-force distance from the centre to the surface.
void check_internal(const TriangleMesh& m, const BakeResult& r) {
  const MeshQuery q(m);
  REQUIRE(r.spheres.size() > 0);
  REQUIRE(r.samples.size() == r.spheres.size());
  for (const Sphere& s : r.spheres.spheres) {
    CHECK(s.radius > 0.0);
    CHECK(s.radius <= brute_distance(m, s.center));
    CHECK(q.winding_number_exact(s.center) > 0.5);
  }
}

BakeResult bake_at(const TriangleMesh& m, int resolution, int threads = 0) {
  BakeOptions o;
  o.resolution = resolution;
  o.threads = threads;
  return bake(m, o);
}

bool bit_identical(const SphereSet& a, const SphereSet& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(a.spheres[i].center.data(), b.spheres[i].center.data(), 3 * sizeof(double)) !=
        0)
      return false;
    if (std::memcmp(&a.spheres[i].radius, &b.spheres[i].radius, sizeof(double)) != 0) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("baked spheres are inside generated closed solids", "[bake]") {
  for (const TriangleMesh& m : {make_box({1.0, 0.6, 0.3}, 3), make_torus(1.0, 0.3, 48, 24),
                                make_capsule(0.3, 0.8, 24, 6), make_icosphere(1.0, 3)}) {
    check_internal(m, bake_at(m, 24));
  }
}

TEST_CASE("box: centres lie on the medial surface, radii are the face distances", "[bake]") {
  const Eigen::Vector3d h(1.0, 0.6, 0.3);
  const BakeResult r = bake_at(make_box(h, 2), 32);
  REQUIRE(r.spheres.size() > 50);
  const double tol = r.stats.medial_tolerance;
  for (const Sphere& s : r.spheres.spheres) {
    // Distances to the six faces; the medial surface is where the smallest is attained
    // twice. The centre is within `tol` of it along the search segment, and the gap
    // between the two smallest distances changes at most twice as fast as position.
    double d[6];
    for (int a = 0; a < 3; ++a) {
      d[2 * a] = h[a] - s.center[a];
      d[2 * a + 1] = h[a] + s.center[a];
    }
    std::sort(d, d + 6);
    CHECK(d[1] - d[0] <= 2.0 * tol + 1e-12);
    CHECK(s.radius == Approx(d[0]).margin(1e-9));
  }
}

TEST_CASE("sphere, capsule and torus: centres on the known medial axis", "[bake]") {
  SECTION("sphere: one sphere at the centre") {
    const BakeResult r = bake_at(make_icosphere(1.0, 4), 24);
    REQUIRE(r.spheres.size() == 1);
    // The icosphere's facets lie within 1 - cos(edge angle / 2) of the unit sphere;
    // their medial point sits within that of the origin.
    CHECK(r.spheres.spheres[0].center.norm() < 0.01);
    CHECK(r.spheres.spheres[0].radius == Approx(1.0).margin(0.01));
  }
  SECTION("capsule: centres on the axis segment") {
    const double R = 0.3, half = 0.8;
    const int slices = 48;
    const BakeResult r = bake_at(make_capsule(R, half, slices, 12), 32);
    REQUIRE(r.spheres.size() >= 10);
    // Tessellation puts the polygonal tube's medial axis within half a facet of the
    // true axis; the search adds at most its tolerance.
    const double fuzz = R * std::sin(kPi / slices) + r.stats.medial_tolerance;
    for (const Sphere& s : r.spheres.spheres) {
      CHECK(std::hypot(s.center.x(), s.center.y()) <= fuzz);
      CHECK(std::abs(s.center.z()) <= half + fuzz);
      CHECK(s.radius == Approx(R).margin(2 * fuzz));
    }
  }
  SECTION("torus: centres on the core circle") {
    const double R = 1.0, rr = 0.3;
    const int nu = 96, nv = 32;
    const BakeResult r = bake_at(make_torus(R, rr, nu, nv), 32);
    REQUIRE(r.spheres.size() >= 40);
    const double fuzz =
        rr * std::sin(kPi / nv) + R * (1 - std::cos(kPi / nu)) + r.stats.medial_tolerance;
    for (const Sphere& s : r.spheres.spheres) {
      CHECK(std::abs(std::hypot(s.center.x(), s.center.y()) - R) <= fuzz);
      CHECK(std::abs(s.center.z()) <= fuzz);
      CHECK(s.radius == Approx(rr).margin(2 * fuzz));
    }
  }
}

TEST_CASE("sphere count grows with resolution", "[bake]") {
  const TriangleMesh knot =
      load_mesh(std::string(MEDSPHERES_SOURCE_DIR) + "/examples/data/knot1.off").mesh;
  const MeshQuery q(knot);
  std::size_t prev = 0;
  for (int res : {12, 16, 24, 32, 48}) {
    BakeOptions o;
    o.resolution = res;
    const std::size_t n = bake(q, o).spheres.size();
    INFO("resolution " << res);
    CHECK(n > prev);
    prev = n;
  }
}

TEST_CASE("output is bit-identical for every thread count", "[bake]") {
  const TriangleMesh m =
      load_mesh(std::string(MEDSPHERES_SOURCE_DIR) + "/examples/data/eight.off").mesh;
  const BakeResult one = bake_at(m, 40, 1);
  REQUIRE(one.spheres.size() > 10);
  for (int threads : {2, 3, 4}) {
    const BakeResult many = bake_at(m, 40, threads);
    CHECK(bit_identical(one.spheres, many.spheres));
    CHECK(many.stats.closest_point_queries == one.stats.closest_point_queries);
  }
}

TEST_CASE("a sphere budget picks the largest resolution within it", "[bake]") {
  const TriangleMesh m =
      load_mesh(std::string(MEDSPHERES_SOURCE_DIR) + "/examples/data/knot1.off").mesh;
  const MeshQuery q(m);
  for (std::size_t budget : {50u, 200u}) {
    const BakeResult r = bake_max_spheres(q, budget);
    INFO("budget " << budget << ", resolution " << r.stats.resolution);
    CHECK(r.spheres.size() <= budget);
    BakeOptions o;
    o.resolution = r.stats.resolution + 1;
    CHECK(bake(q, o).spheres.size() > budget);
  }
  CHECK_THROWS_AS(bake_max_spheres(q, 0), std::invalid_argument);
}

TEST_CASE("the resolution search stops once doubling adds no sphere", "[bake]") {
  // A ball's medial surface is its centre: low resolutions find it as one sphere, and
  // doubling them finds no more, so the search need not climb to the limit.
  const TriangleMesh m = make_icosphere(1.0, 3);
  const MeshQuery q(m);
  const BakeResult r = bake_max_spheres(q, 500);
  INFO("resolution " << r.stats.resolution << ", spheres " << r.spheres.size());
  CHECK(r.spheres.size() <= 500);
  CHECK(r.stats.resolution < 512);
  BakeOptions half;
  half.resolution = r.stats.resolution / 2;
  CHECK(bake(q, half).spheres.size() >= r.spheres.size());
}

TEST_CASE("an error target the resolution cannot reach stops where doubling stops helping",
          "[bake]") {
  const TriangleMesh m = make_box({1.0, 0.6, 0.3}, 2);
  const MeshQuery q(m);
  int calls = 0;
  const ErrorFn flat = [&](const SphereSet&) {
    ++calls;
    return 1.0;
  };
  try {
    bake_target_error(q, 0.5, flat);
    FAIL("an unreachable target must throw");
  } catch (const Error& e) {
    CHECK_THAT(e.what(), Contains("stopped reducing"));
  }
  // Start 28, one doubling to 56: two distinct resolutions, each measured once.
  CHECK(calls == 2);
}

TEST_CASE("an error target picks the smallest resolution that meets it", "[bake]") {
  const TriangleMesh m = make_box({1.0, 0.6, 0.3}, 2);
  const MeshQuery q(m);
  // A stand-in error with a known trend: 1 / (number of spheres).
  const ErrorFn inverse_count = [](const SphereSet& s) {
    return 1.0 / static_cast<double>(s.size());
  };
  const BakeResult r = bake_target_error(q, 1.0 / 300.0, inverse_count);
  CHECK(inverse_count(r.spheres) <= 1.0 / 300.0);
  BakeOptions o;
  o.resolution = r.stats.resolution - 1;
  CHECK(inverse_count(bake(q, o).spheres) > 1.0 / 300.0);
  CHECK_THROWS_AS(bake_target_error(q, 1e-9, inverse_count, {}, 16), Error);
  CHECK_THROWS_AS(bake_target_error(q, 0.0, inverse_count), std::invalid_argument);
}

TEST_CASE("nonsense options are rejected by name", "[bake]") {
  const TriangleMesh m = make_box({1, 1, 1});
  auto with = [&](auto set) {
    BakeOptions o;
    set(o);
    return o;
  };
  CHECK_THROWS_WITH(bake(m, with([](BakeOptions& o) { o.resolution = 0; })),
                    Contains("resolution"));
  CHECK_THROWS_WITH(bake(m, with([](BakeOptions& o) { o.resolution = -4; })),
                    Contains("resolution"));
  CHECK_THROWS_WITH(bake(m, with([](BakeOptions& o) { o.object_angle = -0.1; })),
                    Contains("object angle"));
  CHECK_THROWS_WITH(bake(m, with([](BakeOptions& o) { o.object_angle = 4.0; })),
                    Contains("object angle"));
  CHECK_THROWS_WITH(bake(m, with([](BakeOptions& o) { o.medial_tolerance = -1; })),
                    Contains("tolerance"));
  CHECK_THROWS_WITH(bake(m, with([](BakeOptions& o) { o.medial_tolerance = std::nan(""); })),
                    Contains("tolerance"));
  CHECK_THROWS_WITH(bake(m, with([](BakeOptions& o) { o.threads = -1; })), Contains("threads"));
}

TEST_CASE("meshes without interior give a clear error", "[bake]") {
  TriangleMesh sheet;  // a flat square
  sheet.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
  CHECK_THROWS_WITH(bake_at(sheet, 16), Contains("no grid vertex lies inside"));

  TriangleMesh soup;  // disjoint random triangles
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 60; ++i) {
    const Eigen::Vector3d c(u(rng), u(rng), u(rng));
    const int b = static_cast<int>(soup.vertices.size());
    for (int k = 0; k < 3; ++k)
      soup.vertices.push_back(c + 0.1 * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    soup.triangles.push_back({b, b + 1, b + 2});
  }
  CHECK_THROWS_AS(bake_at(soup, 16), InputError);
}

#ifdef MEDSPHERES_SHARED_MESHES
TEST_CASE("baked spheres are inside every closed shared mesh", "[bake][shared]") {
  for (const auto& row : test::shared_meshes()) {
    if (!row.closed) continue;
    INFO(row.file);
    const LoadedMesh loaded = load_mesh(row.path);
    const MeshQuery q(loaded.mesh);
    BakeOptions o;
    o.resolution = 24;
    const BakeResult r = bake(q, o);
    REQUIRE(r.spheres.size() > 0);
    for (const Sphere& s : r.spheres.spheres) {
      // MeshQuery is checked against brute force in mesh_query_test; here it serves as
      // the oracle for meshes too large for brute force.
      CHECK(s.radius <= q.closest_point(s.center).distance());
      CHECK(q.winding_number_exact(s.center) > 0.5);
    }
  }
}
#endif
