// The opt-in header: plain fcl::distance / fcl::collide calls, and FCL's own default
// broadphase callbacks, pick up sphere sets. Every translation unit of this test program
// includes the header, as its caveat demands.

#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/fcl/fcl_overloads.h"
#include "support/fcl_fixtures.h"
#include "support/sphere_fixtures.h"

using medspheres::fcl::SphereSetGeometry;
namespace mt = medspheres::test;

TEST_CASE("With fcl_overloads.h, fcl::distance and fcl::collide handle sphere sets",
          "[fcl][overloads]") {
  std::mt19937 rng(41);
  for (int k = 0; k < 20; ++k) {
    auto ga = std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 30));
    auto gb = std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 30));
    const fcl::CollisionObjectd a(ga, mt::random_pose(rng, 1.5)), b(gb, mt::random_pose(rng, 1.5));
    fcl::DistanceRequestd req(true, true);
    fcl::DistanceResultd via_fcl, via_medspheres;
    const double d = fcl::distance(&a, &b, req, via_fcl);
    CHECK(d == medspheres::fcl::distance(&a, &b, req, via_medspheres));
    CHECK(via_fcl.b1 == via_medspheres.b1);
    CHECK(via_fcl.nearest_points[1] == via_medspheres.nearest_points[1]);
    const double brute =
        mt::brute_min(ga->sphere_set(), a.getTransform(), gb->sphere_set(), b.getTransform()).value;
    CHECK(d == Approx(brute).margin(1e-9));
    fcl::CollisionRequestd creq(100, true);
    fcl::CollisionResultd c1, c2;
    CHECK(fcl::collide(&a, &b, creq, c1) == medspheres::fcl::collide(&a, &b, creq, c2));
    CHECK(c1.isCollision() == (brute <= 0.0));
  }
}

TEST_CASE("With fcl_overloads.h, FCL's default broadphase callbacks handle sphere sets",
          "[fcl][overloads]") {
  std::mt19937 rng(42);
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
  std::vector<std::shared_ptr<SphereSetGeometry>> sets;
  for (int k = 0; k < 8; ++k) {
    sets.push_back(std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 20, 0.4)));
    objects.push_back(
        std::make_unique<fcl::CollisionObjectd>(sets.back(), mt::random_pose(rng, 2.0)));
  }
  objects.push_back(std::make_unique<fcl::CollisionObjectd>(
      std::make_shared<fcl::Boxd>(0.5, 0.5, 0.5), mt::random_pose(rng, 2.0)));
  double direct_min = std::numeric_limits<double>::infinity();
  bool direct_collision = false;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    for (std::size_t j = i + 1; j < objects.size(); ++j) {
      fcl::DistanceRequestd req;
      fcl::DistanceResultd res;
      direct_min = std::min(
          direct_min, medspheres::fcl::distance(objects[i].get(), objects[j].get(), req, res));
      fcl::CollisionRequestd creq;
      fcl::CollisionResultd cres;
      direct_collision =
          direct_collision ||
          medspheres::fcl::collide(objects[i].get(), objects[j].get(), creq, cres) > 0;
    }
  }
  fcl::DynamicAABBTreeCollisionManagerd manager;
  for (auto& o : objects) manager.registerObject(o.get());
  manager.setup();
  fcl::DefaultDistanceData<double> ddata;
  manager.distance(&ddata, fcl::DefaultDistanceFunction);
  if (direct_min > 0)
    CHECK(ddata.result.min_distance == Approx(direct_min).margin(1e-9));
  else
    CHECK(ddata.result.min_distance <= 0.0);
  fcl::DefaultCollisionData<double> cdata;
  manager.collide(&cdata, fcl::DefaultCollisionFunction);
  CHECK(cdata.result.isCollision() == direct_collision);
}

TEST_CASE("With fcl_overloads.h, pairs medspheres does not answer go to libfcl, without throwing",
          "[fcl][overloads]") {
  // libfcl never throws for a pair it cannot answer, and FCL's default callbacks do not
  // catch: the overloads must not throw either. A sphere set against fcl::TriangleP, or
  // at a non-finite pose, is answered by libfcl as for the guard box (an fcl::Box).
  std::mt19937 rng(43);
  auto set = std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 20, 0.4));
  const fcl::Boxd box(set->side);
  auto triangle = std::make_shared<fcl::TrianglePd>(
      Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0));
  const fcl::Transform3d I = fcl::Transform3d::Identity();
  fcl::Transform3d bad = I;
  bad.translation().x() = std::numeric_limits<double>::quiet_NaN();
  for (const fcl::Transform3d& X : {I, bad}) {
    fcl::CollisionRequestd creq;
    fcl::CollisionResultd on_set, on_box;
    CHECK_NOTHROW(fcl::collide(set.get(), X, triangle.get(), I, creq, on_set));
    fcl::collide<double>(&box, X, triangle.get(), I, creq, on_box);
    CHECK(on_set.numContacts() == on_box.numContacts());
    fcl::DistanceRequestd dreq;
    fcl::DistanceResultd d_set, d_box;
    double d = 0.0;
    CHECK_NOTHROW(d = fcl::distance(triangle.get(), I, set.get(), X, dreq, d_set));
    CHECK(d == fcl::distance<double>(triangle.get(), I, &box, X, dreq, d_box));
  }
  // The explicit medspheres::fcl entry points say what is wrong instead.
  fcl::CollisionRequestd creq;
  fcl::CollisionResultd cres;
  CHECK_THROWS_AS(medspheres::fcl::collide(set.get(), I, triangle.get(), I, creq, cres),
                  std::invalid_argument);
  CHECK_THROWS_AS(medspheres::fcl::collide(set.get(), bad, triangle.get(), I, creq, cres),
                  std::invalid_argument);
  // Through a broadphase manager and FCL's default callbacks: no exception escapes.
  fcl::CollisionObjectd a(set, I), b(triangle, I);
  fcl::DynamicAABBTreeCollisionManagerd manager;
  manager.registerObject(&a);
  manager.registerObject(&b);
  manager.setup();
  fcl::DefaultCollisionData<double> cdata;
  CHECK_NOTHROW(manager.collide(&cdata, fcl::DefaultCollisionFunction));
  fcl::DefaultDistanceData<double> ddata;
  CHECK_NOTHROW(manager.distance(&ddata, fcl::DefaultDistanceFunction));
}
