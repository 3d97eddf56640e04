// CertifiedChecker (medspheres/fcl/certified_checker.h) against the exact answer: FCL's
// distance between every link mesh and every scene object, and between the meshes of
// every self pair, over seeded configurations of the capsule arm (check_fixtures.h), with
// a planner level of 4 and a fine level of 10 balls per link.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <tuple>

#include <fcl/fcl.h>
#include <octomap/octomap.h>
#include <catch2/catch.hpp>

#include "medspheres/fcl/certified_checker.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/point_triangle.h"
#include "support/check_fixtures.h"
#include "support/fcl_fixtures.h"
#include "support/temp_dir.h"

using namespace medspheres;
namespace mf = medspheres::fcl;
using check::Verdict;
using test::pose_of;

namespace {

// FCL's GJK, which answers a mesh against a primitive, stops at a tolerance of 1e-6:
// configurations whose exact distance lies that close to the margin are not judged.
constexpr double kGjkTolerance = 1e-6;

struct FclWorld {
  std::vector<std::shared_ptr<::fcl::CollisionObjectd>> objects;  // as the checker takes them
  std::vector<std::shared_ptr<::fcl::CollisionObjectd>> oracle;   // the octree as boxes
  std::map<std::string, std::shared_ptr<const mf::MeshModel>> meshes;

  FclWorld() {
    auto add = [&](std::shared_ptr<::fcl::CollisionGeometryd> g, const Eigen::Isometry3d& X) {
      objects.push_back(std::make_shared<::fcl::CollisionObjectd>(g, X));
      oracle.push_back(objects.back());
    };
    add(std::make_shared<::fcl::Boxd>(2, 2, 0.05), pose_of({0, 0, -0.125}));
    add(std::make_shared<::fcl::Boxd>(0.3, 0.2, 0.4), pose_of({0.5, 0.2, 0.3}, 0.2, 0.0, 0.5));
    add(std::make_shared<::fcl::Sphered>(0.12), pose_of({-0.4, 0.4, 0.6}));
    add(std::make_shared<::fcl::Capsuled>(0.06, 0.5), pose_of({0.1, -0.5, 0.5}, 0.7));
    add(std::make_shared<::fcl::Cylinderd>(0.08, 0.4), pose_of({-0.5, -0.3, 0.3}, 0.0, 0.9));
    add(test::make_bvh<::fcl::OBBRSSd>(make_icosphere(0.15, 2)), pose_of({0.3, 0.5, 0.9}));
    auto tree = std::make_shared<octomap::OcTree>(0.04);
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 200; ++i)
      tree->updateNode(octomap::point3d(float(0.6 + 0.2 * u(rng)), float(-0.4 + 0.8 * u(rng)),
                                        float(0.8 + 0.4 * u(rng))),
                       true);
    tree->updateInnerOccupancy();
    auto octree = std::make_shared<::fcl::OcTreed>(tree);
    objects.push_back(std::make_shared<::fcl::CollisionObjectd>(octree));
    for (const auto& b : octree->toBoxes())
      oracle.push_back(std::make_shared<::fcl::CollisionObjectd>(
          std::make_shared<::fcl::Boxd>(b[3], b[3], b[3]), pose_of({b[0], b[1], b[2]})));
    for (auto& o : objects) o->computeAABB();
    for (auto& o : oracle) o->computeAABB();
    for (const test::CapsuleLink& l : test::capsule_arm_links())
      meshes[l.name] = test::make_bvh<::fcl::OBBRSSd>(test::capsule_link_mesh(l));
  }

  std::vector<const ::fcl::CollisionObjectd*> scene() const {
    std::vector<const ::fcl::CollisionObjectd*> out;
    for (const auto& o : objects) out.push_back(o.get());
    return out;
  }
};

const FclWorld& world() {
  static const FclWorld w;
  return w;
}

// The distance from the mesh object a (a surface) to the sphere object b, brute force over
// the triangles (FCL's own sphere-to-mesh distance, fcl 0.7, leaves a triangle that meets
// the ball unset).
double mesh_to_sphere(const ::fcl::CollisionObjectd& a, const ::fcl::CollisionObjectd& b) {
  const auto& mesh = static_cast<const mf::MeshModel&>(*a.collisionGeometry());
  const Eigen::Vector3d c = a.getTransform().inverse() * b.getTranslation();
  double d = std::numeric_limits<double>::infinity();
  for (int t = 0; t < mesh.num_tris; ++t) {
    const ::fcl::Triangle& k = mesh.tri_indices[t];
    const Eigen::Vector3d q =
        closest_point_on_triangle(c, mesh.vertices[k[0]], mesh.vertices[k[1]], mesh.vertices[k[2]]);
    d = std::min(d, (q - c).norm());
  }
  return std::max(0.0, d - static_cast<const ::fcl::Sphered&>(*b.collisionGeometry()).radius);
}

double fcl_distance(const ::fcl::CollisionObjectd& a, const ::fcl::CollisionObjectd& b) {
  if (b.getNodeType() == ::fcl::GEOM_SPHERE && a.getObjectType() == ::fcl::OT_BVH)
    return mesh_to_sphere(a, b);
  ::fcl::DistanceRequestd request;
  ::fcl::DistanceResultd result;
  return std::max(0.0, ::fcl::distance(&a, &b, request, result));
}

// The smallest exact distance over the checker's pairs at q, or infinity when every pair's
// AABBs are more than `beyond` apart.
double exact_distance(const mf::CertifiedChecker& c, const RobotModel& arm, const double* q,
                      double beyond) {
  const KinematicTree tree(arm);
  const auto X = tree.link_poses(Eigen::Map<const Eigen::VectorXd>(q, 8));
  const std::vector<std::string>& links = c.spheres().links();
  std::vector<::fcl::CollisionObjectd> posed;
  for (const std::string& l : links)
    posed.emplace_back(std::const_pointer_cast<mf::MeshModel>(world().meshes.at(l)),
                       X[tree.link_index(l)]);
  double best = std::numeric_limits<double>::infinity();
  auto pair = [&](const ::fcl::CollisionObjectd& a, const ::fcl::CollisionObjectd& b) {
    if (a.getAABB().distance(b.getAABB()) <= beyond) best = std::min(best, fcl_distance(a, b));
  };
  for (auto& p : posed) {
    p.computeAABB();
    for (const auto& o : world().oracle) pair(p, *o);
  }
  for (const auto& [a, b] : c.spheres().self_pairs()) pair(posed[a], posed[b]);
  return best;
}

// The link's capsule mesh as an fcl::Convex: FCL's GJK measures the distance between the
// solids (0 when one lies wholly inside the other), where the meshes' BVH distance measures
// their surfaces.
std::shared_ptr<::fcl::Convexd> convex_link(const std::string& name) {
  for (const test::CapsuleLink& l : test::capsule_arm_links()) {
    if (l.name != name) continue;
    const TriangleMesh m = test::capsule_link_mesh(l);
    auto faces = std::make_shared<std::vector<int>>();
    for (const auto& t : m.triangles) faces->insert(faces->end(), {3, t[0], t[1], t[2]});
    return std::make_shared<::fcl::Convexd>(
        std::make_shared<const std::vector<Eigen::Vector3d>>(m.vertices),
        static_cast<int>(m.triangles.size()), faces);
  }
  return nullptr;
}

// The smallest distance between the solids of the checker's self pairs at q (convex_link).
double solid_self_distance(const mf::CertifiedChecker& c, const RobotModel& arm, const double* q) {
  const KinematicTree tree(arm);
  const auto X = tree.link_poses(Eigen::Map<const Eigen::VectorXd>(q, 8));
  const std::vector<std::string>& links = c.spheres().links();
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [a, b] : c.spheres().self_pairs()) {
    const ::fcl::CollisionObjectd oa(convex_link(links[a]), X[tree.link_index(links[a])]);
    const ::fcl::CollisionObjectd ob(convex_link(links[b]), X[tree.link_index(links[b])]);
    best = std::min(best, fcl_distance(oa, ob));
  }
  return best;
}

// The witnesses' tests' fallback: the sphere trees \p trees (finer than the bounds' inner
// sets, whose witnesses would have decided already) and witnesses learnt from 400
// configurations.
mf::FallbackOptions witness_fallback(const RobotModel& trees) {
  mf::FallbackOptions fallback;
  fallback.trees = &trees;
  fallback.order.samples = 400;
  fallback.order.seed = 5;
  return fallback;
}

check::CheckerOptions options(double margin) {
  check::CheckerOptions o;
  o.margin = margin;
  o.disabled = {{"tool", "l7"}};
  return o;
}

}  // namespace

TEST_CASE("certified checker: no missed collision, no false alarm, against FCL's exact meshes",
          "[check][fcl]") {
  const RobotModel arm = test::capsule_arm(4), fine = test::capsule_arm(10);
  const double margin = 0.01;
  const mf::CertifiedChecker checker(arm, &fine, world().meshes, world().scene(), options(margin));
  const std::vector<double> q = test::capsule_arm_configs(300, 21);
  std::vector<Verdict> v(300);
  mf::FallbackStats stats;
  checker.check(q.data(), v.size(), v.data(), 1, &stats);
  std::size_t missed = 0, alarms = 0, undecided = 0, colliding = 0, near = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double d = exact_distance(checker, arm, q.data() + 8 * i, margin + 1e-3);
    undecided += v[i] == Verdict::undecided;
    if (std::abs(d - margin) < kGjkTolerance) {
      ++near;
      continue;
    }
    colliding += d <= margin;
    missed += d <= margin && v[i] == Verdict::free;
    alarms += d > margin && v[i] == Verdict::colliding;
  }
  CHECK(missed == 0);
  CHECK(alarms == 0);
  CHECK(undecided == 0);
  CHECK(near <= 3);
  CHECK(colliding > 30);
  CHECK(colliding < 270);
  // The meshes were needed somewhere, so the fallback was exercised.
  CHECK(stats.configurations > 0);
  CHECK(stats.pairs >= stats.configurations);
}

TEST_CASE("certified checker: thread counts and edges agree with one configuration at a time",
          "[check][fcl]") {
  const RobotModel arm = test::capsule_arm(4), fine = test::capsule_arm(10);
  const mf::CertifiedChecker checker(arm, &fine, world().meshes, world().scene(), options(0.0));
  const std::vector<double> q = test::capsule_arm_configs(81, 22);
  std::vector<Verdict> one(81), two(81);
  checker.check(q.data(), 81, one.data(), 1);
  checker.check(q.data(), 81, two.data(), 2);
  CHECK(one == two);
  for (std::size_t i = 0; i < 81; ++i) CHECK(checker.check(q.data() + 8 * i) == one[i]);
  std::vector<Verdict> edges(80);
  checker.check_edges(q.data(), q.data() + 8, 80, 0.1, edges.data(), 2);
  std::size_t free = 0;
  std::vector<double> at(8);
  for (std::size_t e = 0; e < 80; ++e) {
    const double* q0 = q.data() + 8 * e;
    const double* q1 = q0 + 8;
    const std::size_t n = checker.spheres().edge_steps(q0, q1, 0.1);
    Verdict truth = Verdict::free;
    for (std::size_t k = 0; k <= n && truth != Verdict::colliding; ++k) {
      for (int j = 0; j < 8; ++j) at[j] = q0[j] + double(k) / double(n) * (q1[j] - q0[j]);
      const Verdict s = checker.check(at.data());
      if (s != Verdict::free) truth = s;
    }
    CHECK(edges[e] == truth);
    free += truth == Verdict::free;
  }
  CHECK(free > 0);
}

TEST_CASE("certified checker: a covering set without a certificate is refused", "[check][fcl]") {
  RobotModel arm = test::capsule_arm(4);
  arm.links[3].spheres.outer_certificate_json.clear();
  CHECK_THROWS_WITH(mf::CertifiedChecker(arm, nullptr, world().meshes, world().scene()),
                    Catch::Contains("l3"));
}

TEST_CASE("certified checker: finer sphere trees give the same certified verdicts, fewer meshes",
          "[check][fcl]") {
  const RobotModel arm = test::capsule_arm(4), fine = test::capsule_arm(10);
  const RobotModel trees = test::capsule_arm(24);
  const double margin = 0.01;
  const mf::CertifiedChecker plain(arm, &fine, world().meshes, world().scene(), options(margin));
  mf::FallbackOptions fallback;
  fallback.trees = &trees;
  const mf::CertifiedChecker finer(arm, &fine, world().meshes, world().scene(), options(margin),
                                   fallback);
  const std::vector<double> q = test::capsule_arm_configs(300, 21);
  std::vector<Verdict> a(300), b(300);
  mf::FallbackStats sa, sb;
  plain.check(q.data(), a.size(), a.data(), 1, &sa);
  finer.check(q.data(), b.size(), b.data(), 1, &sb);
  // Both are certified and decide every configuration, so they agree (and the first test
  // case holds the plain checker to FCL's exact answer).
  CHECK(std::count(b.begin(), b.end(), Verdict::undecided) == 0);
  CHECK(a == b);
  CHECK(sb.configurations == sa.configurations);
  CHECK(sb.configurations > 0);
  CHECK(sb.meshes < sa.meshes);
  RobotModel other = trees;
  other.joints[2].name = "renamed";
  fallback.trees = &other;
  CHECK_THROWS_WITH(
      mf::CertifiedChecker(arm, &fine, world().meshes, world().scene(), options(margin), fallback),
      Catch::Contains("joints differ"));
}

TEST_CASE("certified checker: a learnt pair order and witnesses change no verdict",
          "[check][fcl]") {
  const RobotModel arm = test::capsule_arm(4), fine = test::capsule_arm(10);
  const double margin = 0.01;
  const mf::CertifiedChecker plain(arm, &fine, world().meshes, world().scene(), options(margin));
  mf::FallbackOptions fallback;
  fallback.order.samples = 400;
  fallback.order.margin = margin;
  fallback.kernel_witnesses = false;  // the fallback's witnesses (the kernel's: below)
  const mf::CertifiedChecker learnt(arm, &fine, world().meshes, world().scene(), options(margin),
                                    fallback);
  REQUIRE(!learnt.fallback().witnesses().empty());
  const std::vector<double> q = test::capsule_arm_configs(300, 23);
  std::vector<Verdict> a(300), b(300);
  mf::FallbackStats sa, sb;
  plain.check(q.data(), a.size(), a.data(), 1, &sa);
  learnt.check(q.data(), b.size(), b.data(), 1, &sb);
  CHECK(a == b);
  CHECK(sb.configurations == sa.configurations);
  CHECK(sb.configurations > 0);
  // The witnesses settle some configurations before any pair's walk.
  CHECK(sb.pairs < sa.pairs);
  // The order is learnt at the checker's margin, whatever order.margin says: the same
  // witnesses as RobotBounds learns at that margin, and not those of margin 0.
  fallback.order.margin = 0.0;
  const mf::CertifiedChecker unset(arm, &fine, world().meshes, world().scene(), options(margin),
                                   fallback);
  fallback.order.margin = margin;
  const mf::RobotBounds at_margin(fine, world().meshes, options(margin).disabled, {},
                                  fallback.order);
  fallback.order.margin = 0.0;
  const mf::RobotBounds at_zero(fine, world().meshes, options(margin).disabled, {}, fallback.order);
  CHECK(unset.fallback().witnesses().size() == at_margin.witnesses().size());
  CHECK(at_zero.witnesses().size() != at_margin.witnesses().size());
}

TEST_CASE(
    "certified checker: a witness settles only configurations the exact meshes find colliding",
    "[check][fcl]") {
  const RobotModel arm = test::capsule_arm(4), fine = test::capsule_arm(10);
  // Witnesses finer than the bounds' inner sets (those would have decided already).
  const RobotModel trees = test::capsule_arm(24);
  const double margin = 0.01;
  constexpr std::size_t kConfigs = 1500;
  mf::FallbackOptions fallback = witness_fallback(trees);
  fallback.kernel_witnesses = false;  // the fallback tests them (the kernel's: below)
  // No scene: every fallback is a self pair's, where the witnesses are.
  const mf::CertifiedChecker learnt(arm, &fine, world().meshes, {}, options(margin), fallback);
  const std::vector<double> q = test::capsule_arm_configs(kConfigs, 24);
  std::size_t witnessed = 0, fallbacks = 0;
  for (std::size_t i = 0; i < kConfigs; ++i) {
    mf::FallbackStats s;
    const Verdict v = learnt.check(q.data() + 8 * i, &s);
    fallbacks += s.configurations;
    if (s.witnessed == 0) continue;
    ++witnessed;
    CHECK(v == Verdict::colliding);
    CHECK(s.pairs == 0);  // no pair walked
    CHECK(solid_self_distance(learnt, arm, q.data() + 8 * i) <= margin + kGjkTolerance);
  }
  INFO("witnesses " << learnt.fallback().witnesses().size() << ", fallbacks " << fallbacks);
  CHECK(witnessed > 0);
  CHECK(witnessed < fallbacks);
  // The batch and the edges agree with one configuration at a time.
  std::vector<Verdict> batch(kConfigs);
  mf::FallbackStats s;
  learnt.check(q.data(), kConfigs, batch.data(), 2, &s);
  CHECK(s.witnessed == witnessed);
  for (std::size_t i = 0; i < kConfigs; ++i) CHECK(learnt.check(q.data() + 8 * i) == batch[i]);
  std::vector<Verdict> edges(kConfigs - 1);
  mf::FallbackStats se;
  learnt.check_edges(q.data(), q.data() + 8, kConfigs - 1, 0.1, edges.data(), 2, &se);
  CHECK(se.witnessed > 0);
  std::vector<double> at(8);
  for (std::size_t e = 0; e < kConfigs - 1; ++e) {
    const double* q0 = q.data() + 8 * e;
    const std::size_t n = learnt.spheres().edge_steps(q0, q0 + 8, 0.1);
    Verdict truth = Verdict::free;
    for (std::size_t k = 0; k <= n && truth != Verdict::colliding; ++k) {
      for (int j = 0; j < 8; ++j) at[j] = q0[j] + double(k) / double(n) * (q0[8 + j] - q0[j]);
      const Verdict v = learnt.check(at.data());
      if (v != Verdict::free) truth = v;
    }
    CHECK(edges[e] == truth);
  }
}

TEST_CASE("certified checker: every witness that holds is a pair of solids within the margin",
          "[check][fcl]") {
  const RobotModel arm = test::capsule_arm(4), fine = test::capsule_arm(10);
  const RobotModel trees = test::capsule_arm(24);
  const double margin = 0.01;
  mf::FallbackOptions fallback = witness_fallback(trees);
  const mf::CertifiedChecker learnt(arm, &fine, world().meshes, {}, options(margin), fallback);
  const mf::RobotBounds& rb = learnt.fallback();
  REQUIRE(!rb.witnesses().empty());
  const std::vector<double> q = test::capsule_arm_configs(1500, 25);
  std::size_t held = 0;
  for (std::size_t i = 0; i < 1500; ++i) {
    const auto X = rb.poses(Eigen::Map<const Eigen::VectorXd>(q.data() + 8 * i, 8),
                            Eigen::Isometry3d::Identity());
    for (const mf::SelfWitness& w : rb.witnesses()) {
      if (!mf::witness_holds(w, X, margin)) continue;
      ++held;
      const ::fcl::CollisionObjectd a(convex_link(rb.geometries()[w.a].link()), X[w.a]);
      const ::fcl::CollisionObjectd b(convex_link(rb.geometries()[w.b].link()), X[w.b]);
      INFO(rb.geometries()[w.a].link() << " " << rb.geometries()[w.b].link());
      CHECK(fcl_distance(a, b) <= margin + kGjkTolerance);
    }
  }
  CHECK(held > 20);
}

TEST_CASE("certified checker: the witnesses in the kernel prove only collisions of the solids",
          "[check][fcl]") {
  const RobotModel arm = test::capsule_arm(4), fine = test::capsule_arm(10);
  const RobotModel trees = test::capsule_arm(24);
  const double margin = 0.01;
  mf::FallbackOptions fallback = witness_fallback(trees);
  check::CheckerOptions o = options(margin);
  const mf::CertifiedChecker learnt(arm, &fine, world().meshes, {}, o, fallback);
  o.simd = check::Simd::scalar;
  const mf::CertifiedChecker scalar(arm, &fine, world().meshes, {}, o, fallback);
  fallback.kernel_witnesses = false;
  const mf::CertifiedChecker apart(arm, &fine, world().meshes, {}, options(margin), fallback);
  REQUIRE(!learnt.fallback().witnesses().empty());
  constexpr std::size_t kConfigs = 1500;
  const std::vector<double> q = test::capsule_arm_configs(kConfigs, 26);
  std::vector<Verdict> kb(kConfigs), ab(kConfigs), sb(kConfigs);
  learnt.spheres().check(q.data(), kConfigs, check::Mode::bounds, kb.data(), 1);
  apart.spheres().check(q.data(), kConfigs, check::Mode::bounds, ab.data(), 1);
  scalar.spheres().check(q.data(), kConfigs, check::Mode::bounds, sb.data(), 2);
  CHECK(sb == kb);
  // Each lane the witnesses' points prove colliding (and the planner's and fine sets do
  // not) collides by the exact answer: the solids' distance (FCL's GJK on the convex
  // capsules). No scene: the witnesses are self pairs' points.
  std::size_t proved = 0;
  for (std::size_t i = 0; i < kConfigs; ++i) {
    if (ab[i] == Verdict::colliding) CHECK(kb[i] == Verdict::colliding);
    CHECK((kb[i] == Verdict::free) == (ab[i] == Verdict::free));
    if (kb[i] != Verdict::colliding || ab[i] == Verdict::colliding) continue;
    ++proved;
    const double* qi = q.data() + 8 * i;
    const double d = solid_self_distance(learnt, arm, qi);
    INFO("configuration " << i << ": distance " << d);
    CHECK(d <= margin + kGjkTolerance);
  }
  INFO("proved by the witnesses' points " << proved);
  CHECK(proved > 5);
  // The certified verdicts are the same, with fewer configurations for the fallback, on
  // either path and any thread count.
  std::vector<Verdict> k(kConfigs), a(kConfigs), s(kConfigs);
  mf::FallbackStats sk, sa;
  learnt.check(q.data(), kConfigs, k.data(), 1, &sk);
  apart.check(q.data(), kConfigs, a.data(), 2, &sa);
  scalar.check(q.data(), kConfigs, s.data(), 2);
  CHECK(k == a);
  CHECK(s == k);
  CHECK(std::count(k.begin(), k.end(), Verdict::undecided) == 0);
  CHECK(sk.configurations + proved == sa.configurations);
}

TEST_CASE("certified checker: joint-space tables for the pairs two revolute joints apart",
          "[check][fcl]") {
  const RobotModel arm = test::capsule_arm(4), fine = test::capsule_arm(10);
  mf::FallbackOptions fallback;
  fallback.table_cells = 4;
  const mf::CertifiedChecker tabled(arm, &fine, world().meshes, {}, options(0.01), fallback);
  const mf::RobotBounds& rb = tabled.fallback();
  auto table = [&](const std::string& a, const std::string& b) {
    std::size_t ga = 0, gb = 0;
    while (rb.geometries()[ga].link() != a) ++ga;
    while (rb.geometries()[gb].link() != b) ++gb;
    return tabled.table(ga, gb);
  };
  REQUIRE(table("l1", "l3") != nullptr);
  CHECK(table("l1", "l3")->cells() <= 4);
  CHECK(table("l6", "tool") != nullptr);        // one revolute joint, then fixed ones
  CHECK(table("l0", "l4") == nullptr);          // four joints apart
  CHECK(table("tool", "finger_a") == nullptr);  // adjacent: not a self pair
  CHECK(table("l6", "finger_a") == nullptr);    // a prismatic joint on the path
  // table_pairs: tables for the first pairs of the order only, the same pairs as without it.
  const auto& pairs = rb.self_pairs();
  std::size_t first = 0;  // pairs up to and including the second that takes a table
  for (std::size_t taken = 0; first < pairs.size() && taken < 2; ++first)
    taken += tabled.table(pairs[first].first, pairs[first].second) != nullptr;
  REQUIRE(first < pairs.size());
  fallback.table_pairs = first;
  const mf::CertifiedChecker some(arm, &fine, world().meshes, {}, options(0.01), fallback);
  REQUIRE(some.fallback().self_pairs() == pairs);
  std::size_t tables = 0, beyond = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const bool has = some.table(pairs[k].first, pairs[k].second) != nullptr;
    tables += has;
    if (k < first)
      CHECK(has == (tabled.table(pairs[k].first, pairs[k].second) != nullptr));
    else
      beyond += tabled.table(pairs[k].first, pairs[k].second) != nullptr && !has;
  }
  CHECK(tables == 2);
  CHECK(beyond > 0);  // pairs that take a table left without one
}

TEST_CASE("certified checker: with_scene gives a new checker's verdicts, its robot's parts shared",
          "[check][fcl]") {
  const RobotModel arm = test::capsule_arm(4), fine = test::capsule_arm(10);
  const double margin = 0.01;
  mf::FallbackOptions fallback;
  fallback.order.samples = 400;
  fallback.table_cells = 64;
  // Built on no scene (no octree: the links' cells are made when a scene brings one), then
  // moved to the world of the other tests, and back.
  const mf::CertifiedChecker empty(arm, &fine, world().meshes, {}, options(margin), fallback);
  const mf::CertifiedChecker moved = empty.with_scene(world().scene());
  const mf::CertifiedChecker anew(arm, &fine, world().meshes, world().scene(), options(margin),
                                  fallback);
  const mf::CertifiedChecker back = moved.with_scene({});
  CHECK(&moved.fallback() == &empty.fallback());
  CHECK(&back.fallback() == &empty.fallback());
  std::size_t shared_tables = 0;
  for (const auto& [a, b] : empty.fallback().self_pairs()) {
    CHECK(moved.table(a, b) == empty.table(a, b));
    shared_tables += empty.table(a, b) != nullptr;
  }
  CHECK(shared_tables > 0);
  const std::vector<double> q = test::capsule_arm_configs(300, 27);
  std::vector<Verdict> v_moved(300), v_anew(300), v_empty(300), v_back(300);
  mf::FallbackStats s_moved, s_anew, s_empty, s_back;
  moved.check(q.data(), 300, v_moved.data(), 2, &s_moved);
  anew.check(q.data(), 300, v_anew.data(), 2, &s_anew);
  empty.check(q.data(), 300, v_empty.data(), 1, &s_empty);
  back.check(q.data(), 300, v_back.data(), 1, &s_back);
  CHECK(v_moved == v_anew);
  CHECK(v_back == v_empty);
  CHECK(v_moved != v_empty);  // the world's objects matter
  // The same path through the fallback: the octree's cells, planes and meshes alike.
  CHECK(s_moved.configurations == s_anew.configurations);
  CHECK(s_moved.pairs == s_anew.pairs);
  CHECK(s_moved.planes == s_anew.planes);
  CHECK(s_moved.meshes == s_anew.meshes);
  CHECK(s_moved.meshes > 0);
  CHECK(s_back.meshes == s_empty.meshes);
  // And against the exact meshes.
  std::size_t missed = 0, alarms = 0;
  for (std::size_t i = 0; i < 300; ++i) {
    const double d = exact_distance(moved, arm, q.data() + 8 * i, margin + 1e-3);
    if (std::abs(d - margin) < kGjkTolerance) continue;
    missed += d <= margin && v_moved[i] == Verdict::free;
    alarms += d > margin && v_moved[i] == Verdict::colliding;
  }
  CHECK(missed == 0);
  CHECK(alarms == 0);
  std::vector<Verdict> e_moved(40), e_anew(40);
  CHECK(moved.check_edges(q.data(), q.data() + 8, 40, 0.1, e_moved.data(), 2) ==
        anew.check_edges(q.data(), q.data() + 8, 40, 0.1, e_anew.data(), 2));
  CHECK(e_moved == e_anew);
}

// A folding chain: a base, a short middle link and a tip of half length tip_half that folds
// back onto the base (two revolute joints apart: a pair PairJointTable takes), with the
// capsule arm's closed-form sets and meshes.
std::vector<test::CapsuleLink> fold_links(double tip_half) {
  return {{"base", 0.03, 0.1, pose_of({0, 0, 0.1})},
          {"mid", 0.02, 0.04, pose_of({0, 0, 0.06})},
          {"tip", 0.03, tip_half, pose_of({0, 0, tip_half})}};
}

RobotModel fold_chain(int k, double tip_half) {
  RobotModel m;
  m.name = "fold";
  m.root_link = "base";
  for (const test::CapsuleLink& l : fold_links(tip_half)) {
    Link link;
    link.name = l.name;
    link.spheres.outer = test::capsule_set(l, k, true);
    link.spheres.inner = test::capsule_set(l, k, false);
    link.spheres.outer_certificate_json = R"({"certified": true, "method": "closed form"})";
    m.links.push_back(link);
  }
  for (const auto& [name, parent, child, z] :
       {std::tuple{"j1", "base", "mid", 0.2}, std::tuple{"j2", "mid", "tip", 0.12}}) {
    Joint j;
    j.name = name;
    j.type = JointType::kRevolute;
    j.parent = parent;
    j.child = child;
    j.origin = pose_of({0, 0, z});
    j.axis = Eigen::Vector3d(0, 1, 0);
    j.limits = JointLimits{-2.8, 2.8, 2.0, 10.0};
    m.joints.push_back(j);
  }
  return m;
}

// The fold chain of half tip length tip_half with its meshes, certified checkers without
// tables (plain) and with a table of at most `cells` cells on its one self pair (tabled),
// and FCL's distance between that pair's meshes.
struct FoldTable {
  FoldTable(double tip_half, std::size_t cells)
      : planner(fold_chain(4, tip_half)), fine(fold_chain(10, tip_half)), tree(fine) {
    for (const test::CapsuleLink& l : fold_links(tip_half))
      meshes[l.name] = test::make_bvh<::fcl::OBBRSSd>(test::capsule_link_mesh(l));
    o.margin = 0.01;
    mf::FallbackOptions fallback;
    fallback.table_cells = cells;
    plain = std::make_unique<mf::CertifiedChecker>(
        planner, &fine, meshes, std::vector<const ::fcl::CollisionObjectd*>{}, o);
    tabled = std::make_unique<mf::CertifiedChecker>(
        planner, &fine, meshes, std::vector<const ::fcl::CollisionObjectd*>{}, o, fallback);
    REQUIRE(tabled->fallback().self_pairs().size() == 1);
    std::tie(ga, gb) = tabled->fallback().self_pairs()[0];
  }
  const mf::PairJointTable* table() const { return tabled->table(ga, gb); }
  double distance(const double* q) const {
    const auto X = tree.link_poses(Eigen::Map<const Eigen::VectorXd>(q, 2));
    auto mesh = [&](std::size_t g) {
      const std::string& link = tabled->fallback().geometries()[g].link();
      return ::fcl::CollisionObjectd(std::const_pointer_cast<mf::MeshModel>(meshes.at(link)),
                                     X[tree.link_index(link)]);
    };
    return fcl_distance(mesh(ga), mesh(gb));
  }

  RobotModel planner, fine;
  KinematicTree tree;
  std::map<std::string, std::shared_ptr<const mf::MeshModel>> meshes;
  check::CheckerOptions o;
  std::unique_ptr<mf::CertifiedChecker> plain, tabled;
  std::size_t ga = 0, gb = 0;
};

// A long tip (0.25) comes close to the base along its length and far from its joint, where
// the table's levers (the shells of the tip far from the joint) weigh most.
TEST_CASE("certified checker: a joint-space table agrees with FCL's meshes, near contact too",
          "[check][fcl]") {
  const double tip_half = GENERATE(0.1, 0.25);
  INFO("tip half length " << tip_half);
  const FoldTable fold(tip_half, tip_half < 0.2 ? 2048 : 8192);
  const mf::CertifiedChecker &plain = *fold.plain, &tabled = *fold.tabled;
  const mf::PairJointTable* table = fold.table();
  REQUIRE(table != nullptr);
  CHECK(plain.table(fold.ga, fold.gb) == nullptr);
  // Seeded configurations, and as many bisected to contact between a free and a colliding one.
  std::mt19937 rng(27);
  std::uniform_real_distribution<double> u(-2.8, 2.8);
  std::vector<double> q;
  for (int i = 0; i < 2000; ++i) q.insert(q.end(), {u(rng), u(rng)});
  std::vector<Verdict> v(2000);
  plain.check(q.data(), 2000, v.data());
  for (std::size_t i = 0; i + 1 < 2000; ++i) {
    if (v[i] == v[i + 1]) continue;
    double lo = 0.0, hi = 1.0;  // lo on v[i]'s side
    for (int step = 0; step < 30; ++step) {
      const double t = 0.5 * (lo + hi);
      const double at[2] = {q[2 * i] + t * (q[2 * i + 2] - q[2 * i]),
                            q[2 * i + 1] + t * (q[2 * i + 3] - q[2 * i + 1])};
      (plain.check(at) == v[i] ? lo : hi) = t;
    }
    // The contact, and a point nine tenths of the way to it from the free end.
    const double contact = v[i] == Verdict::free ? lo : hi;
    for (double t : {contact, v[i] == Verdict::free ? 0.9 * contact : 1.0 - 0.9 * (1.0 - contact)})
      q.insert(q.end(), {q[2 * i] + t * (q[2 * i + 2] - q[2 * i]),
                         q[2 * i + 1] + t * (q[2 * i + 3] - q[2 * i + 1])});
  }
  const std::size_t n = q.size() / 2;
  REQUIRE(n > 2400);
  std::size_t free = 0, near_free = 0;
  const double margin = fold.o.margin;
  for (std::size_t i = 0; i < n; ++i) {
    const BoundsVerdict t = table->verdict(q.data() + 2 * i);
    if (t == BoundsVerdict::undecided) continue;
    const double d = fold.distance(q.data() + 2 * i);
    INFO("configuration " << i << ": distance " << d);
    CHECK((t == BoundsVerdict::free ? d > margin - kGjkTolerance : d <= margin + kGjkTolerance));
    free += t == BoundsVerdict::free;
    near_free += t == BoundsVerdict::free && i >= 2000;
  }
  CHECK(free > 500);
  CHECK(near_free > 0);
  std::vector<Verdict> a(n), b(n);
  mf::FallbackStats sa, sb;
  plain.check(q.data(), n, a.data(), 1, &sa);
  tabled.check(q.data(), n, b.data(), 2, &sb);
  CHECK(a == b);
  CHECK(std::count(b.begin(), b.end(), Verdict::undecided) == 0);
  CHECK(sb.meshes <= sa.meshes);
  // The table's colliding cells settle configurations before the bounds, in a batch and
  // one at a time alike.
  CHECK(sb.table_first > 50);
  CHECK(sa.table_first == 0);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < n; i += 7) differ += tabled.check(q.data() + 2 * i) != b[i];
  CHECK(differ == 0);
}

// The levers' bound where it is tightest: around contacts of the long-tipped fold chain
// (bisected by FCL's distance between a free and a colliding configuration), configurations
// within 0.02 of each joint; every one the table calls free is beyond the margin by FCL's
// distance, every one it calls colliding within it.
TEST_CASE("certified checker: a joint-space table's cells next to contact, by FCL's meshes",
          "[check][fcl]") {
  const FoldTable fold(0.25, 8192);
  const mf::PairJointTable* table = fold.table();
  REQUIRE(table != nullptr);
  const double margin = fold.o.margin;
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-2.8, 2.8), near(-0.1, 0.1);
  std::size_t free = 0, colliding = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const double a[2] = {u(rng), u(rng)}, b[2] = {u(rng), u(rng)};
    const bool a_free = fold.distance(a) > margin;
    if (a_free == (fold.distance(b) > margin)) continue;
    double lo = 0.0, hi = 1.0;  // lo on a's side
    for (int step = 0; step < 40; ++step) {
      const double t = 0.5 * (lo + hi),
                   at[2] = {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
      ((fold.distance(at) > margin) == a_free ? lo : hi) = t;
    }
    for (int k = 0; k < 16; ++k) {
      double at[2];
      for (int j = 0; j < 2; ++j)
        at[j] = std::clamp(a[j] + lo * (b[j] - a[j]) + near(rng), -2.8, 2.8);
      const BoundsVerdict v = table->verdict(at);
      if (v == BoundsVerdict::undecided) continue;
      const double d = fold.distance(at);
      INFO("trial " << trial << ": (" << at[0] << ", " << at[1] << "), distance " << d);
      CHECK((v == BoundsVerdict::free ? d > margin - kGjkTolerance : d <= margin + kGjkTolerance));
      (v == BoundsVerdict::free ? free : colliding) += 1;
    }
  }
  CHECK(free > 30);
  CHECK(colliding > 30);
}

// Bad input with the tables first: every row is checked before the tables settle any, and
// the row at fault is named by its index in the batch.
TEST_CASE("certified checker: with tables first, a bad configuration is named by its row",
          "[check][fcl]") {
  const FoldTable fold(0.1, 2048);
  std::mt19937 rng(43);
  std::uniform_real_distribution<double> u(-2.8, 2.8);
  std::vector<double> q;
  for (int i = 0; i < 2000; ++i) q.insert(q.end(), {u(rng), u(rng)});
  std::vector<Verdict> v(2000);
  mf::FallbackStats stats;
  fold.tabled->check(q.data(), 2000, v.data(), 1, &stats);
  REQUIRE(stats.table_first > 20);
  q[2 * 1999 + 1] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(fold.tabled->check(q.data(), 2000, v.data()),
                    Catch::Contains("configuration 1999") && Catch::Contains("not finite"));
  CHECK_THROWS_WITH(fold.tabled->check(q.data() + 2 * 1999), Catch::Contains("not finite"));
  // A thread count out of range is refused before any work, with or without tables.
  q[2 * 1999 + 1] = 0.0;
  for (const int threads : {-1, 100000})
    for (const mf::CertifiedChecker* c : {fold.tabled.get(), fold.plain.get()}) {
      CHECK_THROWS_WITH(c->check(q.data(), 2000, v.data(), threads),
                        Catch::Contains("threads must be in [0, 1024]"));
      CHECK_THROWS_WITH(c->check_edges(q.data(), q.data() + 2, 1, 0.1, v.data(), threads),
                        Catch::Contains("threads must be in [0, 1024]"));
    }
  // An edge whose resolution would check more than kMaxEdgeSteps configurations is refused
  // by its index before any work, with two threads too (at 1e-12 these edges would have run
  // for days).
  for (const mf::CertifiedChecker* c : {fold.tabled.get(), fold.plain.get()})
    CHECK_THROWS_WITH(c->check_edges(q.data(), q.data() + 2, 3, 1e-12, v.data(), 2),
                      Catch::Contains("edge 0") && Catch::Contains("configurations on it"));
}

// The tables' store: a checker built again reads the table it baked (the same cells); a
// table of another margin or budget gets a file of its own; a damaged file is baked again
// and replaced, never read; a store that cannot be a folder, or cannot be written, is refused
// by name.
TEST_CASE("certified checker: joint-space tables kept in a store and read back", "[check][fcl]") {
  const FoldTable fold(0.25, 512);
  const test::TempDir dir;
  const std::string folder = dir.file("tables");
  auto tabled = [&](double margin, std::size_t cells) {
    check::CheckerOptions o = fold.o;
    o.margin = margin;
    mf::FallbackOptions f;
    f.table_cells = cells;
    f.table_store = folder;
    return std::make_unique<const mf::CertifiedChecker>(
        fold.planner, &fold.fine, fold.meshes, std::vector<const ::fcl::CollisionObjectd*>{}, o, f);
  };
  auto files = [&] {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(folder))
      out.push_back(e.path().string());
    return out;
  };
  const auto baked = tabled(0.01, 512);
  const mf::PairJointTable* t0 = baked->table(fold.ga, fold.gb);
  REQUIRE(t0 != nullptr);
  CHECK_FALSE(t0->stored());
  REQUIRE(files().size() == 1);
  const std::string file = files()[0];
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(-2.9, 2.9);  // beyond the limits too
  std::vector<double> q;
  for (int i = 0; i < 4000; ++i) q.insert(q.end(), {u(rng), u(rng)});
  auto same_as_baked = [&](const mf::PairJointTable& t) {
    CHECK(t.cells() == t0->cells());
    CHECK(t.free_cells() == t0->free_cells());
    CHECK(t.colliding_cells() == t0->colliding_cells());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < 4000; ++i)
      differ += t.verdict(q.data() + 2 * i) != t0->verdict(q.data() + 2 * i);
    CHECK(differ == 0);
  };
  // Without a store, the same table.
  same_as_baked(*fold.tabled->table(fold.ga, fold.gb));
  {
    const auto read = tabled(0.01, 512);
    REQUIRE(read->table(fold.ga, fold.gb)->stored());
    same_as_baked(*read->table(fold.ga, fold.gb));
  }
  // Damaged files: cut short, not CBOR, a map of other keys, and one byte changed at places
  // spread over the file.
  const std::string bytes = test::read_file(file);
  REQUIRE(bytes.size() > 1000);
  std::vector<std::string> damaged{bytes.substr(0, bytes.size() / 2), "not a table",
                                   std::string("\xA1\x66"
                                               "format\x01",
                                               9)};
  for (std::size_t at = 0; at < bytes.size(); at += bytes.size() / 16 + 1) {
    damaged.push_back(bytes);
    damaged.back()[at] = char(damaged.back()[at] ^ 0x10);
  }
  for (std::size_t k = 0; k < damaged.size(); ++k) {
    INFO("damaged file " << k);
    dir.write("tables/" + std::filesystem::path(file).filename().string(), damaged[k]);
    const auto again = tabled(0.01, 512);
    CHECK_FALSE(again->table(fold.ga, fold.gb)->stored());
    same_as_baked(*again->table(fold.ga, fold.gb));
    CHECK(test::read_file(file) == bytes);  // replaced by the bake
  }
  // Another margin, another budget: files of their own.
  CHECK_FALSE(tabled(0.02, 512)->table(fold.ga, fold.gb)->stored());
  CHECK_FALSE(tabled(0.01, 256)->table(fold.ga, fold.gb)->stored());
  CHECK(files().size() == 3);
  CHECK(tabled(0.01, 256)->table(fold.ga, fold.gb)->stored());
  // A store whose folder is a file.
  const std::string not_folder = dir.write("plain", "a file");
  mf::FallbackOptions f;
  f.table_cells = 64;
  f.table_store = not_folder + "/tables";
  CHECK_THROWS_WITH(mf::CertifiedChecker(fold.planner, &fold.fine, fold.meshes,
                                         std::vector<const ::fcl::CollisionObjectd*>{}, fold.o, f),
                    Catch::Contains(not_folder) && Catch::Contains("table store"));
  // A folder that cannot be written, even by root (/proc/self): refused before the bake,
  // naming the folder and the pair.
  if (std::filesystem::is_directory("/proc/self")) {
    f.table_store = "/proc/self";
    CHECK_THROWS_WITH(
        mf::CertifiedChecker(fold.planner, &fold.fine, fold.meshes,
                             std::vector<const ::fcl::CollisionObjectd*>{}, fold.o, f),
        Catch::Contains("/proc/self") && Catch::Contains("cannot be written") &&
            Catch::Contains("the table of links"));
  }
  // The write test leaves nothing behind.
  CHECK(files().size() == 3);
}

TEST_CASE("certified checker: separating planes change no verdict, near contact too",
          "[check][fcl]") {
  const RobotModel arm = test::capsule_arm(4), fine = test::capsule_arm(10);
  const double margin = 0.01;
  mf::FallbackOptions without;
  without.separating_planes = false;
  const mf::CertifiedChecker planes(arm, &fine, world().meshes, world().scene(), options(margin));
  const mf::CertifiedChecker meshes(arm, &fine, world().meshes, world().scene(), options(margin),
                                    without);
  std::vector<double> q = test::capsule_arm_configs(400, 23);
  std::vector<Verdict> v(400);
  meshes.check(q.data(), 400, v.data(), 1);
  // Configurations bisected to where the verdict changes, on both sides of it.
  for (std::size_t i = 0; i + 1 < 400; ++i) {
    if (v[i] == v[i + 1]) continue;
    double lo = 0.0, hi = 1.0;  // lo on v[i]'s side
    std::vector<double> at(8);
    auto put = [&](double t) {
      for (int j = 0; j < 8; ++j) at[j] = q[8 * i + j] + t * (q[8 * i + 8 + j] - q[8 * i + j]);
      return at.data();
    };
    for (int step = 0; step < 40; ++step) {
      const double t = 0.5 * (lo + hi);
      (meshes.check(put(t)) == v[i] ? lo : hi) = t;
    }
    for (double t : {lo, hi}) {
      put(t);
      q.insert(q.end(), at.begin(), at.end());
    }
  }
  const std::size_t n = q.size() / 8;
  REQUIRE(n > 440);
  std::vector<Verdict> a(n), b(n), c(n);
  mf::FallbackStats sa, sb;
  meshes.check(q.data(), n, a.data(), 1, &sa);
  planes.check(q.data(), n, b.data(), 1, &sb);
  planes.check(q.data(), n, c.data(), 2);
  CHECK(a == b);
  CHECK(b == c);
  CHECK(std::count(b.begin(), b.end(), Verdict::undecided) == 0);
  CHECK(sa.planes == 0);
  CHECK(sb.planes > 0);
  CHECK(sb.meshes + sb.planes == sa.meshes);
}
