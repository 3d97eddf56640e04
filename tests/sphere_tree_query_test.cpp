// SphereTree queries against brute force over all sphere pairs: distance, witness
// points, signed distance, collision and contacts at random poses, touching included;
// symmetry under swapping; RSS against ball trees; tolerances; many threads.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/sphere_tree.h"
#include "medspheres/triangle_tree.h"
#include "support/sphere_fixtures.h"
#include "support/sphere_scenes.h"

using medspheres::DistanceOptions;
using medspheres::SphereSet;
using medspheres::SphereTree;
using medspheres::TreeContact;
using medspheres::TreeDistance;
namespace ms = medspheres;
namespace mt = medspheres::test;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

using Case = mt::SetPairScene;

double tolerance(const Case& c) {
  return 64 * kEps *
         (mt::set_extent(c.a) + mt::set_extent(c.b) + c.X_WA.translation().norm() +
          c.X_WB.translation().norm());
}

// Checks a reported pair against its definition in sphere_tree.h.
void check_reported_pair(const Case& c, const TreeDistance& d, double tol) {
  REQUIRE(d.found());
  const ms::Sphere& sa = c.a.spheres[static_cast<std::size_t>(d.sphere_a)];
  const ms::Sphere& sb = c.b.spheres[static_cast<std::size_t>(d.primitive_b)];
  const double pair = mt::pair_signed_distance(sa, c.X_WA, sb, c.X_WB);
  CHECK(d.distance == Approx(pair).margin(tol));
  const Eigen::Vector3d ca = c.X_WA * sa.center, cb = c.X_WB * sb.center;
  // Witness points lie on the spheres' surfaces, on the line of centres, and differ by
  // the signed distance along the unit normal from a to b.
  CHECK((d.p_WPa - ca).norm() == Approx(sa.radius).margin(tol));
  CHECK((d.p_WPb - cb).norm() == Approx(sb.radius).margin(tol));
  const Eigen::Vector3d n = (cb - ca).normalized();
  CHECK((d.p_WPb - d.p_WPa - d.distance * n).norm() <= tol);
  CHECK((d.p_WPa - (ca + sa.radius * n)).norm() <= tol);
}

std::set<std::pair<std::intptr_t, std::intptr_t>> brute_overlaps(const Case& c) {
  std::set<std::pair<std::intptr_t, std::intptr_t>> out;
  for (std::size_t i = 0; i < c.a.size(); ++i)
    for (std::size_t j = 0; j < c.b.size(); ++j)
      if (mt::pair_signed_distance(c.a.spheres[i], c.X_WA, c.b.spheres[j], c.X_WB) <= 0.0)
        out.insert({static_cast<std::intptr_t>(i), static_cast<std::intptr_t>(j)});
  return out;
}

}  // namespace

TEST_CASE("SphereTree distance and signed distance match brute force", "[sphere_tree][query]") {
  const std::vector<Case> cases = mt::random_set_pairs(21, 60);
  int separated = 0, overlapping = 0;
  for (const ms::SphereTreeOptions& options : mt::all_tree_options()) {
    for (const Case& c : cases) {
      const SphereTree ta(c.a, options), tb(c.b, options);
      const mt::BrutePair brute = mt::brute_min(c.a, c.X_WA, c.b, c.X_WB);
      const double tol = tolerance(c);
      const TreeDistance sd = medspheres::signed_distance(ta, c.X_WA, tb, c.X_WB);
      CHECK(sd.distance == Approx(brute.value).margin(tol));
      check_reported_pair(c, sd, tol);
      const TreeDistance d = medspheres::distance(ta, c.X_WA, tb, c.X_WB);
      check_reported_pair(c, d, tol);
      if (brute.value > tol) {
        ++separated;
        CHECK(d.distance == Approx(brute.value).margin(tol));
        CHECK_FALSE(medspheres::collide(ta, c.X_WA, tb, c.X_WB));
      } else if (brute.value < -tol) {
        ++overlapping;
        // Unsigned distance stops at the first overlapping pair: <= 0, >= the deepest.
        CHECK(d.distance <= tol);
        CHECK(d.distance >= brute.value - tol);
        CHECK(medspheres::collide(ta, c.X_WA, tb, c.X_WB));
      }
      CHECK(d.stats.bv_tests > 0);
      CHECK(d.stats.leaf_tests > 0);
    }
  }
  CHECK(separated > 40);
  CHECK(overlapping > 40);
}

TEST_CASE("SphereTree with points (radius 0) matches brute force", "[sphere_tree][query]") {
  std::vector<Case> cases = mt::random_set_pairs(43, 30);
  int separated = 0;
  for (Case& c : cases) {
    // Every other ball of each set becomes its centre point.
    for (SphereSet* set : {&c.a, &c.b})
      for (std::size_t i = 0; i < set->size(); i += 2) set->spheres[i].radius = 0.0;
    CHECK_THROWS_AS(SphereTree(c.a), ms::InputError);
    for (ms::SphereTreeOptions options : mt::all_tree_options()) {
      options.allow_points = true;
      const SphereTree ta(c.a, options), tb(c.b, options);
      const mt::BrutePair brute = mt::brute_min(c.a, c.X_WA, c.b, c.X_WB);
      const double tol = tolerance(c);
      const TreeDistance sd = medspheres::signed_distance(ta, c.X_WA, tb, c.X_WB);
      CHECK(sd.distance == Approx(brute.value).margin(tol));
      if (brute.value > tol) {
        ++separated;
        CHECK(medspheres::distance(ta, c.X_WA, tb, c.X_WB).distance ==
              Approx(brute.value).margin(tol));
      }
    }
  }
  CHECK(separated > 10);
}

TEST_CASE("SphereTree contacts are exactly the overlapping pairs", "[sphere_tree][query]") {
  const std::vector<Case> cases = mt::random_set_pairs(5, 40);
  for (const ms::SphereTreeOptions& options : mt::all_tree_options()) {
    for (const Case& c : cases) {
      const SphereTree ta(c.a, options), tb(c.b, options);
      const auto expected = brute_overlaps(c);
      const double tol = tolerance(c);
      std::vector<TreeContact> all;
      const std::size_t n = medspheres::contacts(ta, c.X_WA, tb, c.X_WB, 1u << 30, all);
      CHECK(n == all.size());
      std::set<std::pair<std::intptr_t, std::intptr_t>> got;
      for (const TreeContact& k : all) {
        CHECK(got.insert({k.sphere_a, k.primitive_b}).second);  // no duplicates
        const ms::Sphere& sa = c.a.spheres[static_cast<std::size_t>(k.sphere_a)];
        const ms::Sphere& sb = c.b.spheres[static_cast<std::size_t>(k.primitive_b)];
        const Eigen::Vector3d ca = c.X_WA * sa.center, cb = c.X_WB * sb.center;
        const double sd = (cb - ca).norm() - (sa.radius + sb.radius);
        CHECK(k.depth == Approx(-sd).margin(tol));
        CHECK(k.depth >= 0.0);
        CHECK(k.n_W.norm() == Approx(1.0));
        if ((cb - ca).norm() > tol) CHECK((k.n_W - (cb - ca).normalized()).norm() <= 1e-9);
        // Midpoint of the deepest points a + r_a n and b - r_b n.
        const Eigen::Vector3d mid = 0.5 * (ca + sa.radius * k.n_W + cb - sb.radius * k.n_W);
        CHECK((k.p_WC - mid).norm() <= tol);
      }
      CHECK(got == expected);
      CHECK(medspheres::collide(ta, c.X_WA, tb, c.X_WB) == !expected.empty());
      // A maximum count is honoured, and every pair reported is a real contact.
      for (std::size_t max : {std::size_t{1}, std::size_t{3}}) {
        std::vector<TreeContact> some;
        const std::size_t m = medspheres::contacts(ta, c.X_WA, tb, c.X_WB, max, some);
        CHECK(m == std::min(max, expected.size()));
        CHECK(some.size() == m);
        for (const TreeContact& k : some) CHECK(expected.count({k.sphere_a, k.primitive_b}) == 1);
      }
      std::vector<TreeContact> none;
      CHECK(medspheres::contacts(ta, c.X_WA, tb, c.X_WB, 0, none) == 0);
      CHECK(none.empty());
    }
  }
}

TEST_CASE("SphereTree: touching counts as collision, exactly", "[sphere_tree][query]") {
  // Dyadic coordinates and axis-permuting rotations keep every value exact.
  SphereSet a, b;
  a.spheres.push_back({Eigen::Vector3d(0, 0, 0), 1.0});
  a.spheres.push_back({Eigen::Vector3d(-4, 0, 0), 0.5});
  a.spheres.push_back({Eigen::Vector3d(0, -8, 0), 0.25});
  b.spheres.push_back({Eigen::Vector3d(0, 0, 0), 2.0});
  b.spheres.push_back({Eigen::Vector3d(0, 16, 0), 1.5});
  Eigen::Isometry3d X_WA = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.linear() << 0, -1, 0, 1, 0, 0, 0, 0, 1;  // 90 degrees about z
  for (const ms::SphereTreeOptions& options : mt::all_tree_options()) {
    const SphereTree ta(a, options), tb(b, options);
    X_WB.translation() = Eigen::Vector3d(3.0, 0, 0);  // |3 - 0| = 1 + 2: touching
    CHECK(medspheres::collide(ta, X_WA, tb, X_WB));
    TreeDistance d = medspheres::distance(ta, X_WA, tb, X_WB);
    CHECK(d.distance == 0.0);
    CHECK(d.sphere_a == 0);
    CHECK(d.primitive_b == 0);
    CHECK(d.p_WPa == Eigen::Vector3d(1, 0, 0));
    CHECK(d.p_WPb == Eigen::Vector3d(1, 0, 0));
    d = medspheres::signed_distance(ta, X_WA, tb, X_WB);
    CHECK(d.distance == 0.0);
    std::vector<TreeContact> cs;
    REQUIRE(medspheres::contacts(ta, X_WA, tb, X_WB, 10, cs) == 1);
    CHECK(cs[0].depth == 0.0);
    CHECK(cs[0].n_W == Eigen::Vector3d(1, 0, 0));
    CHECK(cs[0].p_WC == Eigen::Vector3d(1, 0, 0));
    // Separated by one ulp-sized gap: no collision.
    X_WB.translation() = Eigen::Vector3d(3.0 + std::ldexp(1.0, -40), 0, 0);
    CHECK_FALSE(medspheres::collide(ta, X_WA, tb, X_WB));
    d = medspheres::distance(ta, X_WA, tb, X_WB);
    CHECK(d.distance == std::ldexp(1.0, -40));
    // Coincident centres: the normal is W's x axis.
    X_WB.translation() = Eigen::Vector3d(0, 0, 0);
    d = medspheres::signed_distance(ta, X_WA, tb, X_WB);
    CHECK(d.distance == -3.0);
    CHECK(d.p_WPa == Eigen::Vector3d(1, 0, 0));
    CHECK(d.p_WPb == Eigen::Vector3d(-2, 0, 0));
  }
}

TEST_CASE("SphereTree distance is symmetric under swapping", "[sphere_tree][query]") {
  for (const Case& c : mt::random_set_pairs(33, 40)) {
    const SphereTree ta(c.a), tb(c.b);
    const double tol = tolerance(c);
    for (bool is_signed : {false, true}) {
      const TreeDistance ab = is_signed ? medspheres::signed_distance(ta, c.X_WA, tb, c.X_WB)
                                        : medspheres::distance(ta, c.X_WA, tb, c.X_WB);
      const TreeDistance ba = is_signed ? medspheres::signed_distance(tb, c.X_WB, ta, c.X_WA)
                                        : medspheres::distance(tb, c.X_WB, ta, c.X_WA);
      if (!is_signed && ab.distance <= 0.0) continue;  // first overlap found: order-dependent
      CHECK(ab.distance == Approx(ba.distance).margin(tol));
      CHECK(ab.sphere_a == ba.primitive_b);
      CHECK(ab.primitive_b == ba.sphere_a);
      CHECK((ab.p_WPa - ba.p_WPb).norm() <= tol);
      CHECK((ab.p_WPb - ba.p_WPa).norm() <= tol);
    }
    CHECK(medspheres::collide(ta, c.X_WA, tb, c.X_WB) ==
          medspheres::collide(tb, c.X_WB, ta, c.X_WA));
  }
}

TEST_CASE("SphereTree: RSS and ball trees give the same distances", "[sphere_tree][query]") {
  ms::SphereTreeOptions rss, ball;
  ball.kind = ms::BoundingVolumeKind::ball;
  for (const Case& c : mt::random_set_pairs(44, 50)) {
    const SphereTree ra(c.a, rss), rb(c.b, rss), ba(c.a, ball), bb(c.b, ball);
    const double tol = tolerance(c);
    const TreeDistance d_rr = medspheres::signed_distance(ra, c.X_WA, rb, c.X_WB);
    const TreeDistance d_bb = medspheres::signed_distance(ba, c.X_WA, bb, c.X_WB);
    const TreeDistance d_rb = medspheres::signed_distance(ra, c.X_WA, bb, c.X_WB);
    const TreeDistance d_br = medspheres::signed_distance(ba, c.X_WA, rb, c.X_WB);
    CHECK(d_rr.distance == Approx(d_bb.distance).margin(tol));
    CHECK(d_rr.distance == Approx(d_rb.distance).margin(tol));
    CHECK(d_rr.distance == Approx(d_br.distance).margin(tol));
  }
}

TEST_CASE("SphereTree tolerances keep FCL's guarantee", "[sphere_tree][query]") {
  for (const Case& c : mt::random_set_pairs(55, 40)) {
    const SphereTree ta(c.a), tb(c.b);
    const double exact = mt::brute_min(c.a, c.X_WA, c.b, c.X_WB).value;
    if (exact <= 0.0) continue;
    const double tol = tolerance(c);
    DistanceOptions o;
    o.abs_err = 0.2;
    o.rel_err = 0.3;
    const TreeDistance d = medspheres::distance(ta, c.X_WA, tb, c.X_WB, o);
    CHECK(d.distance >= exact - tol);
    CHECK(d.distance <= std::min(exact + o.abs_err, (1 + o.rel_err) * exact) + tol);
    check_reported_pair(c, d, tol);
    // Either tolerance alone leaves the answer exact.
    o.rel_err = 0.0;
    CHECK(medspheres::distance(ta, c.X_WA, tb, c.X_WB, o).distance == Approx(exact).margin(tol));
    o.abs_err = 0.0;
    o.rel_err = 0.5;
    CHECK(medspheres::distance(ta, c.X_WA, tb, c.X_WB, o).distance == Approx(exact).margin(tol));
  }
}

namespace {

// The tolerance modes compared below. With one tolerance zero, FCL's rule prunes exactly
// as with none (c >= best - abs_err and c (1 + rel_err) >= best reduces to c >= best); the
// other tolerance is then set to a value that never binds (1e6, the options must be
// finite) so that the one under test decides.
struct ToleranceMode {
  const char* name;
  double abs_err;  ///< as a fraction of the exact distance when relative_abs
  double rel_err;
  bool relative_abs;
  bool loose;  ///< expected to prune (both tolerances bind), else exact
};

const std::vector<ToleranceMode>& tolerance_modes() {
  static const std::vector<ToleranceMode> modes = {
      {"exact", 0.0, 0.0, false, false},
      {"rel_err 0.5", 1e6, 0.5, false, true},
      {"abs_err 0.5 d*", 0.5, 1e6, true, true},
      {"rel_err 0.5 alone", 0.0, 0.5, false, false},
      {"abs_err 0.5 d* alone", 0.5, 0.0, true, false},
  };
  return modes;
}

// Work summed over scenes, and how many answers exceed the exact minimum, per mode.
struct ToleranceTotals {
  std::vector<std::uint64_t> work = std::vector<std::uint64_t>(tolerance_modes().size(), 0);
  std::vector<int> inexact = std::vector<int>(tolerance_modes().size(), 0);
  int scenes = 0;
};

// Runs \p query (DistanceOptions -> TreeDistance) in every mode on a scene whose exact
// minimum is exact > 0, checks FCL's guarantee d* <= d <= min(d* + abs_err, (1 + rel_err) d*)
// (to tol) and, through \p check_pair, that the reported pair has the reported value;
// accumulates the work (bv_tests + leaf_tests) into totals.
template <class Query, class CheckPair>
void run_tolerance_modes(double exact, double tol, Query query, CheckPair check_pair,
                         ToleranceTotals& totals) {
  ++totals.scenes;
  std::vector<std::uint64_t> work;
  for (std::size_t m = 0; m < tolerance_modes().size(); ++m) {
    const ToleranceMode& mode = tolerance_modes()[m];
    INFO(mode.name);
    DistanceOptions o;
    o.abs_err = mode.relative_abs ? mode.abs_err * exact : mode.abs_err;
    o.rel_err = mode.rel_err;
    const TreeDistance d = query(o);
    REQUIRE(d.found());
    CHECK(d.distance >= exact - tol);
    CHECK(d.distance <= std::min(exact + o.abs_err, (1 + o.rel_err) * exact) + tol);
    check_pair(d, tol);
    if (!mode.loose) CHECK(d.distance == Approx(exact).margin(tol));
    if (d.distance > exact + tol) ++totals.inexact[m];
    work.push_back(d.stats.bv_tests + d.stats.leaf_tests);
    totals.work[m] += work.back();
  }
  // One tolerance alone prunes exactly as none: the same traversal.
  CHECK(work[3] == work[0]);
  CHECK(work[4] == work[0]);
}

void check_tolerance_totals(const ToleranceTotals& totals) {
  INFO("scenes " << totals.scenes);
  CHECK(totals.scenes >= 20);
  for (std::size_t m = 1; m < tolerance_modes().size(); ++m) {
    INFO(tolerance_modes()[m].name << ": work " << totals.work[m] << " against " << totals.work[0]
                                   << " exact, " << totals.inexact[m] << " inexact answers");
    if (tolerance_modes()[m].loose) {
      CHECK(totals.work[m] < totals.work[0]);  // loosening prunes
      CHECK(totals.inexact[m] > 0);            // and is used: some answer is not exact
    } else {
      CHECK(totals.work[m] == totals.work[0]);
      CHECK(totals.inexact[m] == 0);
    }
  }
  CHECK(totals.inexact[0] == 0);
}

}  // namespace

TEST_CASE("SphereTree tolerances prune tree-tree queries within FCL's guarantee",
          "[sphere_tree][query]") {
  for (const ms::SphereTreeOptions& options : mt::all_tree_options()) {
    INFO("kind " << static_cast<int>(options.kind) << " leaf " << options.max_leaf_size);
    ToleranceTotals totals;
    for (const Case& c : mt::random_set_pairs(56, 60)) {
      const SphereTree ta(c.a, options), tb(c.b, options);
      const double exact = mt::brute_min(c.a, c.X_WA, c.b, c.X_WB).value;
      const double tol = tolerance(c);
      if (exact < -tol) {
        // A negative signed distance is exact whatever the tolerances.
        DistanceOptions o;
        o.abs_err = 1e6;
        o.rel_err = 1e6;
        CHECK(medspheres::signed_distance(ta, c.X_WA, tb, c.X_WB, o).distance ==
              Approx(exact).margin(tol));
        continue;
      }
      if (exact <= tol) continue;
      for (bool is_signed : {false, true}) {
        run_tolerance_modes(
            exact, tol,
            [&](const DistanceOptions& o) {
              return is_signed ? medspheres::signed_distance(ta, c.X_WA, tb, c.X_WB, o)
                               : medspheres::distance(ta, c.X_WA, tb, c.X_WB, o);
            },
            [&](const TreeDistance& d, double t) { check_reported_pair(c, d, t); }, totals);
      }
    }
    check_tolerance_totals(totals);
  }
}

TEST_CASE("SphereTree tolerances prune tree-mesh queries within FCL's guarantee",
          "[sphere_tree][query]") {
  const medspheres::TriangleMesh mesh = mt::bumpy_sphere(12, 17, 1.0);
  const medspheres::TriangleTree target(mesh);
  std::mt19937 rng(57);
  for (const ms::SphereTreeOptions& options : mt::all_tree_options()) {
    INFO("kind " << static_cast<int>(options.kind) << " leaf " << options.max_leaf_size);
    ToleranceTotals totals;
    for (int k = 0; k < 40; ++k) {
      const SphereSet set = (k % 2) ? mt::random_sheet_set(rng, 1 + rng() % 120)
                                    : mt::random_sphere_set(rng, 1 + rng() % 120, 0.6, 0.02, 0.2);
      const SphereTree tree(set, options);
      const Eigen::Isometry3d X_WA = mt::random_pose(rng, 3.0);
      const Eigen::Isometry3d X_WB = mt::random_pose(rng, 3.0);
      // Brute force over sphere x triangle pairs, in W (the mesh is a surface).
      auto pair_value = [&](std::size_t i, std::size_t t) {
        const Eigen::Vector3d c = X_WA * set.spheres[i].center;
        const Eigen::Vector3d q = medspheres::closest_point_on_triangle(
            c, X_WB * mesh.corner(t, 0), X_WB * mesh.corner(t, 1), X_WB * mesh.corner(t, 2));
        return (q - c).norm() - set.spheres[i].radius;
      };
      double exact = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < set.size(); ++i)
        for (std::size_t t = 0; t < mesh.num_triangles(); ++t)
          exact = std::min(exact, pair_value(i, t));
      const double tol = 1e-12 * (4 + X_WA.translation().norm() + X_WB.translation().norm());
      if (exact <= tol) continue;
      run_tolerance_modes(
          exact, tol,
          [&](const DistanceOptions& o) {
            return medspheres::distance(tree, X_WA, target, X_WB, o);
          },
          [&](const TreeDistance& d, double t) {
            CHECK(pair_value(static_cast<std::size_t>(d.sphere_a),
                             static_cast<std::size_t>(d.primitive_b)) ==
                  Approx(d.distance).margin(t));
          },
          totals);
    }
    check_tolerance_totals(totals);
  }
}

TEST_CASE("SphereTree honours a preset upper bound", "[sphere_tree][query]") {
  for (const Case& c : mt::random_set_pairs(66, 30)) {
    const SphereTree ta(c.a), tb(c.b);
    const double exact = mt::brute_min(c.a, c.X_WA, c.b, c.X_WB).value;
    if (exact <= 0.0) continue;
    DistanceOptions o;
    o.upper_bound = exact * 0.999;
    TreeDistance d = medspheres::distance(ta, c.X_WA, tb, c.X_WB, o);
    CHECK_FALSE(d.found());
    CHECK(d.distance == o.upper_bound);
    o.upper_bound = exact * 1.001 + 1e-12;
    d = medspheres::distance(ta, c.X_WA, tb, c.X_WB, o);
    CHECK(d.found());
    CHECK(d.distance == Approx(exact).margin(tolerance(c)));
  }
}

TEST_CASE("SphereTree point distance matches brute force", "[sphere_tree][query]") {
  std::mt19937 rng(77);
  for (const ms::SphereTreeOptions& options : mt::all_tree_options()) {
    for (int k = 0; k < 30; ++k) {
      const SphereSet set = mt::random_sphere_set(rng, 1 + rng() % 150);
      const SphereTree tree(set, options);
      const Eigen::Isometry3d X_WA = mt::random_pose(rng, 2.0);
      for (int q = 0; q < 10; ++q) {
        const Eigen::Vector3d p_WQ =
            X_WA * Eigen::Vector3d(std::uniform_real_distribution<double>(-1.5, 1.5)(rng),
                                   std::uniform_real_distribution<double>(-1.5, 1.5)(rng),
                                   std::uniform_real_distribution<double>(-1.5, 1.5)(rng));
        double best = std::numeric_limits<double>::infinity();
        for (const ms::Sphere& s : set.spheres)
          best = std::min(best, (p_WQ - X_WA * s.center).norm() - s.radius);
        const TreeDistance d = medspheres::distance(tree, X_WA, p_WQ);
        const double tol = 64 * kEps * (3 + X_WA.translation().norm());
        CHECK(d.distance == Approx(best).margin(tol));
        REQUIRE(d.found());
        const ms::Sphere& s = set.spheres[static_cast<std::size_t>(d.sphere_a)];
        CHECK((p_WQ - X_WA * s.center).norm() - s.radius == Approx(best).margin(tol));
        CHECK((d.p_WPa - X_WA * s.center).norm() == Approx(s.radius).margin(tol));
        CHECK(d.p_WPb == p_WQ);
        CHECK(d.primitive_b == -1);
      }
    }
  }
}

TEST_CASE("SphereTree queries on empty trees find nothing", "[sphere_tree][query]") {
  const SphereTree empty;
  std::mt19937 rng(3);
  const SphereTree full(mt::random_sphere_set(rng, 10));
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  CHECK_FALSE(medspheres::distance(empty, I, full, I).found());
  CHECK_FALSE(medspheres::signed_distance(full, I, empty, I).found());
  CHECK_FALSE(medspheres::collide(empty, I, full, I));
  CHECK_FALSE(medspheres::distance(empty, I, Eigen::Vector3d(1, 2, 3)).found());
  std::vector<TreeContact> out;
  CHECK(medspheres::contacts(full, I, empty, I, 5, out) == 0);
}

TEST_CASE("SphereTree queries reject bad arguments", "[sphere_tree][query]") {
  std::mt19937 rng(4);
  const SphereTree t(mt::random_sphere_set(rng, 10));
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation().x() = std::numeric_limits<double>::infinity();
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  CHECK_THROWS_AS(medspheres::distance(t, bad, t, I), std::invalid_argument);
  CHECK_THROWS_AS(medspheres::collide(t, I, t, bad), std::invalid_argument);
  CHECK_THROWS_AS(medspheres::distance(t, I, Eigen::Vector3d(0, std::nan(""), 0)),
                  std::invalid_argument);
  DistanceOptions o;
  o.abs_err = -1;
  CHECK_THROWS_AS(medspheres::distance(t, I, t, I, o), std::invalid_argument);
  o.abs_err = 0;
  o.rel_err = std::nan("");
  CHECK_THROWS_AS(medspheres::signed_distance(t, I, t, I, o), std::invalid_argument);
}

TEST_CASE("SphereTree: many threads query one tree", "[sphere_tree][query]") {
  std::mt19937 rng(88);
  const SphereSet set = mt::random_sheet_set(rng, 300);
  const SphereTree tree(set);
  std::vector<Eigen::Isometry3d> poses;
  for (int k = 0; k < 200; ++k) poses.push_back(mt::random_pose(rng, 2.0));
  std::vector<double> expected;
  for (const Eigen::Isometry3d& X : poses)
    expected.push_back(
        medspheres::signed_distance(tree, Eigen::Isometry3d::Identity(), tree, X).distance);
  constexpr int kThreads = 8;
  std::vector<std::vector<double>> got(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (std::size_t k = 0; k < poses.size(); ++k) {
        const std::size_t i = (k + static_cast<std::size_t>(t) * 37) % poses.size();
        got[static_cast<std::size_t>(t)].push_back(
            medspheres::signed_distance(tree, Eigen::Isometry3d::Identity(), tree, poses[i])
                .distance -
            expected[i]);
        std::vector<TreeContact> cs;
        medspheres::contacts(tree, Eigen::Isometry3d::Identity(), tree, poses[i], 4, cs);
      }
    });
  }
  for (std::thread& th : threads) th.join();
  for (const auto& g : got) {
    CHECK(g.size() == poses.size());
    for (double diff : g) CHECK(diff == 0.0);
  }
}
