// The covering bake's volume stage, its element refinement and the protrusion stage's
// restarts, against independent oracles:
// the exact union volume (measure_union), a direct check that every element lies in the
// ball that owns it, and the sampled gap of cover_solids.h as a check of coverage.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "../src/cover/cover_elements.h"
#include "../src/cover/cover_flow.h"
#include "../src/cover/cover_polish.h"
#include "../src/cover/cover_protrusion.h"
#include "medspheres/cover/cover.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/measure/union_volume.h"
#include "medspheres/mesh/mesh_generators.h"
#include "support/cover_solids.h"

using namespace medspheres;
using detail::Clustering;
using detail::Elements;

namespace {

// Every element lies in the ball that owns it: its points within the radius.
bool all_held(const Elements& e, const Clustering& c) {
  for (std::size_t i = 0; i < e.size(); ++i) {
    const Sphere& b = c.balls[static_cast<std::size_t>(c.owner[i])];
    for (int p : e.items[i])
      if ((e.points[static_cast<std::size_t>(p)] - b.center).norm() > b.radius) return false;
  }
  return true;
}

// A loose cover of \p e by \p k balls: centres spread along the solid's box diagonal, each
// element to the nearest, each ball 1.2 times as large as its elements need (a centre
// nearest none is dropped).
Clustering loose_cover(const Elements& e, const Eigen::AlignedBox3d& box, std::size_t k) {
  Clustering c;
  for (std::size_t j = 0; j < k; ++j) {
    const double t = (static_cast<double>(j) + 0.5) / static_cast<double>(k);
    c.balls.push_back({box.min() + t * (box.max() - box.min()), 0.0});
  }
  detail::assign(e, c.balls, c.owner, 1);
  detail::hold_members(e, c);
  for (Sphere& b : c.balls) b.radius *= 1.2;
  detail::drop_empty(c);  // a centre nearest no element
  return c;
}

double surface_area(const Elements& e) {
  double a = 0.0;
  for (std::size_t i = 0; i < e.surface; ++i) a += e.weight[i];
  return a;
}

}  // namespace

TEST_CASE("volume flow: a loose cover's union falls, every element held after", "[cover][flow]") {
  for (const test::NamedSolid& solid : test::cover_solids()) {
    CAPTURE(solid.name);
    const MeshQuery query(solid.mesh);
    const Elements e = detail::make_elements(query, 8, 12, 1);
    Clustering c = loose_cover(e, solid.mesh.bounds(), 8);
    REQUIRE(all_held(e, c));
    const double before = measure_union(c.balls).volume;
    detail::FlowOptions o;
    o.threads = 1;
    c.balls = detail::volume_flow(query, e, c.balls, o);
    for (const Sphere& b : c.balls) REQUIRE(b.center.allFinite());
    detail::hold_all(e, c, 1);
    detail::shrink(e, c);
    detail::drop_empty(c);  // as the volume stage does: a ball left with nothing goes
    CHECK(all_held(e, c));
    CHECK(test::sampled_gap(solid.mesh, c.balls) == 0.0);
    // The loose start leaves room on every solid: a fifth of the union at least.
    CHECK(measure_union(c.balls).volume < 0.8 * before);
  }
}

TEST_CASE("volume flow: the same balls for every thread count", "[cover][flow][threads]") {
  const TriangleMesh torus = make_torus(1.0, 0.3, 32, 12);
  const MeshQuery query(torus);
  const Elements e = detail::make_elements(query, 12, 12, 1);
  const Clustering c = loose_cover(e, torus.bounds(), 12);
  detail::FlowOptions one, two;
  one.threads = 1;
  two.threads = 2;
  one.cap = two.cap = 0.2;
  test::check_same_spheres(detail::volume_flow(query, e, c.balls, one),
                           detail::volume_flow(query, e, c.balls, two));
}

TEST_CASE("refine_binding: balls only shrink, the elements stay held, the area stays",
          "[cover][flow]") {
  // Two balls over a box, the second larger and reaching into the first's half: the first
  // keeps only the elements the second does not hold whole, and its radius is bound by
  // elements that straddle the second's sphere. Their pieces that the second holds leave,
  // so the first shrinks.
  const TriangleMesh box = make_box(Eigen::Vector3d(1.0, 0.5, 0.5), 2);
  const MeshQuery query(box);
  Elements e = detail::make_elements(query, 2, 0, 1);
  const double area = surface_area(e);
  Clustering c;
  c.balls = {{Eigen::Vector3d(-0.8, 0.0, 0.0), 0.0}, {Eigen::Vector3d(0.2, 0.0, 0.0), 0.0}};
  detail::assign(e, c.balls, c.owner, 1);
  detail::hold_members(e, c);
  detail::shrink(e, c);
  REQUIRE(all_held(e, c));
  const std::vector<Sphere> before = c.balls;
  const std::size_t elements = e.size();
  detail::refine_binding(e, c, 3);
  CHECK(all_held(e, c));
  CHECK(e.size() > elements);
  CHECK(surface_area(e) == Approx(area).epsilon(1e-12));
  for (std::size_t j = 0; j < c.balls.size(); ++j) {
    CHECK(c.balls[j].center == before[j].center);
    CHECK(c.balls[j].radius <= before[j].radius);
  }
  CHECK(c.balls[0].radius + c.balls[1].radius < before[0].radius + before[1].radius);
  CHECK(measure_union(c.balls).volume <= measure_union(before).volume);
  CHECK(test::sampled_gap(box, c.balls) == 0.0);
}

TEST_CASE("elements of a dense mesh: adjacent triangles in pairs, refined and certified",
          "[cover][flow]") {
  // 86,400 triangles, more than twice the elements the bake needs: the triangles go in pairs, each
  // element two triangles of the mesh (abc and abd) or one, every triangle in exactly one.
  const TriangleMesh torus = make_torus(1.0, 0.3, 360, 120);
  const MeshQuery query(torus);
  Elements e = detail::make_elements(query, 16, 0, 1);
  REQUIRE(e.surface == e.size());
  CHECK(e.surface < torus.num_triangles() * 3 / 5);
  auto sorted = [](std::array<int, 3> t) {
    std::sort(t.begin(), t.end());
    return t;
  };
  std::vector<std::array<int, 3>> from_elements, from_mesh;
  double mesh_area = 0.0;
  for (std::size_t t = 0; t < torus.num_triangles(); ++t) {
    from_mesh.push_back(sorted(torus.triangles[t]));
    mesh_area += 0.5 * (torus.corner(t, 1) - torus.corner(t, 0))
                           .cross(torus.corner(t, 2) - torus.corner(t, 0))
                           .norm();
  }
  for (std::size_t i = 0; i < e.surface; ++i) {
    const std::array<int, 4>& q = e.items[i];
    from_elements.push_back(sorted({q[0], q[1], q[2]}));
    if (detail::paired(e, i)) from_elements.push_back(sorted({q[0], q[1], q[3]}));
  }
  std::sort(from_elements.begin(), from_elements.end());
  std::sort(from_mesh.begin(), from_mesh.end());
  CHECK(from_elements == from_mesh);
  CHECK(surface_area(e) == Approx(mesh_area).epsilon(1e-12));
  // The refinement splits binding pairs into triangles and pieces, every element held.
  Clustering c = loose_cover(e, torus.bounds(), 8);
  detail::shrink(e, c);
  const std::vector<Sphere> before = c.balls;
  detail::refine_binding(e, c, 3);
  CHECK(all_held(e, c));
  CHECK(surface_area(e) == Approx(mesh_area).epsilon(1e-12));
  for (std::size_t j = 0; j < c.balls.size(); ++j) CHECK(c.balls[j].radius <= before[j].radius);
  const CoverResult cover = bake_cover(query, 8);
  CHECK(cover.stats.certified);
  CHECK(cover.spheres.spheres.size() <= 8);
  CHECK(test::sampled_gap(torus, cover.spheres.spheres) == 0.0);
}

TEST_CASE("reach_from: the largest distance plus radius, bit for bit, over points and balls",
          "[cover]") {
  // The oracle is the definition, max over atoms of |a - c| + r_a, one root per atom; the
  // bake's version takes one root for all the points. Seeded atoms of mixed kinds and scales,
  // ties included (the same point twice, points on one sphere about c).
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::ldexp(1.0, trial % 40 - 20);
    const Eigen::Vector3d c(u(rng) * scale, u(rng) * scale, u(rng) * scale);
    std::vector<Sphere> atoms;
    const int n = 1 + trial % 37;
    for (int a = 0; a < n; ++a) {
      const Eigen::Vector3d p(u(rng) * scale, u(rng) * scale, u(rng) * scale);
      const int kind = (trial + a) % 4;  // points, balls, a repeat, a point on c's sphere
      if (kind == 0 || (trial % 3 == 0 && kind != 2)) atoms.push_back({p, 0.0});
      if (kind == 1) atoms.push_back({p, 0.5 * (u(rng) + 1.0) * scale});
      if (kind == 2 && !atoms.empty()) atoms.push_back(atoms.back());
      if (kind == 3) atoms.push_back({c + (p - c).normalized() * scale, 0.0});
    }
    if (atoms.empty()) continue;
    double expected = 0.0;
    for (const Sphere& a : atoms) expected = std::max(expected, (a.center - c).norm() + a.radius);
    INFO("trial " << trial);
    CHECK(detail::reach_from(atoms, c) == expected);
    ++checked;
  }
  CHECK(checked > 1900);
}

TEST_CASE("bake_cover rejects a protrusion allowance that is negative or not finite", "[cover]") {
  const MeshQuery query(make_icosphere(1.0, 1));
  for (double a :
       {-0.1, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    CoverOptions o;
    o.protrusion_allowance = a;
    CHECK_THROWS_AS(bake_cover(query, 4, o), std::invalid_argument);
  }
}

TEST_CASE("volume polish: a lone ball goes to the box's centre, half its diagonal the radius",
          "[cover][polish]") {
  // Closed form: with no other ball, the union is the ball, so the polish lowers its radius
  // alone: the least ball holding the box's surface is centred at the centre, of radius half
  // the diagonal. The search's last step is 1e-3 of the radius, so it ends within a few of
  // those of it. Its protrusion there, half the diagonal less half the thinnest side, is below
  // the start's, which is the cap.
  const Eigen::Vector3d half(1.0, 0.6, 0.3);
  const TriangleMesh box = make_box(half, 2);
  const MeshQuery query(box);
  const Elements e = detail::make_elements(query, 1, 0, 1);
  Clustering c;
  c.balls = {{Eigen::Vector3d(0.07, -0.04, 0.02), 0.0}};
  c.owner.assign(e.size(), 0);
  detail::hold_members(e, c);
  const double cap = sphere_protrusions(query, c.balls, 1)[0];
  const double half_diagonal = half.norm();
  REQUIRE(c.balls[0].radius > 1.02 * half_diagonal);
  const Clustering p = detail::volume_polish(query, e, c, cap, 10, 1);
  REQUIRE(p.balls.size() == 1);
  CHECK(all_held(e, p));
  CHECK(p.balls[0].radius >= half_diagonal);
  CHECK(p.balls[0].radius <= (1.0 + 5e-3) * half_diagonal);
  CHECK(p.balls[0].center.norm() <= 5e-3 * half_diagonal);
  CHECK(sphere_protrusions(query, p.balls, 1)[0] <= cap);
}

TEST_CASE("volume polish: the union falls, every element held, no ball beyond the cap",
          "[cover][polish]") {
  // Oracles: the exact union (measure_union), a direct check that every element lies in the
  // ball that owns it, the protrusions of fit_metrics and the sampled gap.
  for (const test::NamedSolid& solid : test::cover_solids()) {
    CAPTURE(solid.name);
    const MeshQuery query(solid.mesh);
    const double L = solid.mesh.bounds().sizes().maxCoeff();
    const Elements e = detail::make_elements(query, 8, 12, 1);
    Clustering c = loose_cover(e, solid.mesh.bounds(), 8);
    detail::shrink(e, c);
    detail::drop_empty(c);
    const std::vector<double> start = sphere_protrusions(query, c.balls, 1);
    const double cap = *std::max_element(start.begin(), start.end());
    const Clustering p = detail::volume_polish(query, e, c, cap, 3, 2);
    CHECK(all_held(e, p));
    CHECK(test::sampled_gap(solid.mesh, p.balls) == 0.0);
    for (double q : sphere_protrusions(query, p.balls, 1)) CHECK(q <= cap + 1e-12 * L);
    CHECK(measure_union(p.balls).volume < measure_union(c.balls).volume);
  }
}

TEST_CASE("volume polish: the same balls for every thread count", "[cover][polish][threads]") {
  const TriangleMesh torus = make_torus(1.0, 0.3, 32, 12);
  const MeshQuery query(torus);
  const Elements e = detail::make_elements(query, 16, 12, 1);
  Clustering c = loose_cover(e, torus.bounds(), 16);
  detail::shrink(e, c);
  detail::drop_empty(c);
  const std::vector<double> q = sphere_protrusions(query, c.balls, 1);
  const double cap = *std::max_element(q.begin(), q.end());
  const Clustering one = detail::volume_polish(query, e, c, cap, 2, 1);
  for (int threads : {2, 3}) {
    const Clustering more = detail::volume_polish(query, e, c, cap, 2, threads);
    test::check_same_spheres(one.balls, more.balls);
    CHECK(one.owner == more.owner);
  }
}

TEST_CASE("protrusion restarts: P never rises, every element held, the same for any thread count",
          "[cover]") {
  for (const test::NamedSolid& solid : test::cover_solids()) {
    CAPTURE(solid.name);
    const MeshQuery query(solid.mesh);
    const std::size_t k = 4;
    const Elements e = detail::make_elements(query, k, 12, 1);
    const Elements fine = detail::make_patches(e, k, 4000.0, solid.mesh.bounds().min());
    const std::optional<double> volume = solid_volume(solid.mesh);
    const detail::ProtrusionStage none =
        detail::protrusion_stage(query, e, fine, k, 8, volume, 1, {}, 0);
    const detail::ProtrusionStage six =
        detail::protrusion_stage(query, e, fine, k, 8, volume, 1, {}, 6);
    CHECK(six.clustering.balls.size() <= k);
    CHECK(all_held(e, six.clustering));
    CHECK(detail::largest_protrusion(query, six.clustering.balls, 1) <=
          detail::largest_protrusion(query, none.clustering.balls, 1));
    CHECK(six.rounds > none.rounds);
    // The whole bake with restarts: certified, and the same spheres with 1 and 2 threads.
    CoverOptions o;
    o.protrusion_restarts = 3;
    o.threads = 1;
    const CoverResult one = bake_cover(query, k, o);
    o.threads = 2;
    const CoverResult two = bake_cover(query, k, o);
    CHECK(one.stats.certified);
    CHECK(test::sampled_gap(solid.mesh, one.spheres.spheres) == 0.0);
    test::check_same_spheres(one.spheres.spheres, two.spheres.spheres);
  }
}

TEST_CASE("bake_cover rejects a negative number of protrusion restarts or balancing rounds",
          "[cover]") {
  const MeshQuery query(make_icosphere(1.0, 1));
  CoverOptions o;
  o.protrusion_restarts = -1;
  CHECK_THROWS_WITH(bake_cover(query, 4, o), Catch::Contains("protrusion_restarts"));
  o = CoverOptions{};
  o.balance_rounds = -1;
  CHECK_THROWS_WITH(bake_cover(query, 4, o), Catch::Contains("balance_rounds"));
}

namespace {

// K balls on the axis circle (radius \p major, about z) of a torus, one per slice of K equal
// angles, each holding the triangles whose centroids lie in its slice: the layout of a
// tube's cover, built without the bake.
std::vector<Sphere> ring_cover(const TriangleMesh& torus, double major, std::size_t k) {
  const double kTwoPi = 2.0 * std::acos(-1.0), slice = kTwoPi / static_cast<double>(k);
  std::vector<Sphere> balls;
  for (std::size_t j = 0; j < k; ++j) {
    const double u = slice * (static_cast<double>(j) + 0.5);
    balls.push_back({Eigen::Vector3d(major * std::cos(u), major * std::sin(u), 0.0), 0.0});
  }
  for (std::size_t t = 0; t < torus.num_triangles(); ++t) {
    const Eigen::Vector3d g = (torus.corner(t, 0) + torus.corner(t, 1) + torus.corner(t, 2)) / 3.0;
    const double u = std::fmod(std::atan2(g.y(), g.x()) + kTwoPi, kTwoPi);
    Sphere& b = balls[std::min(k - 1, static_cast<std::size_t>(u / slice))];
    for (int c = 0; c < 3; ++c)
      b.radius = std::max(b.radius, (torus.corner(t, c) - b.center).norm());
  }
  return balls;
}

}  // namespace

// Without balancing the rounds stall at 1.45 times the ring's P (balls of unequal
// protrusion side by side along the tube); with them, 1.06 times.
TEST_CASE(
    "balancing rounds: a torus's protrusion stage near a ring of balls on its axis, the "
    "same for any thread count",
    "[cover]") {
  const TriangleMesh torus = make_torus(1.0, 0.25, 64, 16);
  const MeshQuery query(torus);
  const std::size_t k = 16;
  const Elements e = detail::make_elements(query, k, 12, 1);
  const Elements fine = detail::make_patches(e, k, 4000.0, torus.bounds().min());
  const std::optional<double> volume = solid_volume(torus);
  const std::vector<double> ring = sphere_protrusions(query, ring_cover(torus, 1.0, k), 1);
  const double ring_p = *std::max_element(ring.begin(), ring.end());
  const detail::ProtrusionStage plain =
      detail::protrusion_stage(query, e, fine, k, 8, volume, 1, {}, 0, 0);
  const detail::ProtrusionStage balanced =
      detail::protrusion_stage(query, e, fine, k, 8, volume, 1, {}, 0, 40);
  const double plain_p = detail::largest_protrusion(query, plain.clustering.balls, 1);
  const double balanced_p = detail::largest_protrusion(query, balanced.clustering.balls, 1);
  CHECK(balanced.clustering.balls.size() <= k);
  CHECK(all_held(e, balanced.clustering));
  CHECK(balanced_p <= plain_p);
  CHECK(balanced_p <= 1.1 * ring_p);
  const detail::ProtrusionStage two =
      detail::protrusion_stage(query, e, fine, k, 8, volume, 2, {}, 0, 40);
  test::check_same_spheres(balanced.clustering.balls, two.clustering.balls);
}
