// Broadphase: a scene that mixes sphere sets, meshes and primitives gives the same
// answers through fcl::DynamicAABBTreeCollisionManagerd and the medspheres callbacks as
// through direct calls on every pair; errors inside a callback do not escape it.

#include <algorithm>
#include <limits>
#include <memory>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/fcl/broadphase_callbacks.h"
#include "medspheres/fcl/sphere_set_geometry.h"
#include "support/fcl_fixtures.h"
#include "support/sphere_fixtures.h"

using medspheres::SphereSet;
using medspheres::fcl::SphereSetGeometry;
namespace mt = medspheres::test;

namespace {

std::vector<std::unique_ptr<fcl::CollisionObjectd>> mixed_scene(std::mt19937& rng, int count) {
  const medspheres::TriangleMesh mesh = mt::bumpy_sphere(7, 9, 0.5);
  std::vector<std::shared_ptr<fcl::CollisionGeometryd>> kinds = {
      std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 30, 0.4, 0.05, 0.15)),
      std::make_shared<SphereSetGeometry>(mt::random_sheet_set(rng, 60)),
      mt::make_bvh<fcl::OBBRSSd>(mesh),
      std::make_shared<fcl::Boxd>(0.5, 0.3, 0.4),
      std::make_shared<fcl::Sphered>(0.3),
      std::make_shared<fcl::Capsuled>(0.2, 0.6),
  };
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
  for (int k = 0; k < count; ++k)
    objects.push_back(std::make_unique<fcl::CollisionObjectd>(
        kinds[static_cast<std::size_t>(k) % kinds.size()], mt::random_pose(rng, 2.5)));
  return objects;
}

}  // namespace

TEST_CASE("DynamicAABBTreeCollisionManagerd gives the same answers as direct calls",
          "[fcl][broadphase]") {
  std::mt19937 rng(31);
  for (int trial = 0; trial < 10; ++trial) {
    auto objects = mixed_scene(rng, 14);
    fcl::DynamicAABBTreeCollisionManagerd manager;
    for (auto& o : objects) manager.registerObject(o.get());
    manager.setup();

    // Direct: every pair.
    std::size_t direct_colliding_pairs = 0;
    double direct_min = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < objects.size(); ++i) {
      for (std::size_t j = i + 1; j < objects.size(); ++j) {
        fcl::CollisionRequestd req;
        fcl::CollisionResultd res;
        if (medspheres::fcl::collide(objects[i].get(), objects[j].get(), req, res) > 0)
          ++direct_colliding_pairs;
        fcl::DistanceRequestd dreq;
        fcl::DistanceResultd dres;
        direct_min = std::min(
            direct_min, medspheres::fcl::distance(objects[i].get(), objects[j].get(), dreq, dres));
      }
    }

    // Self-collision: the manager finds a collision iff some pair collides.
    medspheres::fcl::CollisionData first;
    manager.collide(&first, medspheres::fcl::collision_callback);
    medspheres::fcl::rethrow_if_failed(first);
    CHECK(first.result.isCollision() == (direct_colliding_pairs > 0));

    medspheres::fcl::DistanceData ddata;
    manager.distance(&ddata, medspheres::fcl::distance_callback);
    medspheres::fcl::rethrow_if_failed(ddata);
    if (direct_min > 0) {
      CHECK(ddata.result.min_distance == Approx(direct_min).margin(1e-9));
    } else {
      CHECK(ddata.result.min_distance <= 0.0);
    }

    // Object against the manager.
    fcl::CollisionObjectd probe(std::make_shared<SphereSetGeometry>(mt::random_sheet_set(rng, 40)),
                                mt::random_pose(rng, 2.0));
    double probe_min = std::numeric_limits<double>::infinity();
    bool probe_hits = false;
    for (auto& o : objects) {
      fcl::DistanceRequestd dreq;
      fcl::DistanceResultd dres;
      probe_min = std::min(probe_min, medspheres::fcl::distance(&probe, o.get(), dreq, dres));
      fcl::CollisionRequestd creq;
      fcl::CollisionResultd cres;
      probe_hits = probe_hits || medspheres::fcl::collide(&probe, o.get(), creq, cres) > 0;
    }
    medspheres::fcl::DistanceData pd;
    manager.distance(&probe, &pd, medspheres::fcl::distance_callback);
    if (probe_min > 0) {
      CHECK(pd.result.min_distance == Approx(probe_min).margin(1e-9));
    } else {
      CHECK(pd.result.min_distance <= 0.0);
    }
    medspheres::fcl::CollisionData pc;
    manager.collide(&probe, &pc, medspheres::fcl::collision_callback);
    CHECK(pc.result.isCollision() == probe_hits);
  }
}

TEST_CASE("Sphere-only scenes: manager and direct contacts agree pair by pair",
          "[fcl][broadphase]") {
  std::mt19937 rng(32);
  std::vector<std::shared_ptr<SphereSetGeometry>> geometries;
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
  for (int k = 0; k < 10; ++k) {
    geometries.push_back(std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 20, 0.4)));
    objects.push_back(
        std::make_unique<fcl::CollisionObjectd>(geometries.back(), mt::random_pose(rng, 1.5)));
  }
  fcl::DynamicAABBTreeCollisionManagerd manager;
  for (auto& o : objects) manager.registerObject(o.get());
  manager.setup();
  std::multiset<std::pair<const void*, const void*>> direct;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    for (std::size_t j = i + 1; j < objects.size(); ++j) {
      fcl::CollisionRequestd req(1u << 20, true);
      fcl::CollisionResultd res;
      medspheres::fcl::collide(objects[i].get(), objects[j].get(), req, res);
      for (std::size_t k = 0; k < res.numContacts(); ++k)
        direct.insert({std::min<const void*>(res.getContact(k).o1, res.getContact(k).o2),
                       std::max<const void*>(res.getContact(k).o1, res.getContact(k).o2)});
    }
  }
  medspheres::fcl::CollisionData data;
  data.request.num_max_contacts = 1u << 20;
  data.request.enable_contact = true;
  manager.collide(&data, medspheres::fcl::collision_callback);
  std::multiset<std::pair<const void*, const void*>> managed;
  for (std::size_t k = 0; k < data.result.numContacts(); ++k)
    managed.insert(
        {std::min<const void*>(data.result.getContact(k).o1, data.result.getContact(k).o2),
         std::max<const void*>(data.result.getContact(k).o1, data.result.getContact(k).o2)});
  CHECK(!direct.empty());
  CHECK(managed == direct);
}

TEST_CASE("An exception inside a callback is stored, not thrown through FCL", "[fcl][broadphase]") {
  std::mt19937 rng(33);
  auto sphere_set = std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 10, 0.3));
  auto triangle = std::make_shared<fcl::TriangleP<double>>(
      Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(1, -1, 0), Eigen::Vector3d(0, 1, 0));
  fcl::CollisionObjectd a(sphere_set, fcl::Transform3d::Identity());
  fcl::CollisionObjectd b(triangle, fcl::Transform3d::Identity());
  fcl::DynamicAABBTreeCollisionManagerd manager;
  manager.registerObject(&a);
  manager.registerObject(&b);
  manager.setup();
  medspheres::fcl::CollisionData cdata;
  CHECK_NOTHROW(manager.collide(&cdata, medspheres::fcl::collision_callback));
  CHECK(cdata.done);
  CHECK_THROWS_AS(medspheres::fcl::rethrow_if_failed(cdata), std::invalid_argument);
  medspheres::fcl::DistanceData ddata;
  CHECK_NOTHROW(manager.distance(&ddata, medspheres::fcl::distance_callback));
  CHECK_THROWS_AS(medspheres::fcl::rethrow_if_failed(ddata), std::invalid_argument);
}
