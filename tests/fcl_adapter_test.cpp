// medspheres::fcl: the geometry, sphere set against sphere set against brute force through
// FCL's own fcl::Sphere narrowphase, FCL's result conventions, the libfcl guard, pairs
// without a sphere set, and many threads.

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/fcl/sphere_set_geometry.h"
#include "support/fcl_fixtures.h"
#include "support/sphere_fixtures.h"
#include "support/sphere_scenes.h"
#include "support/tolerance_tally.h"

using medspheres::Sphere;
using medspheres::SphereSet;
using medspheres::fcl::SphereSetGeometry;
namespace mt = medspheres::test;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

struct Scene {
  SphereSet a, b;
  std::shared_ptr<SphereSetGeometry> ga, gb;
  fcl::Transform3d X_WA, X_WB;
};

// Sphere sets and sheets (B always a set) at poses up to 2.4 apart; every third A on a
// ball tree.
std::vector<Scene> random_scenes(unsigned seed, int count) {
  mt::SceneMix mix;
  mix.max_spheres = 80;
  mix.sheet_a_period = 2;
  mix.sheet_b_period = 0;
  mix.spread_step = 0.4;
  mix.spread_cycle = 6;
  std::vector<Scene> out;
  int k = 0;
  for (const mt::SetPairScene& p : mt::random_set_pairs(seed, count, mix)) {
    Scene s{p.a, p.b, nullptr, nullptr, p.X_WA, p.X_WB};
    medspheres::SphereTreeOptions options;
    options.kind =
        (k++ % 3 == 0) ? medspheres::BoundingVolumeKind::ball : medspheres::BoundingVolumeKind::rss;
    s.ga = std::make_shared<SphereSetGeometry>(s.a, options);
    s.gb = std::make_shared<SphereSetGeometry>(s.b);
    out.push_back(s);
  }
  return out;
}

double tolerance(const Scene& s) {
  return 1e-12 * (4 + s.X_WA.translation().norm() + s.X_WB.translation().norm());
}

// Brute force through FCL: fcl::Sphere against fcl::Sphere for every pair.
struct Brute {
  double min_signed = std::numeric_limits<double>::infinity();
  std::size_t i = 0, j = 0;
  std::map<std::pair<int, int>, mt::FclAnswer> colliding;
};

Brute brute(const Scene& s) {
  Brute out;
  for (std::size_t i = 0; i < s.a.size(); ++i) {
    for (std::size_t j = 0; j < s.b.size(); ++j) {
      const fcl::Sphered sb(s.b.spheres[j].radius);
      const mt::FclAnswer ans = mt::fcl_sphere_answer(s.a.spheres[i], s.X_WA, &sb,
                                                      mt::sphere_pose(s.b.spheres[j], s.X_WB));
      if (ans.collides) out.colliding[{static_cast<int>(i), static_cast<int>(j)}] = ans;
      if (ans.signed_distance() < out.min_signed) {
        out.min_signed = ans.signed_distance();
        out.i = i;
        out.j = j;
      }
    }
  }
  return out;
}

}  // namespace

TEST_CASE("SphereSetGeometry: construction, identity and the guard box", "[fcl]") {
  CHECK_THROWS_AS(SphereSetGeometry(SphereSet{}), std::invalid_argument);
  SphereSet bad;
  bad.spheres.push_back({Eigen::Vector3d(0, 0, 0), 0.0});
  CHECK_THROWS_AS(SphereSetGeometry(bad), medspheres::InputError);
  std::mt19937 rng(1);
  const SphereSet set = mt::random_sheet_set(rng, 50);
  const SphereSetGeometry g(set);
  CHECK(g.sphere_set().size() == 50);
  CHECK(g.tree().num_spheres() == 50);
  CHECK(medspheres::fcl::as_sphere_set(&g) == &g);
  const fcl::Boxd box(1, 1, 1);
  CHECK(medspheres::fcl::as_sphere_set(&box) == nullptr);
  CHECK(medspheres::fcl::as_sphere_set(nullptr) == nullptr);
  // What libfcl sees: a box centred on the set's origin containing every sphere.
  CHECK(g.getNodeType() == fcl::GEOM_BOX);
  CHECK(g.getObjectType() == fcl::OT_GEOM);
  for (const Sphere& s : set.spheres)
    for (int k = 0; k < 3; ++k) CHECK(std::abs(s.center[k]) + s.radius <= 0.5 * g.side[k]);
  // Tight: some sphere touches each pair of faces, to rounding.
  for (int k = 0; k < 3; ++k) {
    double need = 0.0;
    for (const Sphere& s : set.spheres) need = std::max(need, std::abs(s.center[k]) + s.radius);
    CHECK(0.5 * g.side[k] <= need * (1 + 1e-13));
  }
  CHECK_THROWS_AS(g.computeVolume(), std::logic_error);
  CHECK_THROWS_AS(g.computeCOM(), std::logic_error);
  CHECK_THROWS_AS(g.computeMomentofInertia(), std::logic_error);
  // Far out: |coordinate| + radius is finite (validate_sphere_set accepts it) but twice it
  // is not. The side is then the largest finite double, never infinite.
  const double big = 0.75 * std::numeric_limits<double>::max();
  SphereSet far;
  far.spheres = {{Eigen::Vector3d(big, 0, 0), 1.0}, {Eigen::Vector3d(0, -2, 0), 1.0}};
  const SphereSetGeometry gf(far);
  CHECK(gf.side.allFinite());
  CHECK(gf.side.x() == std::numeric_limits<double>::max());
  CHECK(0.5 * gf.side.y() >= 3.0);
  CHECK(0.5 * gf.side.z() >= 1.0);
}

TEST_CASE("SphereSetGeometry: computeLocalAABB is correct for rotated objects", "[fcl]") {
  std::mt19937 rng(2);
  for (int k = 0; k < 50; ++k) {
    SphereSet set = mt::random_sphere_set(rng, 1 + rng() % 40, 1.0, 0.01, 0.5);
    for (Sphere& s : set.spheres) s.center += Eigen::Vector3d(3, -2, 1);  // off the origin
    auto g = std::make_shared<SphereSetGeometry>(set);
    const fcl::Transform3d X = (k == 0) ? fcl::Transform3d::Identity() : mt::random_pose(rng, 5.0);
    const fcl::CollisionObjectd obj(g, X);
    // Definitions: aabb_local is the spheres' box, aabb_center its centre, aabb_radius the
    // smallest radius about it that holds every sphere.
    CHECK(g->aabb_local.min_ == set.bounds().min());
    CHECK(g->aabb_local.max_ == set.bounds().max());
    CHECK(g->aabb_center == g->aabb_local.center());
    double need = 0.0;
    for (const Sphere& s : set.spheres)
      need = std::max(need, (s.center - g->aabb_center).norm() + s.radius);
    CHECK(g->aabb_radius >= need);
    CHECK(g->aabb_radius <= need * (1 + 1e-12));
    // The world box of the object contains every sphere at this pose.
    const fcl::AABBd& box = obj.getAABB();
    for (const Sphere& s : set.spheres) {
      const Eigen::Vector3d c = X * s.center;
      const double tol = 1e-12 * (1 + c.norm());
      CHECK((c.array() - s.radius >= box.min_.array() - tol).all());
      CHECK((c.array() + s.radius <= box.max_.array() + tol).all());
    }
  }
}

TEST_CASE("SphereSetGeometry nodes use fcl::RSS's corner convention", "[fcl]") {
  std::mt19937 rng(3);
  const SphereSet set = mt::random_sheet_set(rng, 200);
  const SphereSetGeometry g(set);
  const medspheres::SphereTree& tree = g.tree();
  for (std::size_t node = 0; node < tree.num_nodes(); ++node) {
    const medspheres::Rss rss = tree.rss(node);
    fcl::RSSd f;
    f.axis = rss.axis;
    f.To = rss.corner;
    f.l[0] = rss.length[0];
    f.l[1] = rss.length[1];
    f.r = rss.radius;
    CHECK((f.center() - rss.center()).norm() <= 1e-12);
    CHECK(f.width() == Approx(rss.length[0] + 2 * rss.radius));
    // fcl::RSS::contain misjudges points whose rectangle coordinate is exactly 0 or l
    // (its branches use strict inequalities), so test points a hair inside instead.
    for (std::size_t i : tree.spheres_below(node)) {
      const Eigen::Vector3d c = set.spheres[i].center;
      CHECK(f.contain(c + 1e-9 * (rss.center() - c)));
    }
  }
}

TEST_CASE("Sphere set against sphere set matches FCL's sphere narrowphase", "[fcl]") {
  int separated = 0, colliding = 0;
  for (const Scene& s : random_scenes(11, 60)) {
    const Brute b = brute(s);
    const double tol = tolerance(s);
    const fcl::CollisionObjectd oa(s.ga, s.X_WA), ob(s.gb, s.X_WB);

    // Signed distance: minus the deepest penetration, with the two deepest points.
    fcl::DistanceRequestd req(true, true);
    fcl::DistanceResultd res;
    const double d = medspheres::fcl::distance(&oa, &ob, req, res);
    CHECK(d == res.min_distance);
    CHECK(d == Approx(b.min_signed).margin(1e-9));
    CHECK(res.o1 == s.ga.get());
    CHECK(res.o2 == s.gb.get());
    const Sphere& sa = s.a.spheres[static_cast<std::size_t>(res.b1)];
    const Sphere& sb = s.b.spheres[static_cast<std::size_t>(res.b2)];
    const Eigen::Vector3d ca = s.X_WA * sa.center, cb = s.X_WB * sb.center;
    CHECK((cb - ca).norm() - sa.radius - sb.radius == Approx(b.min_signed).margin(1e-9));
    const Eigen::Vector3d n = (cb - ca).normalized();
    CHECK((res.nearest_points[0] - (ca + sa.radius * n)).norm() <= tol);
    CHECK((res.nearest_points[1] - (cb - sb.radius * n)).norm() <= tol);

    // Unsigned distance and collision.
    fcl::DistanceRequestd ureq(true);
    fcl::DistanceResultd ures;
    medspheres::fcl::distance(s.ga.get(), s.X_WA, s.gb.get(), s.X_WB, ureq, ures);
    fcl::CollisionRequestd creq(1u << 20, true);
    fcl::CollisionResultd cres;
    const std::size_t n_contacts = medspheres::fcl::collide(&oa, &ob, creq, cres);
    CHECK(n_contacts == cres.numContacts());
    CHECK(n_contacts == b.colliding.size());
    if (b.min_signed > 0) {
      ++separated;
      CHECK(ures.min_distance == Approx(b.min_signed).margin(1e-9));
      // FCL's own sphere-sphere nearest points for the closest pair.
      const fcl::Sphered s1(s.a.spheres[b.i].radius), s2(s.b.spheres[b.j].radius);
      const mt::FclAnswer ans = mt::fcl_sphere_answer(s.a.spheres[b.i], s.X_WA, &s2,
                                                      mt::sphere_pose(s.b.spheres[b.j], s.X_WB));
      CHECK((ures.nearest_points[0] - ans.p_sphere).norm() <= 1e-9);
      CHECK((ures.nearest_points[1] - ans.p_other).norm() <= 1e-9);
      CHECK(ures.b1 == static_cast<intptr_t>(b.i));
      CHECK(ures.b2 == static_cast<intptr_t>(b.j));
    } else {
      ++colliding;
      CHECK(ures.min_distance <= 0.0);
      CHECK(ures.min_distance >= b.min_signed - 1e-9);
    }
    // Every contact is one of FCL's colliding pairs, with FCL's depth and normal.
    std::set<std::pair<int, int>> seen;
    for (std::size_t k = 0; k < cres.numContacts(); ++k) {
      const fcl::Contactd& c = cres.getContact(k);
      CHECK(c.o1 == s.ga.get());
      CHECK(c.o2 == s.gb.get());
      const auto it = b.colliding.find({static_cast<int>(c.b1), static_cast<int>(c.b2)});
      REQUIRE(it != b.colliding.end());
      CHECK(seen.insert(it->first).second);
      CHECK(c.penetration_depth == Approx(it->second.depth).margin(1e-9));
      if (it->second.normal.norm() > 0.5) CHECK((c.normal - it->second.normal).norm() <= 1e-9);
    }
  }
  CHECK(separated > 15);
  CHECK(colliding > 15);
}

TEST_CASE("Sphere set pairs: touching is a collision, as in FCL", "[fcl]") {
  SphereSet a, b;
  a.spheres.push_back({Eigen::Vector3d(0, 0, 0), 1.0});
  b.spheres.push_back({Eigen::Vector3d(0, 0, 0), 0.5});
  auto ga = std::make_shared<SphereSetGeometry>(a);
  auto gb = std::make_shared<SphereSetGeometry>(b);
  fcl::Transform3d X_WB = fcl::Transform3d::Identity();
  X_WB.translation() = Eigen::Vector3d(0, 1.5, 0);
  const fcl::Transform3d I = fcl::Transform3d::Identity();
  fcl::CollisionRequestd creq(4, true);
  fcl::CollisionResultd cres;
  CHECK(medspheres::fcl::collide(ga.get(), I, gb.get(), X_WB, creq, cres) == 1);
  CHECK(cres.getContact(0).penetration_depth == 0.0);
  CHECK(cres.getContact(0).normal == Eigen::Vector3d(0, 1, 0));
  // FCL agrees.
  const fcl::Sphered s1(1.0), s2(0.5);
  fcl::CollisionResultd fres;
  CHECK(fcl::collide(&s1, I, &s2, X_WB, creq, fres) == 1);
  fcl::DistanceRequestd dreq(true);
  fcl::DistanceResultd dres;
  CHECK(medspheres::fcl::distance(ga.get(), I, gb.get(), X_WB, dreq, dres) == 0.0);
  X_WB.translation().y() = 1.5 + std::ldexp(1.0, -30);
  cres.clear();
  CHECK(medspheres::fcl::collide(ga.get(), I, gb.get(), X_WB, creq, cres) == 0);
}

TEST_CASE("Sphere set pairs are symmetric under swapping", "[fcl]") {
  for (const Scene& s : random_scenes(12, 40)) {
    fcl::DistanceRequestd req(true, true);
    fcl::DistanceResultd ab, ba;
    medspheres::fcl::distance(s.ga.get(), s.X_WA, s.gb.get(), s.X_WB, req, ab);
    medspheres::fcl::distance(s.gb.get(), s.X_WB, s.ga.get(), s.X_WA, req, ba);
    const double tol = tolerance(s);
    CHECK(ab.min_distance == Approx(ba.min_distance).margin(tol));
    CHECK(ab.b1 == ba.b2);
    CHECK(ab.b2 == ba.b1);
    CHECK((ab.nearest_points[0] - ba.nearest_points[1]).norm() <= tol);
    CHECK((ab.nearest_points[1] - ba.nearest_points[0]).norm() <= tol);
    fcl::CollisionRequestd creq(1u << 20, true);
    fcl::CollisionResultd cab, cba;
    medspheres::fcl::collide(s.ga.get(), s.X_WA, s.gb.get(), s.X_WB, creq, cab);
    medspheres::fcl::collide(s.gb.get(), s.X_WB, s.ga.get(), s.X_WA, creq, cba);
    REQUIRE(cab.numContacts() == cba.numContacts());
    std::map<std::pair<intptr_t, intptr_t>, fcl::Contactd> by_pair;
    for (std::size_t k = 0; k < cab.numContacts(); ++k)
      by_pair[{cab.getContact(k).b1, cab.getContact(k).b2}] = cab.getContact(k);
    for (std::size_t k = 0; k < cba.numContacts(); ++k) {
      const fcl::Contactd& c = cba.getContact(k);
      const fcl::Contactd& m = by_pair.at({c.b2, c.b1});
      CHECK(c.penetration_depth == Approx(m.penetration_depth).margin(tol));
      CHECK((c.normal + m.normal).norm() <= 1e-9);  // from o1 to o2: opposite
      CHECK((c.pos - m.pos).norm() <= tol);
    }
  }
}

TEST_CASE("abs_err and rel_err prune sphere set pairs within FCL's guarantee", "[fcl]") {
  // Over seeded scenes apart: with both tolerances binding, some answers exceed the exact
  // minimum d*; every answer keeps d* <= d <= min(d* + abs_err, (1 + rel_err) d*) and is
  // the value of the pair it reports; one tolerance alone leaves the answer exact (FCL's
  // rule then prunes as with none).
  const std::vector<mt::ToleranceMode>& modes = mt::kToleranceModes;
  mt::ToleranceTally tally;
  for (const Scene& s : random_scenes(18, 80)) {
    const double exact = brute(s).min_signed;
    if (exact <= 1e-6) continue;
    tally.add_scene();
    const double tol = 1e-9;
    for (std::size_t m = 0; m < modes.size(); ++m) {
      INFO(modes[m].name);
      const double abs_err = modes[m].abs_err_for(exact);
      for (bool is_signed : {false, true}) {
        fcl::DistanceRequestd req(true, is_signed, modes[m].rel_err, abs_err);
        fcl::DistanceResultd res;
        const double d =
            medspheres::fcl::distance(s.ga.get(), s.X_WA, s.gb.get(), s.X_WB, req, res);
        tally.check(m, d, exact, abs_err, tol, !is_signed);
        REQUIRE(res.b1 >= 0);
        REQUIRE(res.b2 >= 0);
        CHECK(mt::pair_signed_distance(s.a.spheres[static_cast<std::size_t>(res.b1)], s.X_WA,
                                       s.b.spheres[static_cast<std::size_t>(res.b2)],
                                       s.X_WB) == Approx(d).margin(tol));
      }
    }
  }
  tally.check_totals(20);
}

TEST_CASE("medspheres::fcl follows FCL's request and result conventions", "[fcl]") {
  std::mt19937 rng(13);
  SphereSet a = mt::random_sphere_set(rng, 40, 0.5, 0.1, 0.3);
  SphereSet b = mt::random_sphere_set(rng, 40, 0.5, 0.1, 0.3);
  auto ga = std::make_shared<SphereSetGeometry>(a);
  auto gb = std::make_shared<SphereSetGeometry>(b);
  fcl::Transform3d X_WB = fcl::Transform3d::Identity();
  X_WB.translation() = Eigen::Vector3d(5, 0, 0);
  const fcl::Transform3d I = fcl::Transform3d::Identity();
  fcl::DistanceRequestd req(true);
  fcl::DistanceResultd exact;
  const double d = medspheres::fcl::distance(ga.get(), I, gb.get(), X_WB, req, exact);
  REQUIRE(d > 0);

  SECTION("a preset min_distance below the answer is kept") {
    fcl::DistanceResultd res;
    res.min_distance = 0.5 * d;
    CHECK(medspheres::fcl::distance(ga.get(), I, gb.get(), X_WB, req, res) == 0.5 * d);
    CHECK(res.o1 == nullptr);
    res.min_distance = 2 * d;
    CHECK(medspheres::fcl::distance(ga.get(), I, gb.get(), X_WB, req, res) == d);
    CHECK(res.o1 == ga.get());
  }
  SECTION("nearest points are written only when asked for") {
    fcl::DistanceRequestd no_points(false);
    fcl::DistanceResultd res;
    res.nearest_points[0] = Eigen::Vector3d(7, 7, 7);
    medspheres::fcl::distance(ga.get(), I, gb.get(), X_WB, no_points, res);
    CHECK(res.min_distance == d);
    CHECK(res.nearest_points[0] == Eigen::Vector3d(7, 7, 7));
    CHECK(res.b1 == exact.b1);
  }
  SECTION("abs_err and rel_err keep FCL's guarantee") {
    fcl::DistanceRequestd loose(true, false, 0.5, 0.3);
    fcl::DistanceResultd res;
    medspheres::fcl::distance(ga.get(), I, gb.get(), X_WB, loose, res);
    CHECK(res.min_distance >= d - 1e-12);
    CHECK(res.min_distance <= std::min(d + 0.3, 1.5 * d) + 1e-12);
  }
  SECTION("num_max_contacts counts the contacts already in the result") {
    X_WB.translation() = Eigen::Vector3d(0.05, 0, 0);
    fcl::CollisionRequestd all(1u << 20, true);
    fcl::CollisionResultd full;
    const std::size_t total = medspheres::fcl::collide(ga.get(), I, gb.get(), X_WB, all, full);
    REQUIRE(total > 5);
    fcl::CollisionRequestd three(3, true);
    fcl::CollisionResultd res;
    CHECK(medspheres::fcl::collide(ga.get(), I, gb.get(), X_WB, three, res) == 3);
    CHECK(medspheres::fcl::collide(ga.get(), I, gb.get(), X_WB, three, res) == 3);  // satisfied
    fcl::CollisionRequestd five(5, true);
    CHECK(medspheres::fcl::collide(ga.get(), I, gb.get(), X_WB, five, res) == 5);
    fcl::CollisionRequestd none(0, true);
    CHECK(medspheres::fcl::collide(ga.get(), I, gb.get(), X_WB, none, res) == 0);
    // Without enable_contact, contacts carry only the objects and primitives.
    fcl::CollisionRequestd bare(2, false);
    fcl::CollisionResultd bare_res;
    CHECK(medspheres::fcl::collide(ga.get(), I, gb.get(), X_WB, bare, bare_res) == 2);
    CHECK(bare_res.getContact(0).o1 == ga.get());
    CHECK(bare_res.getContact(0).b1 >= 0);
    // A geometry that is not occupied collides with nothing.
    gb->cost_density = 0.0;
    fcl::CollisionResultd free_res;
    CHECK(medspheres::fcl::collide(ga.get(), I, gb.get(), X_WB, all, free_res) == 0);
    gb->cost_density = 1.0;
  }
  SECTION("signed distance and non-finite poses") {
    X_WB.translation() = Eigen::Vector3d(0.2, 0, 0);
    fcl::DistanceRequestd sreq(true, true);
    fcl::DistanceResultd res;
    const double sd = medspheres::fcl::distance(ga.get(), I, gb.get(), X_WB, sreq, res);
    CHECK(sd < 0.0);
    CHECK((res.nearest_points[0] - res.nearest_points[1]).norm() == Approx(-sd));
    fcl::Transform3d bad = I;
    bad.translation().x() = std::nan("");
    CHECK_THROWS_AS(medspheres::fcl::distance(ga.get(), bad, gb.get(), I, sreq, res),
                    std::invalid_argument);
    CHECK_THROWS_AS(medspheres::fcl::distance(nullptr, I, gb.get(), I, sreq, res),
                    std::invalid_argument);
  }
}

TEST_CASE("Pairs without a sphere set return exactly what fcl:: returns", "[fcl]") {
  const medspheres::TriangleMesh mesh = mt::bumpy_sphere(8, 11, 0.8);
  std::vector<std::shared_ptr<fcl::CollisionGeometryd>> geometries = {
      std::make_shared<fcl::Boxd>(0.6, 0.4, 0.9),
      std::make_shared<fcl::Sphered>(0.5),
      std::make_shared<fcl::Capsuled>(0.3, 0.8),
      std::make_shared<fcl::Cylinderd>(0.4, 0.7),
      std::make_shared<fcl::Ellipsoidd>(0.3, 0.5, 0.4),
      mt::make_bvh<fcl::OBBRSSd>(mesh),
      mt::make_bvh<fcl::kIOSd>(mesh),
  };
  // BVHModel<RSS> is left out: libfcl 0.7's RSS mesh-mesh collision frees with delete[]
  // what its BVHModel copy constructor got from malloc (AddressSanitizer aborts on it).
  std::mt19937 rng(14);
  for (int k = 0; k < 40; ++k) {
    for (std::size_t i = 0; i < geometries.size(); ++i) {
      for (std::size_t j = 0; j < geometries.size(); ++j) {
        const fcl::CollisionGeometryd* g1 = geometries[i].get();
        const fcl::CollisionGeometryd* g2 = geometries[j].get();
        const bool both_meshes =
            g1->getObjectType() == fcl::OT_BVH && g2->getObjectType() == fcl::OT_BVH;
        if (both_meshes && g1->getNodeType() != g2->getNodeType()) continue;  // FCL: unsupported
        const fcl::Transform3d X1 = mt::random_pose(rng, 1.0), X2 = mt::random_pose(rng, 1.0);
        // When an fcl::Sphere overlaps a mesh, libfcl's distance reads an uninitialized
        // distance and points (fcl::detail::sphereTriangleDistance leaves them unset), so
        // there is nothing reproducible to compare.
        const bool sphere_mesh =
            (g1->getNodeType() == fcl::GEOM_SPHERE && g2->getObjectType() == fcl::OT_BVH) ||
            (g2->getNodeType() == fcl::GEOM_SPHERE && g1->getObjectType() == fcl::OT_BVH);
        fcl::CollisionResultd overlap;
        fcl::collide(g1, X1, g2, X2, fcl::CollisionRequestd(), overlap);
        if (!(sphere_mesh && overlap.isCollision())) {
          fcl::DistanceRequestd req(true);
          fcl::DistanceResultd expected, got;
          // FCL leaves nearest points unset for some pairs: start both from one value.
          for (fcl::DistanceResultd* r : {&expected, &got})
            r->nearest_points[0] = r->nearest_points[1] = Eigen::Vector3d::Zero();
          const double de = fcl::distance(g1, X1, g2, X2, req, expected);
          const double dg = medspheres::fcl::distance(g1, X1, g2, X2, req, got);
          CHECK(dg == de);
          CHECK(got.min_distance == expected.min_distance);
          CHECK(got.nearest_points[0] == expected.nearest_points[0]);
          CHECK(got.nearest_points[1] == expected.nearest_points[1]);
          CHECK(got.b1 == expected.b1);
          CHECK(got.b2 == expected.b2);
          CHECK(got.o1 == expected.o1);
        }
        fcl::CollisionRequestd creq(8, true);
        fcl::CollisionResultd ce, cg;
        CHECK(medspheres::fcl::collide(g1, X1, g2, X2, creq, cg) ==
              fcl::collide(g1, X1, g2, X2, creq, ce));
        REQUIRE(cg.numContacts() == ce.numContacts());
        for (std::size_t c = 0; c < ce.numContacts(); ++c) {
          CHECK(cg.getContact(c).pos == ce.getContact(c).pos);
          CHECK(cg.getContact(c).normal == ce.getContact(c).normal);
          CHECK(cg.getContact(c).penetration_depth == ce.getContact(c).penetration_depth);
          CHECK(cg.getContact(c).b1 == ce.getContact(c).b1);
          CHECK(cg.getContact(c).b2 == ce.getContact(c).b2);
        }
      }
    }
  }
}

TEST_CASE("libfcl sees a sphere set as a box that contains it", "[fcl]") {
  int colliding = 0;
  for (const Scene& s : random_scenes(15, 60)) {
    const Brute b = brute(s);
    fcl::CollisionRequestd creq;
    fcl::CollisionResultd cres;
    fcl::collide(s.ga.get(), s.X_WA, s.gb.get(), s.X_WB, creq, cres);  // libfcl, not ours
    if (!b.colliding.empty()) {
      ++colliding;
      CHECK(cres.isCollision());  // never "no collision" for spheres that collide
    }
    fcl::DistanceRequestd dreq;
    fcl::DistanceResultd dres;
    const double d = fcl::distance(s.ga.get(), s.X_WA, s.gb.get(), s.X_WB, dreq, dres);
    if (!cres.isCollision()) CHECK(d <= b.min_signed + 1e-6);
  }
  CHECK(colliding > 10);
}

TEST_CASE("libfcl's answers for a sphere set are its answers for the guard box", "[fcl]") {
  // Against every geometry libfcl pairs with a box, libfcl's collide() and, where it
  // computes one, distance() on a sphere set equal its answers on an fcl::Box of the
  // same sides: the guard is that box, whatever the other geometry.
  std::mt19937 rng(23);
  const medspheres::TriangleMesh mesh = mt::bumpy_sphere(7, 9, 0.6);
  auto verts = std::make_shared<std::vector<Eigen::Vector3d>>(std::vector<Eigen::Vector3d>{
      {-0.9, -0.7, -0.5}, {0.9, -0.7, -0.5}, {0.0, 1.0, -0.5}, {0.0, 0.0, 1.1}});
  auto faces = std::make_shared<std::vector<int>>(
      std::vector<int>{3, 0, 2, 1, 3, 0, 1, 3, 3, 1, 2, 3, 3, 2, 0, 3});
  struct Other {
    const char* name;
    std::shared_ptr<fcl::CollisionGeometryd> g;
    bool distance;  // libfcl computes box distances to it
  };
  const std::vector<Other> others = {
      {"box", std::make_shared<fcl::Boxd>(0.8, 0.5, 1.1), true},
      {"sphere", std::make_shared<fcl::Sphered>(0.6), true},
      {"ellipsoid", std::make_shared<fcl::Ellipsoidd>(0.5, 0.3, 0.7), true},
      {"capsule", std::make_shared<fcl::Capsuled>(0.3, 0.9), true},
      {"cone", std::make_shared<fcl::Coned>(0.7, 1.4), true},
      {"cylinder", std::make_shared<fcl::Cylinderd>(0.4, 0.8), true},
      {"convex", std::make_shared<fcl::Convexd>(verts, 4, faces, true), true},
      // libfcl 0.7's distance to planes and halfspaces crashes for every shape.
      {"plane", std::make_shared<fcl::Planed>(Eigen::Vector3d(0.3, -0.2, 1.0).normalized(), 0.1),
       false},
      {"halfspace",
       std::make_shared<fcl::Halfspaced>(Eigen::Vector3d(-0.5, 0.2, 1.0).normalized(), -0.2),
       false},
      {"BVHModel<OBBRSS>", mt::make_bvh<fcl::OBBRSSd>(mesh), true},
      {"BVHModel<RSS>", mt::make_bvh<fcl::RSSd>(mesh), true},
      {"BVHModel<kIOS>", mt::make_bvh<fcl::kIOSd>(mesh), true},
      {"BVHModel<AABB>", mt::make_bvh<fcl::AABBd>(mesh), false},
      {"BVHModel<OBB>", mt::make_bvh<fcl::OBBd>(mesh), false},
      {"BVHModel<KDOP24>", mt::make_bvh<fcl::KDOPd<24>>(mesh), false},
  };
  for (const Other& other : others) {
    INFO(other.name);
    int hits = 0, misses = 0;
    for (int k = 0; k < 20; ++k) {
      SphereSet set = mt::random_sphere_set(rng, 1 + rng() % 20, 0.5, 0.05, 0.25);
      for (Sphere& s : set.spheres) s.center += Eigen::Vector3d(0.3, -0.2, 0.1);  // off-centre
      const SphereSetGeometry g(set);
      const fcl::Boxd box(g.side);
      const fcl::Transform3d X_WA = mt::random_pose(rng, 1.2);
      const fcl::Transform3d X_WB = mt::random_pose(rng, 1.2);
      fcl::CollisionRequestd creq(4, true);
      fcl::CollisionResultd on_set, on_box;
      fcl::collide(&g, X_WA, other.g.get(), X_WB, creq, on_set);
      fcl::collide(&box, X_WA, other.g.get(), X_WB, creq, on_box);
      CHECK(on_set.numContacts() == on_box.numContacts());
      (on_box.isCollision() ? hits : misses)++;
      if (other.distance) {
        fcl::DistanceRequestd dreq;
        fcl::DistanceResultd d_set, d_box;
        CHECK(fcl::distance(&g, X_WA, other.g.get(), X_WB, dreq, d_set) ==
              fcl::distance(&box, X_WA, other.g.get(), X_WB, dreq, d_box));
      }
    }
    CHECK(hits > 0);
    CHECK(misses > 0);
  }
}

TEST_CASE("Sphere sets against unsupported geometries throw instead of reaching libfcl", "[fcl]") {
  std::mt19937 rng(16);
  auto g = std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 10));
  const fcl::TriangleP<double> triangle(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                        Eigen::Vector3d(0, 1, 0));
  const fcl::Transform3d I = fcl::Transform3d::Identity();
  fcl::DistanceRequestd dreq;
  fcl::DistanceResultd dres;
  CHECK_THROWS_AS(medspheres::fcl::distance(g.get(), I, &triangle, I, dreq, dres),
                  std::invalid_argument);
  fcl::CollisionRequestd creq;
  fcl::CollisionResultd cres;
  CHECK_THROWS_AS(medspheres::fcl::collide(&triangle, I, g.get(), I, creq, cres),
                  std::invalid_argument);
  fcl::BVHModel<fcl::OBBRSSd> points;
  points.beginModel();
  points.addSubModel(
      std::vector<Eigen::Vector3d>{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)});
  points.endModel();
  CHECK_THROWS_AS(medspheres::fcl::distance(g.get(), I, &points, I, dreq, dres),
                  std::invalid_argument);
  CHECK_THROWS_WITH(medspheres::fcl::collide(&points, I, g.get(), I, creq, cres),
                    Catch::Matchers::Contains("BVHModel of points"));
  fcl::BVHModel<fcl::AABBd> unfinished;
  unfinished.beginModel();
  unfinished.addTriangle(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                         Eigen::Vector3d(0, 1, 0));
  CHECK_THROWS_WITH(medspheres::fcl::distance(&unfinished, I, g.get(), I, dreq, dres),
                    Catch::Matchers::Contains("not finished"));
  CHECK_THROWS_WITH(medspheres::fcl::collide(g.get(), I, &unfinished, I, creq, cres),
                    Catch::Matchers::Contains("not finished"));
  CHECK_THROWS_WITH(medspheres::fcl::collide(g.get(), I, &triangle, I, creq, cres),
                    Catch::Matchers::Contains("is not supported"));
}

TEST_CASE("Many threads query one SphereSetGeometry", "[fcl]") {
  std::mt19937 rng(17);
  auto g = std::make_shared<SphereSetGeometry>(mt::random_sheet_set(rng, 300));
  const fcl::CollisionObjectd fixed(g, fcl::Transform3d::Identity());
  // CollisionObjects write the geometry's AABB members when built: build them first.
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> moving;
  for (int k = 0; k < 100; ++k)
    moving.push_back(std::make_unique<fcl::CollisionObjectd>(g, mt::random_pose(rng, 2.0)));
  std::vector<double> expected;
  for (const auto& m : moving) {
    fcl::DistanceRequestd req(true, true);
    fcl::DistanceResultd res;
    expected.push_back(medspheres::fcl::distance(&fixed, m.get(), req, res));
  }
  std::vector<int> mismatches(8, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      for (std::size_t k = 0; k < moving.size(); ++k) {
        const std::size_t i = (k + 13 * static_cast<std::size_t>(t)) % moving.size();
        fcl::DistanceRequestd req(true, true);
        fcl::DistanceResultd res;
        if (medspheres::fcl::distance(&fixed, moving[i].get(), req, res) != expected[i])
          ++mismatches[static_cast<std::size_t>(t)];
        fcl::CollisionRequestd creq(4, true);
        fcl::CollisionResultd cres;
        medspheres::fcl::collide(&fixed, moving[i].get(), creq, cres);
      }
    });
  }
  for (std::thread& th : threads) th.join();
  for (int m : mismatches) CHECK(m == 0);
}
