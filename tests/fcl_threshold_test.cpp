// medspheres::fcl::distance with a preset min_distance (a threshold, as MoveIt presets
// it) and collide() test bounding volumes first and may return before they walk the sphere
// tree (pair_beyond). Oracle: the same query without a threshold, the full walk. For a
// sphere set against another sphere set, BVHModels of every BV type, every bounded FCL
// primitive and an octree, in both orders, unsigned and signed: the same verdict (closer
// than the threshold or not) and, when closer, the same distance, pair and points; when
// not, the result untouched (overlapping sets in an unsigned query report the first
// overlapping pair found, whichever it is: there only the verdict is compared).
// Thresholds: at the distance, next to it, and across the range where bounding volumes
// settle the pair. The distances themselves are checked against brute force in
// fcl_targets_test.cpp.

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include <octomap/octomap.h>
#include <catch2/catch.hpp>

#include "medspheres/fcl/sphere_set_geometry.h"
#include "support/fcl_fixtures.h"
#include "support/sphere_fixtures.h"

using medspheres::SphereSet;
using medspheres::fcl::SphereSetGeometry;
namespace mt = medspheres::test;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Named {
  const char* name;
  std::shared_ptr<fcl::CollisionGeometryd> g;
};

// An octree of cells of side 0.1 on a noisy patch, some of them free.
std::shared_ptr<fcl::OcTreed> patch_octree(std::mt19937& rng) {
  auto tree = std::make_shared<octomap::OcTree>(0.1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 300; ++k) {
    const double x = u(rng), y = u(rng);
    tree->updateNode(octomap::point3d(static_cast<float>(x), static_cast<float>(y),
                                      static_cast<float>(0.2 * std::sin(3 * x) + 0.05 * u(rng))),
                     k % 6 != 0);
  }
  tree->updateInnerOccupancy();
  return std::make_shared<fcl::OcTreed>(tree);
}

std::vector<Named> geometries(std::mt19937& rng) {
  const medspheres::TriangleMesh mesh = mt::bumpy_sphere(7, 11, 0.8);
  return {
      {"sphere set", std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 30, 0.6))},
      {"OBBRSS", mt::make_bvh<fcl::OBBRSSd>(mesh)},
      {"RSS", mt::make_bvh<fcl::RSSd>(mesh)},
      {"AABB", mt::make_bvh<fcl::AABBd>(mesh)},
      {"OBB", mt::make_bvh<fcl::OBBd>(mesh)},
      {"kIOS", mt::make_bvh<fcl::kIOSd>(mesh)},
      {"KDOP16", mt::make_bvh<fcl::KDOPd<16>>(mesh)},
      {"box", std::make_shared<fcl::Boxd>(0.8, 0.3, 1.1)},
      {"sphere", std::make_shared<fcl::Sphered>(0.5)},
      {"capsule", std::make_shared<fcl::Capsuled>(0.25, 0.9)},
      {"cylinder", std::make_shared<fcl::Cylinderd>(0.4, 0.7)},
      {"ellipsoid", std::make_shared<fcl::Ellipsoidd>(0.5, 0.3, 0.6)},
      {"octree", patch_octree(rng)},
  };
}

// A set of 1 to 30 spheres and two poses, each within `extent` of the origin.
struct Scene {
  std::shared_ptr<SphereSetGeometry> set;
  fcl::Transform3d X_WA, X_WB;
};

Scene random_scene(std::mt19937& rng, double extent) {
  Scene s;
  s.set = std::make_shared<SphereSetGeometry>(
      mt::random_sphere_set(rng, 1 + rng() % 30, 0.4, 0.03, 0.2));
  s.X_WA = mt::random_pose(rng, extent);
  s.X_WB = mt::random_pose(rng, extent);
  return s;
}

// Thresholds at the full answer d, next to it, and across [0, 2 d + 0.2]. Next to it: 1e-12
// away, above the few ulps by which the walk's bounds and sums round (sphere_tree.h), far
// below the bounding test's allowance.
std::vector<double> thresholds(double d, std::mt19937& rng) {
  const double near = 1e-12 * (1.0 + std::abs(d));
  std::vector<double> out = {d, d + near, d - near, d + 1e-9, d - 1e-9, 0.0, -0.05};
  std::uniform_real_distribution<double> u(0.0, 2.0 * std::abs(d) + 0.2);
  for (int k = 0; k < 8; ++k) out.push_back(u(rng));
  return out;
}

// The query with min_distance preset to m against the full one (`full`, no threshold).
void check_threshold(const fcl::CollisionGeometryd* o1, const fcl::Transform3d& X1,
                     const fcl::CollisionGeometryd* o2, const fcl::Transform3d& X2,
                     const fcl::DistanceRequestd& request, const fcl::DistanceResultd& full,
                     double m, int& settled_closer, int& settled_beyond) {
  INFO("threshold " << m << ", full answer " << full.min_distance);
  fcl::DistanceResultd r;
  r.min_distance = m;
  const double d = medspheres::fcl::distance(o1, X1, o2, X2, request, r);
  CHECK(d == r.min_distance);
  if (!request.enable_signed_distance && full.min_distance <= 0.0) {
    // Overlapping, unsigned: the first overlapping pair found, implementation defined (FCL's
    // convention); the walk differs with the threshold. Below a positive threshold it is
    // an overlapping pair; below a negative one, any pair deeper than it, or none.
    if (m > 0.0) {
      ++settled_closer;
      CHECK(r.min_distance <= 0.0);
      CHECK(r.o1 == o1);
    } else {
      CHECK(r.min_distance <= m);
      CHECK((r.min_distance == m || r.o1 == o1));
    }
    return;
  }
  if (full.min_distance < m) {
    ++settled_closer;
    CHECK(r.min_distance == full.min_distance);
    CHECK(r.o1 == o1);
    CHECK(r.o2 == o2);
    CHECK(r.b1 == full.b1);
    CHECK(r.b2 == full.b2);
    CHECK(r.nearest_points[0] == full.nearest_points[0]);
    CHECK(r.nearest_points[1] == full.nearest_points[1]);
  } else {
    ++settled_beyond;
    CHECK(r.min_distance == m);
    CHECK(r.o1 == nullptr);
    CHECK(r.o2 == nullptr);
    const int none = fcl::DistanceResultd::NONE;  // a copy: Catch takes operands by reference
    CHECK(r.b1 == none);
    CHECK(r.b2 == none);
  }
}

}  // namespace

TEST_CASE("A preset min_distance gives the full answer's verdict, distance, pair and points",
          "[fcl][threshold]") {
  std::mt19937 rng(41);
  for (const Named& other : geometries(rng)) {
    INFO(other.name);
    int closer = 0, beyond = 0;
    for (int scene = 0; scene < 12; ++scene) {
      const auto [set, X_WA, X_WB] = random_scene(rng, 1.6);
      for (bool is_signed : {false, true})
        for (bool set_first : {true, false}) {
          INFO("scene " << scene << ", signed " << is_signed << ", set first " << set_first);
          const fcl::CollisionGeometryd* o1 = set_first ? set.get() : other.g.get();
          const fcl::CollisionGeometryd* o2 = set_first ? other.g.get() : set.get();
          const fcl::Transform3d& X1 = set_first ? X_WA : X_WB;
          const fcl::Transform3d& X2 = set_first ? X_WB : X_WA;
          const fcl::DistanceRequestd request(true, is_signed);
          fcl::DistanceResultd full;
          medspheres::fcl::distance(o1, X1, o2, X2, request, full);
          REQUIRE(full.o1 == o1);
          for (double m : thresholds(full.min_distance, rng))
            check_threshold(o1, X1, o2, X2, request, full, m, closer, beyond);
        }
    }
    // Both verdicts, many times over.
    CHECK(closer > 50);
    CHECK(beyond > 50);
  }
}

TEST_CASE("collide() finds what the full distance query puts at or below 0", "[fcl][threshold]") {
  std::mt19937 rng(42);
  for (const Named& other : geometries(rng)) {
    INFO(other.name);
    int touching = 0, apart = 0;
    for (int scene = 0; scene < 60; ++scene) {
      const auto [set, X_WA, X_WB] = random_scene(rng, 1.0);
      fcl::DistanceResultd full;
      medspheres::fcl::distance(set.get(), X_WA, other.g.get(), X_WB, fcl::DistanceRequestd(),
                                full);
      for (bool set_first : {true, false}) {
        fcl::CollisionResultd c;
        if (set_first)
          medspheres::fcl::collide(set.get(), X_WA, other.g.get(), X_WB, fcl::CollisionRequestd(),
                                   c);
        else
          medspheres::fcl::collide(other.g.get(), X_WB, set.get(), X_WA, fcl::CollisionRequestd(),
                                   c);
        INFO("scene " << scene << ", distance " << full.min_distance);
        CHECK(c.isCollision() == (full.min_distance <= 0.0));
      }
      ++(full.min_distance <= 0.0 ? touching : apart);
    }
    CHECK(touching > 4);
    CHECK(apart > 4);
  }
}

TEST_CASE("Non-finite poses throw before the bounding test, finite ones never do",
          "[fcl][threshold]") {
  std::mt19937 rng(43);
  auto set = std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 10, 0.3));
  const fcl::Boxd box(0.2, 0.2, 0.2);
  fcl::Transform3d far = fcl::Transform3d::Identity();
  far.translation() = Eigen::Vector3d(5.0, 0.0, 0.0);  // beyond any threshold used here
  const fcl::Transform3d I = fcl::Transform3d::Identity();
  fcl::Transform3d nan_rotation = far, inf_corner = far, huge = far;
  nan_rotation.linear()(1, 2) = std::nan("");
  inf_corner.matrix()(3, 0) = kInf;                            // the row an isometry never reads
  huge.translation() = Eigen::Vector3d(1e308, 1e308, -1e308);  // entries sum past the largest
  for (const fcl::Transform3d* bad : {&nan_rotation, &inf_corner}) {
    fcl::DistanceResultd r;
    r.min_distance = 0.01;
    CHECK_THROWS_AS(medspheres::fcl::distance(set.get(), *bad, &box, I, fcl::DistanceRequestd(), r),
                    std::invalid_argument);
    CHECK_THROWS_AS(medspheres::fcl::distance(&box, I, set.get(), *bad, fcl::DistanceRequestd(), r),
                    std::invalid_argument);
    fcl::CollisionResultd c;
    CHECK_THROWS_AS(medspheres::fcl::collide(set.get(), *bad, &box, I, fcl::CollisionRequestd(), c),
                    std::invalid_argument);
  }
  fcl::DistanceResultd r;
  r.min_distance = 0.01;
  CHECK_NOTHROW(medspheres::fcl::distance(set.get(), huge, &box, huge, fcl::DistanceRequestd(), r));
  CHECK(r.min_distance < 0.0);  // the box sits among the spheres
  fcl::CollisionResultd c;
  CHECK(medspheres::fcl::collide(set.get(), huge, &box, far, fcl::CollisionRequestd(), c) == 0);
}
