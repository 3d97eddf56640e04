// RobotChecker (medspheres/check/robot_checker.h) against oracles: the spheres-only mode
// against every sphere tested against every scene object and every self pair by brute
// force, with the link poses of KinematicTree and distances written out here; the AVX2
// path against the scalar one at configurations bisected to within 1e-12 of a contact;
// thread counts; edges against each of their samples checked alone.

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>
#include <tuple>

#include <catch2/catch.hpp>

#include "medspheres/check/robot_checker.h"
#include "medspheres/error.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/point_triangle.h"
#include "medspheres/threads.h"
#include "support/check_fixtures.h"
#include "support/sanitizer_build.h"

using namespace medspheres;
using check::Mode;
using check::Verdict;
using test::pose_of;

namespace {

// The test scene around the arm: one object of each kind.
struct TestScene {
  check::Scene scene;
  TriangleMesh ball = make_icosphere(0.15, 2);
  Eigen::Isometry3d X_ball = pose_of({0.3, 0.5, 0.9});
  std::vector<Eigen::Vector3d> points, cells;
  TestScene() {
    scene.add_box({2, 2, 0.05}, pose_of({0, 0, -0.125}), "floor");
    scene.add_box({0.3, 0.2, 0.4}, pose_of({0.5, 0.2, 0.3}, 0.2, 0.0, 0.5), "box");
    scene.add_sphere({-0.4, 0.4, 0.6}, 0.12, "sphere");
    scene.add_capsule(0.06, 0.5, pose_of({0.1, -0.5, 0.5}, 0.7), "capsule");
    scene.add_cylinder(0.08, 0.4, pose_of({-0.5, -0.3, 0.3}, 0.0, 0.9), "cylinder");
    scene.add_mesh(ball, X_ball, "mesh");
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 300; ++i)
      points.emplace_back(0.6 + 0.2 * u(rng), -0.4 + 0.8 * u(rng), 0.8 + 0.4 * u(rng));
    scene.add_points(points, "cloud");
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j) cells.emplace_back(-0.7, -0.3 + 0.04 * i, 0.4 + 0.04 * j);
    scene.add_cells(cells, 0.04, "cells");
  }

  // The exact distance from p to the scene (0 inside a solid; the mesh a surface).
  double distance(const Eigen::Vector3d& p) const {
    double best = std::numeric_limits<double>::infinity();
    for (const check::SceneObject& o : scene.objects()) {
      const Eigen::Vector3d l = o.X_WO.inverse() * p;
      switch (o.kind) {
        case check::ShapeKind::box:
          best = std::min(best, (l - l.cwiseMax(-o.size / 2).cwiseMin(o.size / 2)).norm());
          break;
        case check::ShapeKind::sphere:
          best = std::min(best, std::max(0.0, l.norm() - o.radius));
          break;
        case check::ShapeKind::capsule: {
          const double z = std::clamp(l.z(), -o.length / 2, o.length / 2);
          best = std::min(best, std::max(0.0, (l - Eigen::Vector3d(0, 0, z)).norm() - o.radius));
          break;
        }
        case check::ShapeKind::cylinder: {
          const double dr = std::max(0.0, std::hypot(l.x(), l.y()) - o.radius);
          const double dz = std::max(0.0, std::abs(l.z()) - o.length / 2);
          best = std::min(best, std::hypot(dr, dz));
          break;
        }
        case check::ShapeKind::mesh:
          for (const auto& t : o.mesh.triangles) {
            const Eigen::Vector3d q = closest_point_on_triangle(
                l, o.mesh.vertices[t[0]], o.mesh.vertices[t[1]], o.mesh.vertices[t[2]]);
            best = std::min(best, (l - q).norm());
          }
          break;
        case check::ShapeKind::points:
          for (const Eigen::Vector3d& x : o.points) best = std::min(best, (p - x).norm());
          break;
        case check::ShapeKind::cells:
          for (const Eigen::Vector3d& c : o.points) {
            const Eigen::Vector3d h = Eigen::Vector3d::Constant(o.cell_side / 2);
            const Eigen::Vector3d d = p - c;
            best = std::min(best, (d - d.cwiseMax(-h).cwiseMin(h)).norm());
          }
          break;
      }
    }
    return best;
  }
};

const TestScene& test_scene() {
  static const TestScene s;
  return s;
}

check::CheckerOptions options(double margin) {
  check::CheckerOptions o;
  o.margin = margin;
  o.disabled = {{"tool", "l7"}};  // joined across the flange by fixed joints
  // The self pairs' tables of fewer cells in the sanitizer builds, where baking them was a
  // third of each checker's construction: the same code on coarser cells. ("pair tables"
  // below sets its own counts, the default's among them.)
  if (test::kSanitizerBuild) o.pair_table_cells = 1u << 10;
  return o;
}

// Brute force: some sphere of sets[l] (link l's, in its frame) within `margin` of the scene
// (unless `scene` is false) or of a sphere of another link it is paired with.
bool sets_within(const RobotModel& model, const std::vector<std::vector<Sphere>>& sets,
                 const Eigen::VectorXd& q, double margin, bool scene) {
  const KinematicTree tree(model);
  const std::vector<Eigen::Isometry3d> X = tree.link_poses(q);
  std::vector<std::vector<Sphere>> posed(model.links.size());
  for (std::size_t l = 0; l < model.links.size(); ++l)
    for (const Sphere& s : sets[l]) posed[l].push_back({X[l] * s.center, s.radius});
  for (const auto& set : posed)
    for (const Sphere& s : set)
      if (scene && test_scene().distance(s.center) - s.radius <= margin) return true;
  std::set<std::pair<std::string, std::string>> skip = {{"l7", "tool"}, {"tool", "l7"}};
  for (const Joint& j : model.joints) {
    skip.insert({j.parent, j.child});
    skip.insert({j.child, j.parent});
  }
  for (std::size_t a = 0; a < posed.size(); ++a)
    for (std::size_t b = a + 1; b < posed.size(); ++b) {
      if (skip.count({model.links[a].name, model.links[b].name})) continue;
      for (const Sphere& s : posed[a])
        for (const Sphere& t : posed[b])
          if ((s.center - t.center).norm() - s.radius - t.radius <= margin) return true;
    }
  return false;
}

// Brute force: every covering sphere against the scene (unless `scene` is false) and every
// self pair.
bool brute_force(const RobotModel& model, const Eigen::VectorXd& q, double margin,
                 bool scene = true) {
  std::vector<std::vector<Sphere>> sets;
  for (const Link& l : model.links) sets.push_back(l.spheres.outer.spheres);
  return sets_within(model, sets, q, margin, scene);
}

std::vector<Verdict> run(const check::RobotChecker& c, const std::vector<double>& q, Mode mode,
                         int threads = 1) {
  std::vector<Verdict> out(q.size() / c.num_positions());
  c.check(q.data(), out.size(), mode, out.data(), threads);
  return out;
}

// The configurations q and, after them, pairs of configurations 1e-12 apart (in t) on
// either side of contact: bisected between a free and a colliding configuration of q as
// `checker` sees them (up to 120 pairs). Where two computations round differently, some
// end would flip.
std::vector<double> near_contact(const check::RobotChecker& checker, std::vector<double> q) {
  const std::size_t dof = checker.num_positions();
  const std::vector<Verdict> first = run(checker, q, Mode::spheres);
  std::vector<double> edges;
  std::size_t a = 0;
  for (std::size_t i = 1; i < first.size() && edges.size() < dof * 2 * 120; ++i)
    if (first[i] != first[a]) {
      double lo = 0.0, hi = 1.0;
      std::vector<double> at(dof);
      auto point = [&](double t) {
        for (std::size_t j = 0; j < dof; ++j)
          at[j] = q[dof * a + j] + t * (q[dof * i + j] - q[dof * a + j]);
        return at;
      };
      const Verdict v0 = checker.check(point(0.0).data(), Mode::spheres);
      while (hi - lo > 1e-12) {
        const double mid = (lo + hi) / 2;
        (checker.check(point(mid).data(), Mode::spheres) == v0 ? lo : hi) = mid;
      }
      for (double t : {lo, hi})
        for (double x : point(t)) edges.push_back(x);
      a = i;
    }
  q.insert(q.end(), edges.begin(), edges.end());
  return q;
}

}  // namespace

TEST_CASE("spheres mode: the verdict of every sphere and self pair checked by brute force",
          "[check]") {
  const RobotModel arm = test::capsule_arm(5);
  for (const bool floats : {true, false})
    for (double margin : {0.0, 0.01}) {
      check::CheckerOptions o = options(margin);
      o.float_tests = floats;
      const check::RobotChecker checker(arm, test_scene().scene, o);
      REQUIRE(checker.num_positions() == 8);
      const std::vector<double> q = test::capsule_arm_configs(600, 11);
      const std::vector<Verdict> v = run(checker, q, Mode::spheres);
      std::size_t colliding = 0, disagree = 0;
      for (std::size_t i = 0; i < v.size(); ++i) {
        const Eigen::Map<const Eigen::VectorXd> qi(q.data() + 8 * i, 8);
        const bool truth = brute_force(arm, qi, margin);
        colliding += truth;
        disagree += truth != (v[i] == Verdict::colliding);
        CHECK(v[i] != Verdict::undecided);
      }
      CHECK(disagree == 0);
      // Both answers occur often enough for the comparison to mean something.
      CHECK(colliding > v.size() / 10);
      CHECK(colliding < v.size() * 9 / 10);
    }
}

TEST_CASE("bounds mode: colliding only where the inner sets are, free only where the covers are",
          "[check]") {
  // Without a fine level the bounds' verdicts are the sets' own: colliding implies the
  // covers (which hold the inner balls' links) collide, free implies they do not.
  const RobotModel arm = test::capsule_arm(5);
  const check::RobotChecker checker(arm, test_scene().scene, options(0.01));
  const std::vector<double> q = test::capsule_arm_configs(400, 12);
  const std::vector<Verdict> b = run(checker, q, Mode::bounds);
  const std::vector<Verdict> s = run(checker, q, Mode::spheres);
  std::size_t counts[3] = {0, 0, 0};
  for (std::size_t i = 0; i < b.size(); ++i) {
    ++counts[static_cast<int>(b[i])];
    if (b[i] == Verdict::colliding) CHECK(s[i] == Verdict::colliding);
    if (b[i] == Verdict::free) CHECK(s[i] == Verdict::free);
  }
  CHECK(counts[0] > 0);
  CHECK(counts[1] > 0);
  CHECK(counts[2] > 0);
}

TEST_CASE("bounds with pairs: check()'s verdicts, and each configuration's undecided pairs",
          "[check]") {
  // check_bounds runs eight configurations to a block; each lane's pairs must be those of
  // its configuration checked alone (a lane reading another lane's bits would differ).
  const RobotModel arm = test::capsule_arm(5), fine = test::capsule_arm(9);
  const check::RobotChecker checker(arm, test_scene().scene, options(0.01), &fine);
  const std::vector<double> q = test::capsule_arm_configs(301, 16);
  const std::size_t n = q.size() / checker.num_positions();
  for (int threads : {1, 2}) {
    std::vector<Verdict> v(n);
    std::vector<std::vector<check::UndecidedPair>> pairs(n);
    checker.check_bounds(q.data(), n, v.data(), pairs.data(), threads);
    CHECK(v == run(checker, q, Mode::bounds));
    std::size_t undecided = 0, lanes_beyond_first = 0;
    for (std::size_t i = 0; i < n; ++i) {
      std::vector<check::UndecidedPair> one;
      REQUIRE(checker.check(q.data() + i * checker.num_positions(), Mode::bounds, &one) == v[i]);
      REQUIRE(one.size() == pairs[i].size());
      for (std::size_t k = 0; k < one.size(); ++k) {
        CHECK(one[k].link == pairs[i][k].link);
        CHECK(one[k].other == pairs[i][k].other);
        CHECK(one[k].self == pairs[i][k].self);
      }
      if (v[i] == Verdict::undecided) {
        ++undecided;
        CHECK_FALSE(pairs[i].empty());
        lanes_beyond_first += i % 8 != 0;
      } else {
        CHECK(pairs[i].empty());
      }
    }
    CHECK(undecided > 10);
    CHECK(lanes_beyond_first > 5);
  }
  // The float pass gives the pairs of its lanes whose tests were all certain: the double
  // pass's self pairs, and at least its scene objects (those within the slack more).
  check::CheckerOptions d = options(0.01);
  d.float_tests = false;
  const check::RobotChecker doubles(arm, test_scene().scene, d, &fine);
  std::vector<Verdict> vf(n), vd(n);
  std::vector<std::vector<check::UndecidedPair>> pf(n), pd(n);
  checker.check_bounds(q.data(), n, vf.data(), pf.data(), 1);
  doubles.check_bounds(q.data(), n, vd.data(), pd.data(), 1);
  CHECK(vf == vd);
  std::size_t scene_pairs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::set<std::tuple<std::size_t, std::size_t, bool>> in_floats, self_floats, self_doubles;
    for (const check::UndecidedPair& p : pf[i]) {
      in_floats.insert({p.link, p.other, p.self});
      if (p.self) self_floats.insert({p.link, p.other, p.self});
    }
    for (const check::UndecidedPair& p : pd[i]) {
      CHECK(in_floats.count({p.link, p.other, p.self}) == 1);
      if (p.self) self_doubles.insert({p.link, p.other, p.self});
      scene_pairs += !p.self;
    }
    CHECK(self_floats == self_doubles);
  }
  CHECK(scene_pairs > 0);
}

TEST_CASE("AVX2 and scalar paths: the same verdicts, bisected to 1e-12 of contact", "[check]") {
  const RobotModel arm = test::capsule_arm(5);
  const RobotModel fine = test::capsule_arm(9);
  check::CheckerOptions scalar_options = options(0.01), avx2_options = options(0.01);
  scalar_options.simd = check::Simd::scalar;
  avx2_options.simd = check::Simd::avx2;
  const check::RobotChecker scalar(arm, test_scene().scene, scalar_options, &fine);
  CHECK_FALSE(scalar.uses_avx2());
  if (!__builtin_cpu_supports("avx2")) {
    CHECK_THROWS_AS(check::RobotChecker(arm, test_scene().scene, avx2_options),
                    std::invalid_argument);
    WARN("no AVX2 on this processor: the AVX2 path is not compared");
    return;
  }
  const check::RobotChecker avx2(arm, test_scene().scene, avx2_options, &fine);
  REQUIRE(avx2.uses_avx2());
  const std::vector<double> q = near_contact(scalar, test::capsule_arm_configs(2000, 13));
  for (Mode mode : {Mode::spheres, Mode::bounds}) CHECK(run(scalar, q, mode) == run(avx2, q, mode));
  CHECK(q.size() >= 8 * (2000 + 2 * 100));
}

TEST_CASE("spheres batches: each verdict that of its configuration checked alone, 1 or 2 threads",
          "[check]") {
  // Batches of up to 32 blocks gather their set tests' lanes across blocks: whole batches,
  // a last partial block and batch, and one repeated configuration (every test's items
  // fill whole groups of eight); the tests' default order (no head: batches) and the
  // learnt one (a head: block by block). A batch of no items: "an empty scene and no self
  // pairs".
  const RobotModel arm = test::capsule_arm(5);
  std::size_t heads = 0;
  for (const std::size_t samples : {std::size_t(0), std::size_t(256)})
    for (const check::Simd simd : {check::Simd::scalar, check::Simd::automatic}) {
      check::CheckerOptions o = options(0.01);
      o.simd = simd;
      o.order_samples = samples;
      const check::RobotChecker checker(arm, test_scene().scene, o);
      heads += checker.test_order().head > 0;
      const std::vector<double> near = near_contact(checker, test::capsule_arm_configs(300, 16));
      std::vector<double> repeated;
      for (int i = 0; i < 8 * 32; ++i)
        repeated.insert(repeated.end(), near.begin() + 8 * 7, near.begin() + 8 * 8);
      for (const std::vector<double>* all :
           {&near, static_cast<const std::vector<double>*>(&repeated)})
        for (std::size_t n :
             {std::size_t(9), std::size_t(8 * 32), std::size_t(8 * 32 + 1), all->size() / 8}) {
          const std::vector<double> q(all->begin(),
                                      all->begin() + 8 * std::min(n, all->size() / 8));
          const std::vector<Verdict> v = run(checker, q, Mode::spheres);
          std::size_t differ = 0, colliding = 0;
          for (std::size_t i = 0; i < v.size(); ++i) {
            differ += checker.check(q.data() + 8 * i, Mode::spheres) != v[i];
            colliding += v[i] == Verdict::colliding;
          }
          INFO("configurations " << v.size() << ", colliding " << colliding);
          CHECK(differ == 0);
        }
      const std::vector<Verdict> v = run(checker, near, Mode::spheres);
      CHECK(std::count(v.begin(), v.end(), Verdict::colliding) > 0);
      CHECK(std::count(v.begin(), v.end(), Verdict::free) > 0);
      CHECK(run(checker, near, Mode::spheres, 2) == v);
    }
  CHECK(heads == 2);  // the learnt order's, on both paths: the batches ran with the default
}

TEST_CASE("thread counts: the same verdicts with 1, 2 and 3 threads", "[check]") {
  const RobotModel arm = test::capsule_arm(5);
  const check::RobotChecker checker(arm, test_scene().scene, options(0.01));
  const std::vector<double> q = test::capsule_arm_configs(301, 14);
  for (Mode mode : {Mode::spheres, Mode::bounds}) {
    const std::vector<Verdict> one = run(checker, q, mode, 1);
    CHECK(run(checker, q, mode, 2) == one);
    CHECK(run(checker, q, mode, 3) == one);
  }
}

TEST_CASE("edges: the verdict of every interpolated configuration checked alone", "[check]") {
  const RobotModel arm = test::capsule_arm(5);
  const check::RobotChecker checker(arm, test_scene().scene, options(0.0));
  const std::vector<double> q = test::capsule_arm_configs(121, 15);
  const double resolution = 0.05;
  std::size_t colliding = 0, free = 0;
  for (Mode mode : {Mode::spheres, Mode::bounds})
    for (std::size_t e = 0; e + 1 < 121; ++e) {
      const double* q0 = q.data() + 8 * e;
      const double* q1 = q0 + 8;
      // Short edges too: a tenth of the way.
      std::vector<double> end(q0, q0 + 8);
      for (int j = 0; j < 8; ++j) end[j] += (e % 2 ? 0.1 : 1.0) * (q1[j] - q0[j]);
      const std::size_t n = checker.edge_steps(q0, end.data(), resolution);
      bool any_colliding = false, any_undecided = false;
      std::vector<double> at(8);
      for (std::size_t k = 0; k <= n; ++k) {
        const double t = double(k) / double(n);
        for (int j = 0; j < 8; ++j) at[j] = q0[j] + t * (end[j] - q0[j]);
        const Verdict v = checker.check(at.data(), mode);
        any_colliding |= v == Verdict::colliding;
        any_undecided |= v == Verdict::undecided;
      }
      std::vector<double> open;
      std::size_t checked = 0;
      const Verdict v = checker.check_edge(q0, end.data(), resolution, mode, &open, &checked);
      const Verdict truth = any_colliding   ? Verdict::colliding
                            : any_undecided ? Verdict::undecided
                                            : Verdict::free;
      CHECK(v == truth);
      CHECK(checked <= n + 1);
      if (v != Verdict::colliding) CHECK(checked == n + 1);
      if (v != Verdict::colliding) CHECK(open.empty() == (v == Verdict::free));
      colliding += v == Verdict::colliding;
      free += v == Verdict::free;
    }
  CHECK(colliding > 20);
  CHECK(free > 20);
  // The batch agrees with the edges one at a time, with two threads.
  std::vector<Verdict> batch(120);
  const std::size_t checked =
      checker.check_edges(q.data(), q.data() + 8, 120, resolution, Mode::spheres, batch.data(), 2);
  CHECK(checked > 120);
  for (std::size_t e = 0; e < 120; ++e)
    CHECK(batch[e] ==
          checker.check_edge(q.data() + 8 * e, q.data() + 8 * e + 8, resolution, Mode::spheres));
}

TEST_CASE("any_colliding: true exactly when some configuration collides, in any window",
          "[check]") {
  // Windows of 0 to 17 configurations near contact, on both paths: whole blocks, a partial
  // last one, one configuration; a block stops at its first colliding lane, so the answer
  // must be check()'s "some colliding" whichever lane that is.
  const RobotModel arm = test::capsule_arm(5);
  std::size_t yes = 0, no = 0;
  for (const check::Simd simd : {check::Simd::scalar, check::Simd::automatic}) {
    check::CheckerOptions o = options(0.01);
    o.simd = simd;
    const check::RobotChecker checker(arm, test_scene().scene, o);
    const std::vector<double> q = near_contact(checker, test::capsule_arm_configs(200, 17));
    const std::vector<Verdict> v = run(checker, q, Mode::spheres);
    const std::size_t n = v.size();
    for (std::size_t first = 0; first + 17 <= n; first += 5)
      for (std::size_t count : {0, 1, 7, 8, 9, 17}) {
        const bool truth = std::any_of(v.begin() + long(first), v.begin() + long(first + count),
                                       [](Verdict x) { return x == Verdict::colliding; });
        const bool got = checker.any_colliding(q.data() + 8 * first, count);
        CHECK(got == truth);
        (got ? yes : no) += 1;
      }
  }
  CHECK(yes > 50);
  CHECK(no > 50);
}

TEST_CASE("one-configuration calls of two checkers in turn on one thread, and from two threads",
          "[check]") {
  // check(q), check_edge and any_colliding keep a workspace per thread for the checker
  // that used it last: two robots of other sizes in turn, and two threads at once.
  const check::RobotChecker a(test::capsule_arm(5), test_scene().scene, options(0.01));
  const check::RobotChecker b(test::capsule_arm(3), test_scene().scene, options(0.01));
  const std::vector<double> q = test::capsule_arm_configs(400, 18);
  const std::vector<Verdict> va = run(a, q, Mode::spheres), vb = run(b, q, Mode::spheres);
  REQUIRE(va != vb);  // the robots differ where it shows
  auto alone = [&](std::size_t from, std::size_t to) {
    std::size_t differ = 0;
    for (std::size_t i = from; i < to; ++i) {
      differ += a.check(q.data() + 8 * i, Mode::spheres) != va[i];
      differ += b.check(q.data() + 8 * i, Mode::spheres) != vb[i];
      differ += a.any_colliding(q.data() + 8 * i, 1) != (va[i] == Verdict::colliding);
    }
    return differ;
  };
  CHECK(alone(0, 400) == 0);
  std::size_t other = 0;
  std::thread t([&] { other = alone(200, 400); });
  const std::size_t here = alone(0, 200);
  t.join();
  CHECK(here == 0);
  CHECK(other == 0);
}

TEST_CASE("with_scene: the verdicts of a checker built anew on the other scene, on any grid",
          "[check]") {
  // A checker of one scene handed another: a box and a ball, then the same far out (beyond
  // 1 km, where the tables' allowance no longer holds and they are built again), then
  // nothing. Both modes, the learnt order's and the default's, and the tables' counts.
  const RobotModel arm = test::capsule_arm(5);
  const std::vector<double> q = test::capsule_arm_configs(600, 19);
  for (const std::size_t samples : {std::size_t(0), std::size_t(256)}) {
    check::CheckerOptions o = options(0.01);
    o.order_samples = samples;
    const check::RobotChecker first(arm, test_scene().scene, o);
    check::Scene near, far;
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() = Eigen::Vector3d(0.3, -0.2, 0.4);
    near.add_box({0.3, 0.2, 0.25}, X);
    near.add_sphere({-0.3, 0.1, 0.5}, 0.15);
    far = near;
    far.add_sphere({2000.0, 0.0, 0.0}, 1.0);
    check::Scene none;
    for (const check::Scene* scene : {&near, &far, &none}) {
      const check::Scene& s = *scene;
      const check::RobotChecker fresh(arm, s, o);
      const check::RobotChecker moved = first.with_scene(s);
      // The same scene on a coarse grid (as a planner that builds a checker per problem may
      // choose: built sooner, looked up more).
      check::CheckerOptions coarse_grid = o;
      coarse_grid.max_cells = 4096;
      const check::RobotChecker coarse(arm, s, coarse_grid);
      CHECK(moved.pair_tables() == fresh.pair_tables());
      if (scene != &none) CHECK(fresh.grid().cells > 4 * coarse.grid().cells);
      for (Mode mode : {Mode::spheres, Mode::bounds}) {
        const std::vector<Verdict> v = run(fresh, q, mode);
        CHECK(run(moved, q, mode) == v);
        CHECK(run(coarse, q, mode) == v);
        if (scene == &near) CHECK(std::count(v.begin(), v.end(), Verdict::colliding) > 20);
      }
    }
    CHECK(first.pair_tables() > 0);
  }
}

TEST_CASE("robot checker: an empty scene and no self pairs leave everything free", "[check]") {
  check::CheckerOptions o;
  o.self = false;
  const check::RobotChecker checker(test::capsule_arm(3), check::Scene(), o);
  const std::vector<double> q = test::capsule_arm_configs(50, 16);
  for (Mode mode : {Mode::spheres, Mode::bounds})
    for (Verdict v : run(checker, q, mode)) CHECK(v == Verdict::free);
}

TEST_CASE("robot checker: bad input is refused with a message naming it", "[check]") {
  const RobotModel arm = test::capsule_arm(3);
  const check::Scene& scene = test_scene().scene;
  check::CheckerOptions o;
  o.margin = -1;
  CHECK_THROWS_AS(check::RobotChecker(arm, scene, o), std::invalid_argument);
  o.margin = 0;
  o.disabled = {{"l1", "nope"}};
  CHECK_THROWS_WITH(check::RobotChecker(arm, scene, o), Catch::Contains("nope"));
  o.disabled.clear();
  for (const int threads : {-1, medspheres::kMaxThreads + 1}) {
    o.build_threads = threads;
    CHECK_THROWS_WITH(check::RobotChecker(arm, scene, o), Catch::Contains("build_threads"));
  }
  o.build_threads = 0;
  RobotModel other = test::capsule_arm(3);
  other.joints[2].origin.translation().x() += 0.1;
  CHECK_THROWS_WITH(check::RobotChecker(arm, scene, o, &other), Catch::Contains("j3"));
  const check::RobotChecker checker(arm, scene, o);
  std::vector<double> q = test::capsule_arm_configs(3, 17);
  q[8 + 2] = std::nan("");
  std::vector<Verdict> out(3);
  CHECK_THROWS_WITH(checker.check(q.data(), 3, Mode::spheres, out.data()),
                    Catch::Contains("configuration 1") && Catch::Contains("j3"));
  CHECK_THROWS_AS(checker.check_edge(q.data(), q.data() + 16, 0.0, Mode::spheres),
                  std::invalid_argument);
  // A resolution that would check more than kMaxEdgeSteps configurations on an edge is
  // refused, naming the edge, before any edge is checked (1e-300 overflowed the count, and
  // 1e-12 would have run for hours).
  const std::size_t dof = checker.num_positions();
  const std::vector<double> q0 = test::capsule_arm_configs(2, 5);
  std::vector<double> q1 = q0;  // edge 0: no length (one configuration)
  for (std::size_t j = 0; j < dof; ++j) q1[dof + j] += 0.5;
  CHECK(checker.check_edges(q0.data(), q1.data(), 2, 1e-3, Mode::spheres, out.data()) > 0);
  for (const double resolution : {1e-12, 1e-300}) {
    CAPTURE(resolution);
    CHECK_THROWS_WITH(checker.edge_steps(q0.data() + dof, q1.data() + dof, resolution),
                      Catch::Contains("configurations on it"));
    CHECK_THROWS_WITH(
        checker.check_edges(q0.data(), q1.data(), 2, resolution, Mode::spheres, out.data()),
        Catch::Contains("edge 1") && Catch::Contains("configurations on it"));
  }
  CHECK_THROWS_WITH(
      checker.check_edges(q0.data(), q1.data(), 0, std::nan(""), Mode::spheres, out.data()),
      Catch::Contains("resolution"));
  // Thread counts as everywhere in medspheres: 0 to kMaxThreads (a count such as 100000
  // once reached OpenMP, which crashed creating the threads).
  q[8 + 2] = 0.0;
  for (const int threads : {-1, kMaxThreads + 1, 100000}) {
    CAPTURE(threads);
    for (const Mode mode : {Mode::spheres, Mode::bounds})
      CHECK_THROWS_WITH(checker.check(q.data(), 3, mode, out.data(), threads),
                        Catch::Contains("threads must be in [0, 1024]"));
    CHECK_THROWS_WITH(checker.check_bounds(q.data(), 3, out.data(), nullptr, threads),
                      Catch::Contains("threads"));
    CHECK_THROWS_WITH(
        checker.check_edges(q.data(), q.data() + 8, 2, 0.1, Mode::spheres, out.data(), threads),
        Catch::Contains("threads"));
  }
  check::Scene bad;
  CHECK_THROWS_WITH(bad.add_box({1, -1, 1}, Eigen::Isometry3d::Identity(), "crate"),
                    Catch::Contains("crate"));
  CHECK_THROWS_WITH(bad.add_mesh(TriangleMesh{{}, {{0, 1, 2}}}, Eigen::Isometry3d::Identity(), "m"),
                    Catch::Contains("out of range"));
}

namespace {

// Every fifth mesh vertex of each capsule link (on its capsule's surface, so in its closed
// solid) as inner points of radius 0, in the link frame.
std::map<std::string, std::vector<Sphere>> vertex_points() {
  std::map<std::string, std::vector<Sphere>> out;
  for (const test::CapsuleLink& l : test::capsule_arm_links()) {
    const std::vector<Eigen::Vector3d> v = test::capsule_link_mesh(l).vertices;
    for (std::size_t k = 0; k < v.size(); k += 5) out[l.name].push_back({v[k], 0.0});
  }
  return out;
}

// Brute force: some inner sphere or point (`extra`) of a self pair within `margin` of one
// of the other link, or within `margin` of the scene.
bool inner_within(const RobotModel& model, const std::map<std::string, std::vector<Sphere>>& extra,
                  const Eigen::VectorXd& q, double margin) {
  std::vector<std::vector<Sphere>> sets;
  for (const Link& l : model.links) {
    sets.push_back(l.spheres.inner.spheres);
    const auto e = extra.find(l.name);
    if (e != extra.end()) sets.back().insert(sets.back().end(), e->second.begin(), e->second.end());
  }
  return sets_within(model, sets, q, margin, true);
}

}  // namespace

TEST_CASE("inner points: the bounds mode proves collisions by them, each within the margin",
          "[check]") {
  const RobotModel arm = test::capsule_arm(3);
  const double margin = 0.01;
  check::CheckerOptions o = options(margin);
  const check::RobotChecker plain(arm, test_scene().scene, o);
  o.inner_points = vertex_points();
  o.simd = check::Simd::scalar;
  const check::RobotChecker scalar(arm, test_scene().scene, o);
  o.simd = check::Simd::automatic;
  const check::RobotChecker with(arm, test_scene().scene, o);
  std::vector<double> q = test::capsule_arm_configs(700, 31);
  // Configurations bisected to 1e-12 of where the points' proofs begin.
  const std::vector<Verdict> first = run(with, q, Mode::bounds);
  std::vector<double> at(8), extra;
  for (std::size_t i = 1; i < first.size() && extra.size() < 8 * 2 * 60; ++i) {
    if ((first[i] == Verdict::colliding) == (first[i - 1] == Verdict::colliding)) continue;
    auto point = [&](double t) {
      for (std::size_t j = 0; j < 8; ++j)
        at[j] = q[8 * (i - 1) + j] + t * (q[8 * i + j] - q[8 * (i - 1) + j]);
      return at;
    };
    double lo = 0.0, hi = 1.0;  // lo on first[i - 1]'s side
    while (hi - lo > 1e-12) {
      const double mid = (lo + hi) / 2;
      const bool c = with.check(point(mid).data(), Mode::bounds) == Verdict::colliding;
      (c == (first[i - 1] == Verdict::colliding) ? lo : hi) = mid;
    }
    for (double t : {lo, hi})
      for (double x : point(t)) extra.push_back(x);
  }
  q.insert(q.end(), extra.begin(), extra.end());
  const std::size_t n = q.size() / 8;
  REQUIRE(n > 760);
  const std::vector<Verdict> b = run(with, q, Mode::bounds), p = run(plain, q, Mode::bounds);
  CHECK(run(with, q, Mode::spheres) == run(plain, q, Mode::spheres));
  CHECK(run(scalar, q, Mode::bounds) == b);
  CHECK(run(with, q, Mode::bounds, 2) == b);
  std::size_t gained = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Map<const Eigen::VectorXd> qi(q.data() + 8 * i, 8);
    INFO("configuration " << i);
    // The covers are the same: free where they were. A proof rests on an inner pair
    // within the margin; an inner pair within the margin less a hair is proved.
    CHECK((b[i] == Verdict::free) == (p[i] == Verdict::free));
    if (p[i] == Verdict::colliding) CHECK(b[i] == Verdict::colliding);
    if (b[i] == Verdict::colliding) CHECK(inner_within(arm, o.inner_points, qi, margin));
    if (b[i] != Verdict::colliding)
      CHECK_FALSE(inner_within(arm, o.inner_points, qi, margin - 1e-7));
    gained += b[i] == Verdict::colliding && p[i] != Verdict::colliding;
  }
  CHECK(gained > 20);
  // Bad points are refused, naming the link.
  o.inner_points = {{"nope", {{Eigen::Vector3d::Zero(), 0.0}}}};
  CHECK_THROWS_WITH(check::RobotChecker(arm, test_scene().scene, o), Catch::Contains("nope"));
  o.inner_points = {{"l2", {{Eigen::Vector3d::Zero(), -1e-3}}}};
  CHECK_THROWS_WITH(check::RobotChecker(arm, test_scene().scene, o), Catch::Contains("l2"));
  o.inner_points = {{"l3", {{Eigen::Vector3d(0, std::nan(""), 0), 0.0}}}};
  CHECK_THROWS_WITH(check::RobotChecker(arm, test_scene().scene, o), Catch::Contains("l3"));
  RobotModel bare = arm;
  bare.links[4].spheres.outer = {};
  o.inner_points = {{"l4", {{Eigen::Vector3d::Zero(), 0.0}}}};
  CHECK_THROWS_WITH(check::RobotChecker(bare, test_scene().scene, o),
                    Catch::Contains("l4") && Catch::Contains("covering"));
}

TEST_CASE("float tests: the verdicts of the double tests, also at 1e-12 of contact", "[check]") {
  // The float pass decides what it can with its slack and leaves the rest to the doubles:
  // every verdict must be the double one, in both modes, with and without a fine level,
  // and the spheres mode must be brute force's (away from contact, where brute force's own
  // rounding may differ).
  const RobotModel arm = test::capsule_arm(5);
  const RobotModel fine = test::capsule_arm(9);
  check::CheckerOptions with = options(0.01), without = options(0.01);
  without.float_tests = false;
  const check::RobotChecker floats(arm, test_scene().scene, with, &fine);
  const check::RobotChecker doubles(arm, test_scene().scene, without, &fine);
  const std::vector<double> q = near_contact(doubles, test::capsule_arm_configs(600, 11));
  REQUIRE(q.size() >= 8 * (600 + 2 * 100));
  for (Mode mode : {Mode::spheres, Mode::bounds}) {
    const std::vector<Verdict> a = run(floats, q, mode), b = run(doubles, q, mode);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
    INFO("mode " << int(mode));
    CHECK(differ == 0);
  }
  const std::vector<Verdict> v = run(floats, q, Mode::spheres);
  std::size_t disagree = 0;
  for (std::size_t i = 0; i < 600; ++i) {
    const Eigen::Map<const Eigen::VectorXd> qi(q.data() + 8 * i, 8);
    disagree += brute_force(arm, qi, 0.01) != (v[i] == Verdict::colliding);
  }
  CHECK(disagree == 0);
}

TEST_CASE("float tests: a chain of 30 joints, the verdicts of the double tests at 1e-12 of contact",
          "[check]") {
  // Forward kinematics runs in floats, and its distance from the double frames grows with
  // the chain's depth: the slack grows with it, so a long chain must still give the double
  // verdicts, in both modes, on both paths.
  const int n = 30;
  RobotModel snake;
  snake.name = "snake";
  snake.root_link = "s0";
  for (int i = 0; i <= n; ++i) {
    const test::CapsuleLink l{"s" + std::to_string(i), 0.02, 0.03, pose_of({0, 0, 0.04})};
    Link link;
    link.name = l.name;
    link.spheres.outer = test::capsule_set(l, 4, true);
    link.spheres.inner = test::capsule_set(l, 4, false);
    snake.links.push_back(link);
  }
  for (int i = 1; i <= n; ++i) {
    Joint j;
    j.name = "j" + std::to_string(i);
    j.type = JointType::kRevolute;
    j.parent = "s" + std::to_string(i - 1);
    j.child = "s" + std::to_string(i);
    j.origin = pose_of({0, 0, 0.08}, 0.0, 0.0, 0.7 * i);
    j.axis = i % 2 ? Eigen::Vector3d(1, 0, 0) : Eigen::Vector3d(0, 1, 0);
    j.limits = JointLimits{-0.6, 0.6, 2.0, 10.0};
    snake.joints.push_back(j);
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-0.6, 0.6);
  std::vector<double> q(std::size_t(400) * n);
  for (double& x : q) x = angle(rng);
  check::CheckerOptions with, without, scalar;
  with.margin = without.margin = scalar.margin = 0.01;
  without.float_tests = false;
  scalar.simd = check::Simd::scalar;
  const check::RobotChecker floats(snake, test_scene().scene, with);
  const check::RobotChecker doubles(snake, test_scene().scene, without);
  const check::RobotChecker floats_scalar(snake, test_scene().scene, scalar);
  q = near_contact(doubles, q);
  REQUIRE(q.size() >= std::size_t(n) * (400 + 2 * 50));  // contacts to bisect
  for (Mode mode : {Mode::spheres, Mode::bounds}) {
    const std::vector<Verdict> a = run(floats, q, mode), b = run(doubles, q, mode);
    std::size_t differ = 0, colliding = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      differ += a[i] != b[i];
      colliding += b[i] == Verdict::colliding;
    }
    INFO("mode " << int(mode));
    CHECK(differ == 0);
    CHECK(colliding > 0);
    CHECK(colliding < a.size());
    CHECK(run(floats_scalar, q, mode) == a);
  }
}

TEST_CASE("test order: the same verdicts and undecided pairs whatever order the tests run in",
          "[check]") {
  // The learnt order runs the tests that collide most often first (and, with a head, some
  // before the links' bounding spheres meet the scene); a lane leaves only by a certain
  // collision, so every order must give the default order's verdicts, in floats and in
  // doubles, on both paths, at 1e-12 of contact, in both modes, for edges too. (Here self
  // pairs collide in most configurations: the learnt order has a head.)
  const RobotModel arm = test::capsule_arm(5), fine = test::capsule_arm(9);
  // Eighteen checkers are built: in the sanitizer builds on a coarser scene grid, whose
  // distance field was most of each construction there (the same code).
  const std::size_t grid_cells =
      test::kSanitizerBuild ? std::size_t(1) << 17 : check::CheckerOptions{}.max_cells;
  for (const double margin : {0.0, 0.01}) {
    check::CheckerOptions fixed = options(margin);
    fixed.order_samples = 0;
    fixed.max_cells = grid_cells;
    const check::RobotChecker reference(arm, test_scene().scene, fixed, &fine);
    const std::vector<double> q = near_contact(reference, test::capsule_arm_configs(600, 18));
    const std::vector<Verdict> expected = run(reference, q, Mode::spheres);
    const std::vector<Verdict> expected_bounds = run(reference, q, Mode::bounds);
    std::size_t colliding = 0;
    for (Verdict v : expected) colliding += v == Verdict::colliding;
    INFO("margin " << margin << ": " << colliding << " of " << expected.size() << " colliding");
    CHECK(colliding > expected.size() / 10);
    CHECK(colliding < expected.size());
    const check::TestOrder none = reference.test_order();
    CHECK(none.head == 0);
    CHECK(none.probe.empty());
    REQUIRE(none.bounds_tests.size() == none.tests.size());
    for (std::size_t t = 0; t < none.tests.size(); ++t) {
      CHECK(none.tests[t] == t);
      CHECK(none.bounds_tests[t] == t);
    }
    for (const std::size_t samples : {std::size_t(8), std::size_t(300)})
      for (const bool floats : {true, false})
        for (const check::Simd simd : {check::Simd::automatic, check::Simd::scalar}) {
          check::CheckerOptions o = options(margin);
          o.order_samples = samples;
          o.float_tests = floats;
          o.simd = simd;
          o.max_cells = grid_cells;
          const check::RobotChecker checker(arm, test_scene().scene, o, &fine);
          INFO("samples " << samples << ", floats " << floats << ", scalar "
                          << (simd == check::Simd::scalar));
          const check::TestOrder learnt = checker.test_order();
          REQUIRE(learnt.tests.size() == none.tests.size());
          CHECK(std::is_permutation(learnt.tests.begin(), learnt.tests.end(), none.tests.begin()));
          REQUIRE(learnt.bounds_tests.size() == none.tests.size());
          CHECK(std::is_permutation(learnt.bounds_tests.begin(), learnt.bounds_tests.end(),
                                    none.tests.begin()));
          if (samples == 300) {
            CHECK(learnt.tests != none.tests);  // a learnt order to compare
            CHECK(learnt.head > 0);
            CHECK(learnt.bounds_tests != none.tests);
            // At 1 cm a probe proves most samples colliding: check()'s bounds batches run in
            // rounds, the open lanes regrouped (at margin 0 it proves too few to be kept).
            if (margin > 0.0) CHECK(!learnt.probe.empty());
          }
          CHECK(run(checker, q, Mode::spheres) == expected);
          CHECK(run(checker, q, Mode::spheres, 2) == expected);
          CHECK(run(checker, q, Mode::bounds) == expected_bounds);
          CHECK(run(checker, q, Mode::bounds, 2) == expected_bounds);
          std::vector<Verdict> a(100), b(100);
          checker.check_edges(q.data(), q.data() + 8, 100, 0.05, Mode::spheres, a.data(), 1);
          reference.check_edges(q.data(), q.data() + 8, 100, 0.05, Mode::spheres, b.data(), 1);
          CHECK(a == b);
        }
    // The bounds' undecided pairs too (each configuration's pairs are listed in the pairs'
    // own order, whatever order found them).
    check::CheckerOptions learnt = options(margin);
    learnt.order_samples = 300;
    const check::RobotChecker checker(arm, test_scene().scene, learnt, &fine);
    const std::size_t n = 400;
    std::vector<Verdict> va(n), vb(n);
    std::vector<std::vector<check::UndecidedPair>> pa(n), pb(n);
    checker.check_bounds(q.data(), n, va.data(), pa.data(), 1);
    reference.check_bounds(q.data(), n, vb.data(), pb.data(), 1);
    CHECK(va == vb);
    std::size_t undecided = 0;
    for (std::size_t i = 0; i < n; ++i) {
      undecided += va[i] == Verdict::undecided;
      REQUIRE(pa[i].size() == pb[i].size());
      for (std::size_t k = 0; k < pa[i].size(); ++k) {
        CHECK(pa[i][k].link == pb[i][k].link);
        CHECK(pa[i][k].other == pb[i][k].other);
        CHECK(pa[i][k].self == pb[i][k].self);
      }
    }
    CHECK(undecided > 10);
  }
}

TEST_CASE("pair tables: the verdicts of every pair tested, at 1e-12 of self-contact", "[check]") {
  // A self pair whose pose hangs on at most three joints is skipped in a configuration of a
  // free cell of its table (proven apart beyond the margin over the whole cell). Without a
  // scene every contact is a self pair's, and the configurations bisected to 1e-12 of
  // contact sit where a cell wrongly marked free would flip a verdict; tables of few cells
  // (coarse cells, large motion bounds) and of many (cells near contact) are compared with
  // no tables, on both paths, in floats and doubles, and against brute force.
  const RobotModel arm = test::capsule_arm(5), fine = test::capsule_arm(9);
  const check::Scene empty;
  for (const double margin : {0.0, 0.01}) {
    check::CheckerOptions none = options(margin);
    none.pair_table_cells = 0;
    const check::RobotChecker reference(arm, empty, none, &fine);
    CHECK(reference.pair_tables() == 0);
    const std::vector<double> q = near_contact(reference, test::capsule_arm_configs(1500, 21));
    const std::vector<Verdict> expected = run(reference, q, Mode::spheres);
    std::size_t colliding = 0;
    for (Verdict v : expected) colliding += v == Verdict::colliding;
    INFO("margin " << margin << ": " << colliding << " of " << expected.size() << " colliding");
    CHECK(colliding > expected.size() / 10);
    CHECK(colliding < expected.size() * 9 / 10);
    CHECK(q.size() >= 8 * (1500 + 2 * 100));
    std::size_t disagree = 0;
    for (std::size_t i = 0; i < 1500; ++i) {
      const Eigen::Map<const Eigen::VectorXd> qi(q.data() + 8 * i, 8);
      disagree += brute_force(arm, qi, margin, false) != (expected[i] == Verdict::colliding);
    }
    CHECK(disagree == 0);
    // Positions beyond the joints' limits (+-2.8) fall in no cell: blocks whose lanes mix
    // positions within and beyond them, every third coordinate stretched.
    std::vector<double> wide = q;
    std::size_t beyond = 0;
    for (std::size_t i = 0; i < wide.size(); i += 3) {
      wide[i] *= 4.0;
      beyond += std::abs(wide[i]) > 2.8;
    }
    CHECK(beyond > wide.size() / 10);
    const std::vector<Verdict> expected_wide = run(reference, wide, Mode::spheres);
    for (const std::size_t cells : {std::size_t(64), std::size_t(1) << 16})
      for (const bool floats : {true, false})
        for (const check::Simd simd : {check::Simd::automatic, check::Simd::scalar}) {
          check::CheckerOptions o = options(margin);
          o.pair_table_cells = cells;
          o.float_tests = floats;
          o.simd = simd;
          const check::RobotChecker checker(arm, empty, o, &fine);
          INFO("cells " << cells << ", floats " << floats << ", scalar "
                        << (simd == check::Simd::scalar) << ", tables " << checker.pair_tables()
                        << ", free " << checker.pair_tables_free());
          CHECK(checker.pair_tables() >= 5);
          CHECK(checker.pair_tables_free() > 0.1);
          CHECK(run(checker, q, Mode::spheres) == expected);
          CHECK(run(checker, q, Mode::spheres, 2) == expected);
          CHECK(run(checker, wide, Mode::spheres) == expected_wide);
          // The bounds mode does not use the tables.
          CHECK(run(checker, q, Mode::bounds) == run(reference, q, Mode::bounds));
          std::vector<Verdict> a(100), b(100);
          checker.check_edges(q.data(), q.data() + 8, 100, 0.05, Mode::spheres, a.data(), 1);
          reference.check_edges(q.data(), q.data() + 8, 100, 0.05, Mode::spheres, b.data(), 1);
          CHECK(a == b);
        }
  }
}
