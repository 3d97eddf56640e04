// The separating plane (medspheres/fcl/separating_plane.h) against FCL's exact distance:
// a plane may prove a pair free only where the meshes are farther apart than the margin;
// near the margin (pairs bisected to it) never on the wrong side; and its supports equal a
// brute force over the vertices.

#include <cmath>
#include <limits>
#include <random>

#include <fcl/fcl.h>
#include <catch2/catch.hpp>

#include "medspheres/fcl/separating_plane.h"
#include "medspheres/mesh/mesh_generators.h"
#include "support/check_fixtures.h"
#include "support/fcl_fixtures.h"

using namespace medspheres;
namespace mf = medspheres::fcl;
using test::pose_of;

namespace {

// FCL's exact distance between two posed meshes (triangle pairs: exact to rounding).
double mesh_distance(const std::shared_ptr<mf::MeshModel>& a, const Eigen::Isometry3d& X_A,
                     const std::shared_ptr<mf::MeshModel>& b, const Eigen::Isometry3d& X_B) {
  const ::fcl::CollisionObjectd oa(a, X_A), ob(b, X_B);
  ::fcl::DistanceRequestd request;
  ::fcl::DistanceResultd result;
  return std::max(0.0, ::fcl::distance(&oa, &ob, request, result));
}

Eigen::Isometry3d random_pose(std::mt19937& rng, double reach) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d t(reach * u(rng), reach * u(rng), reach * u(rng));
  return pose_of(t, M_PI * u(rng), M_PI * u(rng), M_PI * u(rng));
}

// The solids the tests pose, as FCL meshes and supports: convex (a ball, a capsule, a box)
// and not (a torus, whose hull holds its hole).
struct Solids {
  std::vector<std::shared_ptr<mf::MeshModel>> models;
  std::vector<mf::VertexSupport> supports;

  Solids() {
    for (const TriangleMesh& m :
         {make_icosphere(0.05, 2), make_capsule(0.03, 0.06, 16, 4), make_box({0.04, 0.02, 0.07}, 2),
          make_torus(0.06, 0.015, 24, 8)}) {
      models.push_back(test::make_bvh<::fcl::OBBRSSd>(m));
      supports.emplace_back(*models.back());
    }
  }
};

}  // namespace

TEST_CASE("separating plane: the supports are the vertices' and balls' extremes", "[check][fcl]") {
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  std::vector<Sphere> balls;
  for (int i = 0; i < 3000; ++i) {
    points.emplace_back(u(rng), 0.3 * u(rng), 2.0 + 0.1 * u(rng));
    balls.push_back({points.back(), 0.05 * (1.0 + u(rng))});
  }
  points.push_back(points.front());  // a duplicate, kept once
  const mf::VertexSupport sp(points), sb(balls);
  CHECK(sp.size() == 3000);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d n(u(rng), u(rng), u(rng));
    double best = -std::numeric_limits<double>::infinity(), best_ball = best;
    const double length = n.norm() * (1.0 + 1e-15);
    for (std::size_t i = 0; i < balls.size(); ++i) {
      const Eigen::Vector3d& c = balls[i].center;
      best = std::max(best, n.x() * c.x() + n.y() * c.y() + n.z() * c.z());
      best_ball = std::max(
          best_ball, n.x() * c.x() + n.y() * c.y() + n.z() * c.z() + balls[i].radius * length);
    }
    CHECK(sp.max_along(n).value == best);
    CHECK(sb.max_along(n).value == best_ball);
    CHECK(n.dot(sp.max_along(n).point) == Approx(best).margin(1e-12));
  }
}

TEST_CASE("separating plane: every pair proved free is farther apart than the margin",
          "[check][fcl]") {
  const Solids solids;
  const auto& models = solids.models;
  const auto& supports = solids.supports;
  std::mt19937 rng(42);
  const double margin = 0.01;
  std::size_t proved = 0, within = 0, free_unproved = 0;
  for (int k = 0; k < 3000; ++k) {
    const std::size_t a = rng() % models.size(), b = rng() % models.size();
    const Eigen::Isometry3d X_A = random_pose(rng, 0.1), X_B = random_pose(rng, 0.1);
    const double d = mesh_distance(models[a], X_A, models[b], X_B);
    const mf::PlaneResult r = mf::separated(supports[a], X_A, supports[b], X_B, margin,
                                            X_B.translation() - X_A.translation());
    INFO("pair " << a << ", " << b << ": distance " << d << ", gap " << r.gap);
    if (r.free) {
      ++proved;
      CHECK(d > margin);
      CHECK(r.gap <= d + 1e-12);  // a plane's gap never exceeds the distance
    }
    within += d <= margin;
    free_unproved += d > margin && !r.free;
  }
  CHECK(proved > 300);
  CHECK(within > 300);
  CHECK(free_unproved > 0);  // the torus's hole: free pairs a plane cannot separate
}

TEST_CASE("separating plane: a pair bisected to the margin is never proved free within it",
          "[check][fcl]") {
  const Solids solids;
  const auto& models = solids.models;
  const auto& supports = solids.supports;
  std::mt19937 rng(43);
  const double margin = 0.01;
  std::size_t near_proved = 0, tried = 0;
  for (int k = 0; k < 120; ++k) {
    const std::size_t a = rng() % 3, b = rng() % 3;  // convex: the hulls are the solids
    const Eigen::Isometry3d X_A = random_pose(rng, 0.0);
    Eigen::Isometry3d X_B = random_pose(rng, 0.0);
    const Eigen::Vector3d away = Eigen::Vector3d(1.0, 0.3 * k / 120.0, -0.2).normalized();
    auto at = [&](double s) {
      Eigen::Isometry3d X = X_B;
      X.translation() = s * away;
      return X;
    };
    // s: B's offset along `away`; the distance grows with it past the solids' reach.
    double lo = 0.0, hi = 0.5;
    if (mesh_distance(models[a], X_A, models[b], at(lo)) > margin) continue;
    for (int step = 0; step < 60; ++step) {
      const double s = 0.5 * (lo + hi);
      (mesh_distance(models[a], X_A, models[b], at(s)) > margin ? hi : lo) = s;
    }
    ++tried;
    // lo: within the margin by FCL; a plane must not prove it free. Nor just inside it.
    for (double s : {lo, lo - 1e-9, lo - 1e-6, lo - 1e-4}) {
      const double d = mesh_distance(models[a], X_A, models[b], at(s));
      if (d > margin) continue;
      INFO("offset " << s << ", distance " << d);
      CHECK_FALSE(mf::separated(supports[a], X_A, supports[b], at(s), margin, away).free);
    }
    // Beyond the margin by 1e-5: convex solids are separated by a plane there.
    near_proved += mf::separated(supports[a], X_A, supports[b], at(hi + 2e-5), margin, away).free;
  }
  CHECK(tried > 100);
  CHECK(near_proved > tried * 9 / 10);
}

TEST_CASE("separating plane: the subsets' extremes are the set's points, never beyond them",
          "[check][fcl]") {
  const Solids solids;
  std::mt19937 rng(45);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Sphere> balls;
  for (int i = 0; i < 500; ++i) balls.push_back({{u(rng), u(rng), u(rng)}, 0.1 * (1.0 + u(rng))});
  const mf::VertexSupport sb(balls);
  std::vector<const mf::VertexSupport*> sets = {&sb};
  for (const mf::VertexSupport& s : solids.supports) sets.push_back(&s);
  for (const mf::VertexSupport* s : sets) {
    CHECK(s->coarse_size() <= std::min<std::size_t>(s->size(), 128));
    CHECK(s->coarse_size() >= std::min<std::size_t>(s->size(), 20));
    for (int k = 0; k < 300; ++k) {
      const Eigen::Vector3d n(u(rng), u(rng), u(rng));
      const mf::VertexSupport::CoarseExtreme c = s->coarse_max_along(n);
      const double exact = s->max_along(n).value;
      CHECK(c.value <= exact);
      if (s->size() <= 128) CHECK(c.value == exact);  // a small set is its own subset
      // The index is the point's: max_along started from it finds the same extreme.
      std::uint32_t hint = c.index;
      CHECK(s->max_along(n, &hint).value == exact);
      CHECK(n.dot(c.point) == Approx(c.value).margin(1e-12));
      CHECK(exact - c.value <= 0.1 * n.norm() * 2.0);  // near the extreme: the directions cover
      // at_most: whether the extreme is within a limit, from any start.
      for (double limit : {exact, std::nextafter(exact, -1e300), exact - 1e-3, exact + 1e-9,
                           c.value, exact + 1.0}) {
        const auto start = static_cast<std::uint32_t>(rng() % s->size());
        CHECK(s->at_most(n, limit, start) == (exact <= limit));
        CHECK(s->at_most(n, limit, c.index) == (exact <= limit));
      }
    }
  }
}

TEST_CASE("separating plane: the first phase finds no plane only within the margin",
          "[check][fcl]") {
  // Convex solids: their hulls are the solids, so "no plane" must mean FCL's distance is
  // within the margin (up to the search's rounding), and planes stay found beyond it.
  const Solids solids;
  std::mt19937 rng(46);
  const double margin = 0.01;
  std::size_t no_plane = 0, beyond = 0, proved_beyond = 0;
  for (int k = 0; k < 3000; ++k) {
    const std::size_t a = rng() % 3, b = rng() % 3;
    const Eigen::Isometry3d X_A = random_pose(rng, 0.08), X_B = random_pose(rng, 0.08);
    const double d = mesh_distance(solids.models[a], X_A, solids.models[b], X_B);
    const mf::PlaneResult r = mf::separated(solids.supports[a], X_A, solids.supports[b], X_B,
                                            margin, X_B.translation() - X_A.translation());
    INFO("pair " << a << ", " << b << ": distance " << d << ", coarse steps " << r.coarse_steps);
    if (r.no_plane) {
      ++no_plane;
      CHECK(d <= margin + 1e-9);
      CHECK(r.steps == 0);
      CHECK_FALSE(r.free);
    }
    if (d > margin + 1e-4) {
      ++beyond;
      proved_beyond += r.free;
    }
  }
  CHECK(no_plane > 300);
  CHECK(beyond > 300);
  CHECK(proved_beyond > beyond * 95 / 100);
}

TEST_CASE("separating plane: scene primitives by their corners and balls", "[check][fcl]") {
  const std::shared_ptr<mf::MeshModel> link =
      test::make_bvh<::fcl::OBBRSSd>(make_torus(0.06, 0.015, 24, 8));
  const mf::VertexSupport support(*link);
  std::vector<std::shared_ptr<::fcl::CollisionGeometryd>> shapes = {
      std::make_shared<::fcl::Boxd>(0.2, 0.1, 0.05), std::make_shared<::fcl::Sphered>(0.04),
      std::make_shared<::fcl::Capsuled>(0.03, 0.12),
      test::make_bvh<::fcl::OBBRSSd>(make_icosphere(0.05, 1))};
  CHECK(mf::support_of(::fcl::Cylinderd(0.1, 0.2)) == nullptr);  // no finite point set
  std::mt19937 rng(44);
  const double margin = 0.01;
  std::size_t proved = 0;
  for (int k = 0; k < 2000; ++k) {
    const auto& shape = shapes[std::size_t(k) % shapes.size()];
    const auto s = mf::support_of(*shape);
    REQUIRE(s != nullptr);
    const Eigen::Isometry3d X_A = random_pose(rng, 0.12), X_B = random_pose(rng, 0.12);
    const mf::PlaneResult r =
        mf::separated(support, X_A, *s, X_B, margin, X_B.translation() - X_A.translation());
    if (!r.free) continue;
    ++proved;
    const ::fcl::CollisionObjectd oa(link, X_A), ob(shape, X_B);
    ::fcl::DistanceRequestd request;
    ::fcl::DistanceResultd result;
    const double d = ::fcl::distance(&oa, &ob, request, result);
    INFO("shape " << k % 4 << ": distance " << d << ", gap " << r.gap);
    CHECK(d > margin - 1e-6);  // FCL's GJK for a mesh and a primitive: 1e-6
    CHECK(r.gap <= d + 1e-6);
  }
  CHECK(proved > 300);
}

TEST_CASE("separating plane: bad input", "[check][fcl]") {
  CHECK_THROWS_AS(mf::VertexSupport(std::vector<Eigen::Vector3d>{}), std::invalid_argument);
  CHECK_THROWS_AS(mf::VertexSupport(std::vector<Eigen::Vector3d>{
                      {0.0, std::numeric_limits<double>::quiet_NaN(), 0.0}}),
                  std::invalid_argument);
  CHECK_THROWS_AS(mf::VertexSupport(std::vector<Sphere>{{Eigen::Vector3d::Zero(), -1.0}}),
                  std::invalid_argument);
  const mf::VertexSupport a(std::vector<Eigen::Vector3d>{{0, 0, 0}, {0, 0, 1}});
  const mf::VertexSupport b(std::vector<Eigen::Vector3d>{{1, 0, 0}, {1, 0, 1}});
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  CHECK(mf::separated(a, I, b, I, 0.5, {1, 0, 0}).free);
  CHECK(mf::separated(a, I, b, I, 0.5, {0, 0, 0}).free);        // a zero guess: the origins
  CHECK_FALSE(mf::separated(a, I, b, I, 1.0, {1, 0, 0}).free);  // touching the margin
  CHECK_FALSE(mf::separated(a, I, b, I, std::nan(""), {1, 0, 0}).free);
  CHECK_FALSE(mf::separated(a, I, b, I, -1.0, {1, 0, 0}).free);
  Eigen::Isometry3d bad = I;
  bad.translation().x() = std::numeric_limits<double>::infinity();
  CHECK_FALSE(mf::separated(a, bad, b, I, 0.5, {1, 0, 0}).free);
}
