#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <random>

#include <catch2/catch.hpp>

#include "medspheres/bake/bake.h"
#include "medspheres/bake/dilate.h"
#include "medspheres/error.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "support/point_triangle_oracle.h"
#include "support/shared_meshes.h"
#include "support/temp_dir.h"

using namespace medspheres;
using Catch::Matchers::Contains;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Every sphere lies inside the solid: centre inside (exact winding number), radius at
// most the oracle's distance from the centre to the surface.
void check_internal(const TriangleMesh& m, const BakeResult& r) {
  const MeshQuery q(m);
  REQUIRE(r.spheres.size() > 0);
  REQUIRE(r.samples.size() == r.spheres.size());
  const test::OracleMesh oracle(m);
  for (const Sphere& s : r.spheres.spheres) {
    CHECK(s.radius > 0.0);
    CHECK(s.radius <= oracle.distance(s.center));
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

TriangleMesh translated(TriangleMesh m, const Eigen::Vector3d& offset) {
  for (Eigen::Vector3d& v : m.vertices) v += offset;
  return m;
}

const std::string kKnot = medspheres::test::example_mesh("knot1.off");

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
  const TriangleMesh knot = load_mesh(kKnot).mesh;
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
  const TriangleMesh m = load_mesh(medspheres::test::example_mesh("eight.off")).mesh;
  const BakeResult one = bake_at(m, 40, 1);
  REQUIRE(one.spheres.size() > 10);
  for (int threads : {2, 3, 4}) {
    const BakeResult many = bake_at(m, 40, threads);
    CHECK(bit_identical(one.spheres, many.spheres));
    CHECK(many.stats.closest_point_queries == one.stats.closest_point_queries);
  }
}

TEST_CASE("a sphere budget picks the largest resolution within it", "[bake]") {
  const TriangleMesh m = load_mesh(kKnot).mesh;
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
  } catch (const InputError& e) {
    CHECK(e.kind() == ErrorKind::kUnreachable);
    CHECK(e.field() == "target_error");
    CHECK_THAT(e.what(), Contains("0.5") && Contains("stopped reducing"));
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
  CHECK_THROWS_AS(bake_target_error(q, 1e-9, inverse_count, {}, 16), InputError);
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
                    Contains("object_angle"));
  CHECK_THROWS_WITH(bake(m, with([](BakeOptions& o) { o.object_angle = 4.0; })),
                    Contains("object_angle"));
  CHECK_THROWS_WITH(bake(m, with([](BakeOptions& o) { o.medial_tolerance = -1; })),
                    Contains("tolerance"));
  CHECK_THROWS_WITH(bake(m, with([](BakeOptions& o) { o.medial_tolerance = std::nan(""); })),
                    Contains("tolerance"));
  CHECK_THROWS_WITH(bake(m, with([](BakeOptions& o) { o.threads = -1; })), Contains("threads"));
  // The problem names the field as BakeOptions spells it (the CLI's flags follow it), and
  // the exception says the same.
  CHECK_FALSE(bake_options_problem(BakeOptions{}));
  const auto field_of = [&](auto set) {
    const std::optional<InputError> p = bake_options_problem(with(set));
    REQUIRE(p);
    CHECK(p->kind() == ErrorKind::kOutOfRange);
    CHECK_THROWS_WITH(validate_bake_options(with(set)), p->field() + " " + p->problem());
    return p->field();
  };
  CHECK(field_of([](BakeOptions& o) { o.resolution = 4097; }) == "resolution");
  CHECK(field_of([](BakeOptions& o) { o.object_angle = 0.0; }) == "object_angle");
  CHECK(field_of([](BakeOptions& o) { o.medial_tolerance = -1e-3; }) == "medial_tolerance");
  CHECK(field_of([](BakeOptions& o) { o.threads = kMaxThreads + 1; }) == "threads");
  CHECK_FALSE(medial_tolerance_problem(0.0, 2.0, 10));
  CHECK_FALSE(medial_tolerance_problem(0.1, 2.0, 10));
  CHECK(medial_tolerance_problem(0.2, 2.0, 10)->field() == "medial_tolerance");
  CHECK_THAT(medial_tolerance_problem(0.2, 2.0, 10)->problem(),
             Contains("[2e-09, 0.2)") && Contains("L = 2") && Contains("got 0.2"));
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

TEST_CASE("every sphere is inside meshes far from the origin", "[bake]") {
  // The radius shrink must cover the rounding of the distance at the mesh's coordinates,
  // not only at its size: at an offset of 1e5 that rounding is about 2e-11 L, above the
  // 1e-12 L term alone. The oracle is the 113-bit distance of point_triangle_oracle.h.
  for (const double offset : {0.0, 1e3, 1e5, 1e6}) {
    for (const TriangleMesh& base : {make_torus(1.0, 0.3, 48, 24), make_box({1.0, 0.6, 0.3}, 2),
                                     make_capsule(0.3, 0.8, 24, 6)}) {
      const TriangleMesh m = translated(base, offset * Eigen::Vector3d(1.0, -0.5, 0.25));
      const MeshQuery q(m);
      const BakeResult r = bake(q, BakeOptions{});
      INFO("offset " << offset << ", " << m.triangles.size() << " triangles");
      REQUIRE(r.spheres.size() > 0);
      std::size_t outside = 0;
      const test::OracleMesh oracle(m);
      for (const Sphere& sp : r.spheres.spheres) {
        outside += sp.radius > oracle.distance(sp.center);
        CHECK(q.winding_number_exact(sp.center) > 0.5);
      }
      CHECK(outside == 0);
    }
  }
}

TEST_CASE("medial tolerance: from 1e-9 L to below the cell size, and searches that end", "[bake]") {
  const TriangleMesh m = make_torus(1.0, 0.3, 48, 24);
  const MeshQuery q(m);
  const double L = m.bounds().sizes().maxCoeff();
  auto with = [&](double tolerance, int resolution = 20) {
    BakeOptions o;
    o.resolution = resolution;
    o.medial_tolerance = tolerance;
    return o;
  };
  const double h = L / 20;
  // Out of range: below the rounding scale (halving stops shrinking a bracket at about
  // 1e-15 L, so 1e-18 is never reached), or a cell or more (the bracket then no longer
  // says which cell the medial point is in).
  for (const double bad : {1e-18, 0.99e-9 * L, h, 0.5, 10.0, 1e300}) {
    INFO("tolerance " << bad);
    CHECK_THROWS_WITH(bake(q, with(bad)),
                      Contains("medial_tolerance") && Contains("[") && Contains("cell size"));
  }
  const ToleranceRange range = medial_tolerance_range(L, 20);
  CHECK(range.lo == 1e-9 * L);
  CHECK(range.hi == h);
  // The ends of the range work, and the spheres stay inside.
  for (const double good : {1e-9 * L, 0.99 * h}) {
    INFO("tolerance " << good);
    const BakeResult r = bake(q, with(good));
    CHECK(r.stats.medial_tolerance == good);
    const test::OracleMesh oracle(m);
    for (const Sphere& sp : r.spheres.spheres) CHECK(sp.radius <= oracle.distance(sp.center));
  }
  // The default: 1e-3 L, kept below half a cell.
  CHECK(bake(q, with(0.0, 28)).stats.medial_tolerance == 1e-3 * L);
  // A search must keep the tolerance below the cell of the finest resolution it may bake.
  CHECK_THROWS_WITH(bake_max_spheres(q, 100, with(L / 400)), Contains("medial_tolerance"));
  CHECK_THROWS_WITH(bake_max_spheres(q, 100, with(L / 50), 64), Contains("medial_tolerance"));
  CHECK(bake_max_spheres(q, 100, with(L / 600)).spheres.size() <= 100);
}

TEST_CASE("thread counts are capped at kMaxThreads", "[bake]") {
  // 100000 threads would crash the OpenMP runtime (threads.h): an error instead.
  const TriangleMesh m = make_icosphere(1.0, 2);
  const MeshQuery q(m);
  for (const int threads : {kMaxThreads + 1, 100000, -1}) {
    INFO("threads " << threads);
    BakeOptions o;
    o.threads = threads;
    CHECK_THROWS_WITH(bake(q, o), Contains("threads") && Contains("[0, 1024]"));
    CHECK_THROWS_AS(bake_max_spheres(q, 10, o), std::invalid_argument);
    DilateOptions d;
    d.threads = threads;
    const SphereSet one{{{Eigen::Vector3d::Zero(), 0.9}}};
    CHECK_THROWS_WITH(dilate(q, one, d), Contains("threads") && Contains("[0, 1024]"));
  }
  BakeOptions o;
  o.threads = kMaxThreads;
  CHECK_NOTHROW(validate_bake_options(o));
}

TEST_CASE("a sphere budget: empty bakes are too coarse, and counts are not monotonic", "[bake]") {
  const TriangleMesh m = load_mesh(kKnot).mesh;
  const MeshQuery q(m);
  auto count_at = [&](int resolution) {
    BakeOptions o;
    o.resolution = resolution;
    return bake(q, o).spheres.size();
  };
  // knot1 gives 2 spheres at resolution 3, none at 4 and 5 (and no inside vertex at 2),
  // 14 at 6. An empty bake counts as too coarse, never as an answer within the budget.
  const BakeResult five = bake_max_spheres(q, 5);
  CHECK(five.stats.resolution == 3);
  CHECK(five.spheres.size() == 2);
  // No resolution gives exactly one sphere: an error that says so, with the fewest found.
  CHECK_THROWS_WITH(bake_max_spheres(q, 1), Contains("max_spheres: ") &&
                                                Contains("between 1 and 1 spheres") &&
                                                Contains("fewest found is 2 at resolution 3"));
  // 84 spheres at 13, 112 at 14, exactly 100 at 15: the window above the boundary finds 15.
  const BakeResult hundred = bake_max_spheres(q, 100);
  const int r = hundred.stats.resolution;
  INFO("resolution " << r);
  CHECK(hundred.spheres.size() <= 100);
  CHECK(r >= 15);
  for (int k = 1; k <= kResolutionSearchWindow; ++k) {
    const std::size_t n = count_at(r + k);
    CHECK((n == 0 || n > 100));
  }
  // The search is recorded: every resolution once, the chosen one among them, and the
  // time of the whole search.
  std::vector<int> tried;
  for (const SearchStep& step : hundred.stats.search) tried.push_back(step.resolution);
  CHECK(std::find(tried.begin(), tried.end(), r) != tried.end());
  std::sort(tried.begin(), tried.end());
  CHECK(std::adjacent_find(tried.begin(), tried.end()) == tried.end());
  CHECK(hundred.stats.total_seconds >= hundred.stats.seconds);
  CHECK(hundred.stats.search.size() >= 5);
}

TEST_CASE("an error target: empty bakes never meet it and are never measured", "[bake]") {
  const TriangleMesh m = load_mesh(kKnot).mesh;
  const MeshQuery q(m);
  const FitEvaluator fit(m);
  int empty_calls = 0;
  const ErrorFn nerr = [&](const SphereSet& s) {
    empty_calls += s.empty();
    return fit.volume_error(s.spheres).nerr;  // throws for an empty set
  };
  // Halving from 28 reaches resolutions 2 (no inside vertex) and 5 (no sphere).
  const double target = 0.9;
  const BakeResult r = bake_target_error(q, target, nerr);
  CHECK(empty_calls == 0);
  CHECK(nerr(r.spheres) <= target);
  for (int k = 1; k <= kResolutionSearchWindow && r.stats.resolution - k >= 2; ++k) {
    BakeOptions o;
    o.resolution = r.stats.resolution - k;
    const BakeResult below = [&] {
      try {
        return bake(q, o);
      } catch (const InputError&) {
        return BakeResult{};  // no grid vertex inside: nothing meets the target
      }
    }();
    INFO("resolution " << o.resolution);
    CHECK((below.spheres.empty() || nerr(below.spheres) > target));
  }
  for (const SearchStep& step : r.stats.search)
    if (step.spheres == 0) CHECK(step.error == 1.0);
}

TEST_CASE("spheres of an open mesh stay inside its solid: no ball leaks through a hole", "[bake]") {
  // A box [-1, 1]^3 with its bottom face (z = -1) removed. Its winding-number solid is
  // the box: across the planar hole the level set 1/2 is the hole itself. Without caps
  // the radius of a ball near the hole would be its distance to the walls, and the ball
  // would reach through the bottom.
  TriangleMesh open = make_box(Eigen::Vector3d(1, 1, 1), 4);
  std::vector<std::array<int, 3>> kept;
  for (std::size_t t = 0; t < open.triangles.size(); ++t) {
    bool bottom = true;
    for (int k = 0; k < 3; ++k) bottom = bottom && open.corner(t, k).z() == -1.0;
    if (!bottom) kept.push_back(open.triangles[t]);
  }
  REQUIRE(kept.size() + 32 == open.triangles.size());
  open.triangles = kept;
  BakeOptions options;
  options.resolution = 16;
  const BakeResult r = bake(open, options);
  REQUIRE(r.spheres.size() > 10);
  for (const Sphere& s : r.spheres.spheres) {
    // Inside the closed box: at least r from each of the six face planes.
    for (int axis = 0; axis < 3; ++axis) {
      CHECK(s.center[axis] - s.radius >= -1.0);
      CHECK(s.center[axis] + s.radius <= 1.0);
    }
  }
  // eval measures the same solid: these spheres do not protrude, and a ball reaching
  // through the hole does, by exactly how far it reaches.
  const FitEvaluator fit(open);
  const std::vector<double> p = sphere_protrusions(fit.query(), r.spheres.spheres);
  for (double x : p) CHECK(x <= 0.0);
  const std::vector<double> leak =
      sphere_protrusions(fit.query(), {Sphere{Eigen::Vector3d(0.1, 0.2, -0.5), 0.75}});
  CHECK(leak[0] == Approx(0.25).margin(1e-12));
}
