// Broadphase: a scene that mixes sphere sets, meshes and primitives gives the same
// answers through fcl::DynamicAABBTreeCollisionManagerd and the medspheres callbacks as
// through direct calls on every pair; errors inside a callback do not escape it.

#include <algorithm>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
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

// Objects of six kinds (two sphere sets, a mesh, three primitives), each with its own
// geometry so that a contact's or a distance result's geometries name its objects.
std::vector<std::unique_ptr<fcl::CollisionObjectd>> mixed_scene(std::mt19937& rng, int count,
                                                                double extent) {
  const medspheres::TriangleMesh mesh = mt::bumpy_sphere(7, 9, 0.5);
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
  for (int k = 0; k < count; ++k) {
    std::shared_ptr<fcl::CollisionGeometryd> g;
    switch (k % 6) {
      case 0:
        g = std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 30, 0.4, 0.05, 0.15));
        break;
      case 1:
        g = std::make_shared<SphereSetGeometry>(mt::random_sheet_set(rng, 60));
        break;
      case 2:
        g = mt::make_bvh<fcl::OBBRSSd>(mesh);
        break;
      case 3:
        g = std::make_shared<fcl::Boxd>(0.5, 0.3, 0.4);
        break;
      case 4:
        g = std::make_shared<fcl::Sphered>(0.3);
        break;
      default:
        g = std::make_shared<fcl::Capsuled>(0.2, 0.6);
        break;
    }
    objects.push_back(std::make_unique<fcl::CollisionObjectd>(g, mt::random_pose(rng, extent)));
  }
  return objects;
}

// The object whose geometry is g.
std::size_t object_of(const std::vector<std::unique_ptr<fcl::CollisionObjectd>>& objects,
                      const fcl::CollisionGeometryd* g) {
  for (std::size_t i = 0; i < objects.size(); ++i)
    if (objects[i]->collisionGeometry().get() == g) return i;
  FAIL("a result names a geometry of no object");
  return objects.size();
}

// Two contacts are the same: primitives, depth, normal and position.
void check_same_contact(const fcl::Contactd& got, const fcl::Contactd& expected) {
  CHECK(got.o1 == expected.o1);
  CHECK(got.o2 == expected.o2);
  CHECK(got.b1 == expected.b1);
  CHECK(got.b2 == expected.b2);
  CHECK(got.penetration_depth == expected.penetration_depth);
  CHECK(got.normal == expected.normal);
  CHECK(got.pos == expected.pos);
}

// The contacts a manager's callback gave for the pair of objects are those of a direct
// call on the pair, in the same order.
void check_same_as_direct(const std::vector<std::unique_ptr<fcl::CollisionObjectd>>& objects,
                          const std::pair<std::size_t, std::size_t>& pair,
                          const std::vector<fcl::Contactd>& contacts,
                          const fcl::CollisionRequestd& request) {
  fcl::CollisionResultd direct;
  medspheres::fcl::collide(objects[pair.first].get(), objects[pair.second].get(), request, direct);
  REQUIRE(direct.numContacts() == contacts.size());
  for (std::size_t k = 0; k < contacts.size(); ++k)
    check_same_contact(contacts[k], direct.getContact(k));
}

// A distance result of a manager against the direct call on its two objects in the
// order the manager passed them (the result names them), and against the direct
// minimum over all pairs, which (i, j) attains with result `direct` (i < j or the probe).
void check_distance_result(const std::vector<std::unique_ptr<fcl::CollisionObjectd>>& objects,
                           const fcl::DistanceResultd& got, const fcl::DistanceResultd& direct) {
  CHECK(got.min_distance == Approx(direct.min_distance).margin(1e-9));
  // The same two objects, in either order.
  const bool same_order = got.o1 == direct.o1 && got.o2 == direct.o2;
  const bool swapped = got.o1 == direct.o2 && got.o2 == direct.o1;
  REQUIRE((same_order || swapped));
  if (same_order) {
    CHECK(got.b1 == direct.b1);
    CHECK(got.b2 == direct.b2);
    CHECK((got.nearest_points[0] - direct.nearest_points[0]).norm() <= 1e-9);
    CHECK((got.nearest_points[1] - direct.nearest_points[1]).norm() <= 1e-9);
  } else {
    CHECK(got.b1 == direct.b2);
    CHECK(got.b2 == direct.b1);
    CHECK((got.nearest_points[0] - direct.nearest_points[1]).norm() <= 1e-9);
    CHECK((got.nearest_points[1] - direct.nearest_points[0]).norm() <= 1e-9);
  }
  // The direct call in the manager's order gives exactly this pair and its points.
  const std::size_t a = object_of(objects, got.o1), b = object_of(objects, got.o2);
  fcl::DistanceRequestd req(true);
  fcl::DistanceResultd again;
  medspheres::fcl::distance(objects[a].get(), objects[b].get(), req, again);
  CHECK(got.min_distance == again.min_distance);
  CHECK(got.b1 == again.b1);
  CHECK(got.b2 == again.b2);
  CHECK(got.nearest_points[0] == again.nearest_points[0]);
  CHECK(got.nearest_points[1] == again.nearest_points[1]);
}

}  // namespace

TEST_CASE("DynamicAABBTreeCollisionManagerd gives the same answers as direct calls",
          "[fcl][broadphase]") {
  std::mt19937 rng(31);
  int separated_scenes = 0, colliding_scenes = 0, separated_probes = 0;
  for (int trial = 0; trial < 20; ++trial) {
    // Crowded scenes first, then sparse ones where nothing collides.
    auto objects = trial < 10 ? mixed_scene(rng, 14, 2.5) : mixed_scene(rng, 8, 4.0);
    fcl::DynamicAABBTreeCollisionManagerd manager;
    for (auto& o : objects) manager.registerObject(o.get());
    manager.setup();

    // Direct: every pair, with all its contacts, and the nearest pair.
    std::set<std::pair<std::size_t, std::size_t>> direct_pairs;
    double direct_min = std::numeric_limits<double>::infinity();
    fcl::DistanceResultd direct_nearest;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      for (std::size_t j = i + 1; j < objects.size(); ++j) {
        fcl::CollisionRequestd req;
        fcl::CollisionResultd res;
        if (medspheres::fcl::collide(objects[i].get(), objects[j].get(), req, res) > 0)
          direct_pairs.insert({i, j});
        fcl::DistanceRequestd dreq(true);
        fcl::DistanceResultd dres;
        const double d = medspheres::fcl::distance(objects[i].get(), objects[j].get(), dreq, dres);
        if (d < direct_min) {
          direct_min = d;
          direct_nearest = dres;
        }
      }
    }

    // Self-collision: the manager finds a collision iff some pair collides.
    medspheres::fcl::CollisionData first;
    manager.collide(&first, medspheres::fcl::collision_callback);
    medspheres::fcl::rethrow_if_failed(first);
    CHECK(first.result.isCollision() == !direct_pairs.empty());

    // All contacts: the same colliding pairs, and for each pair, in the order the manager
    // passed it, exactly the contacts of the direct call.
    medspheres::fcl::CollisionData all;
    all.request.num_max_contacts = 1u << 20;
    all.request.enable_contact = true;
    manager.collide(&all, medspheres::fcl::collision_callback);
    medspheres::fcl::rethrow_if_failed(all);
    std::map<std::pair<std::size_t, std::size_t>, std::vector<fcl::Contactd>> managed;
    for (std::size_t k = 0; k < all.result.numContacts(); ++k) {
      const fcl::Contactd& c = all.result.getContact(k);
      managed[{object_of(objects, c.o1), object_of(objects, c.o2)}].push_back(c);
    }
    std::set<std::pair<std::size_t, std::size_t>> managed_pairs;
    for (const auto& [pair, contacts] : managed) {
      CHECK(managed_pairs
                .insert({std::min(pair.first, pair.second), std::max(pair.first, pair.second)})
                .second);  // each pair once, in one order
      check_same_as_direct(objects, pair, contacts, all.request);
    }
    CHECK(managed_pairs == direct_pairs);
    (direct_pairs.empty() ? separated_scenes : colliding_scenes)++;

    medspheres::fcl::DistanceData ddata;
    ddata.request.enable_nearest_points = true;
    manager.distance(&ddata, medspheres::fcl::distance_callback);
    medspheres::fcl::rethrow_if_failed(ddata);
    // (libfcl's distance between an fcl::Sphere and a mesh it overlaps is not defined: it
    // reads an uninitialized value, so only scenes without collisions are compared.)
    if (direct_pairs.empty()) {
      CHECK(direct_min > 0);
      check_distance_result(objects, ddata.result, direct_nearest);
    } else {
      CHECK(ddata.result.min_distance <= 0.0);
    }

    // Object against the manager.
    auto probe_geometry = std::make_shared<SphereSetGeometry>(mt::random_sheet_set(rng, 40));
    fcl::CollisionObjectd probe(probe_geometry, mt::random_pose(rng, 2.0));
    double probe_min = std::numeric_limits<double>::infinity();
    fcl::DistanceResultd probe_nearest;
    std::set<std::size_t> probe_hits;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      fcl::DistanceRequestd dreq(true);
      fcl::DistanceResultd dres;
      const double d = medspheres::fcl::distance(&probe, objects[i].get(), dreq, dres);
      if (d < probe_min) {
        probe_min = d;
        probe_nearest = dres;
      }
      fcl::CollisionRequestd creq;
      fcl::CollisionResultd cres;
      if (medspheres::fcl::collide(&probe, objects[i].get(), creq, cres) > 0) probe_hits.insert(i);
    }
    objects.push_back(
        std::make_unique<fcl::CollisionObjectd>(probe_geometry, probe.getTransform()));
    medspheres::fcl::DistanceData pd;
    pd.request.enable_nearest_points = true;
    manager.distance(&probe, &pd, medspheres::fcl::distance_callback);
    medspheres::fcl::rethrow_if_failed(pd);
    if (probe_min > 0) {
      ++separated_probes;
      check_distance_result(objects, pd.result, probe_nearest);
    } else {
      CHECK(pd.result.min_distance <= 0.0);
    }
    medspheres::fcl::CollisionData pc;
    pc.request.num_max_contacts = 1u << 20;
    pc.request.enable_contact = true;
    manager.collide(&probe, &pc, medspheres::fcl::collision_callback);
    medspheres::fcl::rethrow_if_failed(pc);
    std::map<std::pair<std::size_t, std::size_t>, std::vector<fcl::Contactd>> probed;
    for (std::size_t k = 0; k < pc.result.numContacts(); ++k) {
      const fcl::Contactd& c = pc.result.getContact(k);
      probed[{object_of(objects, c.o1), object_of(objects, c.o2)}].push_back(c);
    }
    std::set<std::size_t> probed_hits;
    const std::size_t probe_index = objects.size() - 1;
    for (const auto& [pair, contacts] : probed) {
      REQUIRE(((pair.first == probe_index) != (pair.second == probe_index)));
      CHECK(probed_hits.insert(pair.first == probe_index ? pair.second : pair.first).second);
      check_same_as_direct(objects, pair, contacts, pc.request);
    }
    CHECK(probed_hits == probe_hits);
  }
  CHECK(separated_scenes >= 3);
  CHECK(colliding_scenes >= 3);
  CHECK(separated_probes >= 3);
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
