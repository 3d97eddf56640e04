// The opt-in header: plain fcl::distance / fcl::collide calls, and FCL's own default
// broadphase callbacks, pick up sphere sets. Every translation unit of this test program
// includes the header, as its caveat demands.

#include <limits>
#include <memory>
#include <random>
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
