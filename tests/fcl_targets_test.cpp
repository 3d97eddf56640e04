// A sphere set against every FCL primitive, BVHModels of every BV type, and an octree,
// against brute force over its spheres through FCL's own fcl::Sphere narrowphase.

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <set>
#include <vector>

#include <octomap/octomap.h>
#include <catch2/catch.hpp>

#include "medspheres/fcl/sphere_set_geometry.h"
#include "support/fcl_fixtures.h"
#include "support/sphere_fixtures.h"

using medspheres::Sphere;
using medspheres::SphereSet;
using medspheres::fcl::SphereSetGeometry;
namespace mt = medspheres::test;

namespace {

constexpr intptr_t kAnyId = -2;  // the oracle does not know the primitive's id

// One sphere's answer from the oracle: its smallest signed distance to the object (with
// FCL's nearest points when apart, if known), and one entry per primitive it collides
// with: the primitive's id, FCL's depth, and FCL's normal (zero when not known).
struct SphereAnswer {
  double signed_distance = std::numeric_limits<double>::infinity();
  Eigen::Vector3d p_sphere = Eigen::Vector3d::Constant(std::nan(""));
  Eigen::Vector3d p_other = Eigen::Vector3d::Constant(std::nan(""));
  struct Hit {
    intptr_t id;
    double depth;
    Eigen::Vector3d normal;
  };
  std::vector<Hit> hits;
};

// Runs medspheres::fcl in both orders against the per-sphere oracle answers.
// tol bounds differences of distances and depths; point_tol those of nearest points
// (GJK's points are accurate to about the square root of its distance tolerance across
// the surface).
void check_against(const std::shared_ptr<SphereSetGeometry>& g, const fcl::Transform3d& X_WA,
                   const fcl::CollisionGeometryd* other, const fcl::Transform3d& X_WB, double tol,
                   double point_tol, const std::vector<SphereAnswer>& answers, int& separated,
                   int& colliding) {
  double min_signed = std::numeric_limits<double>::infinity();
  std::size_t best = 0, hits = 0;
  for (std::size_t i = 0; i < answers.size(); ++i) {
    hits += answers[i].hits.size();
    if (answers[i].signed_distance < min_signed) {
      min_signed = answers[i].signed_distance;
      best = i;
    }
  }
  for (bool sphere_first : {true, false}) {
    const fcl::CollisionGeometryd* o1 = sphere_first ? g.get() : other;
    const fcl::CollisionGeometryd* o2 = sphere_first ? other : g.get();
    const fcl::Transform3d& X1 = sphere_first ? X_WA : X_WB;
    const fcl::Transform3d& X2 = sphere_first ? X_WB : X_WA;
    fcl::DistanceRequestd sreq(true, true);
    fcl::DistanceResultd sres;
    medspheres::fcl::distance(o1, X1, o2, X2, sreq, sres);
    CHECK(sres.min_distance == Approx(min_signed).margin(tol));
    CHECK(sres.o1 == o1);
    CHECK(sres.o2 == o2);
    const intptr_t sphere = sphere_first ? sres.b1 : sres.b2;
    REQUIRE(sphere >= 0);
    CHECK(answers[static_cast<std::size_t>(sphere)].signed_distance ==
          Approx(min_signed).margin(tol));
    // The witness points differ by the signed distance.
    CHECK((sres.nearest_points[1] - sres.nearest_points[0]).norm() ==
          Approx(std::abs(sres.min_distance)).margin(tol));

    fcl::DistanceRequestd ureq(true);
    fcl::DistanceResultd ures;
    medspheres::fcl::distance(o1, X1, o2, X2, ureq, ures);
    fcl::CollisionRequestd creq(1u << 20, true);
    fcl::CollisionResultd cres;
    medspheres::fcl::collide(o1, X1, o2, X2, creq, cres);
    if (hits == 0) {
      CHECK(ures.min_distance == Approx(min_signed).margin(tol));
      const SphereAnswer& a = answers[best];
      if (a.p_sphere.allFinite()) {
        const Eigen::Vector3d& p_sphere =
            sphere_first ? ures.nearest_points[0] : ures.nearest_points[1];
        const Eigen::Vector3d& p_other =
            sphere_first ? ures.nearest_points[1] : ures.nearest_points[0];
        CHECK((p_sphere - a.p_sphere).norm() <= point_tol);
        CHECK((p_other - a.p_other).norm() <= point_tol);
      }
      CHECK_FALSE(cres.isCollision());
      if (sphere_first) ++separated;
    } else {
      CHECK(ures.min_distance <= tol);
      CHECK(cres.numContacts() == hits);
      std::vector<std::vector<bool>> used(answers.size());
      for (std::size_t i = 0; i < answers.size(); ++i)
        used[i].assign(answers[i].hits.size(), false);
      for (std::size_t k = 0; k < cres.numContacts(); ++k) {
        const fcl::Contactd& c = cres.getContact(k);
        const intptr_t s = sphere_first ? c.b1 : c.b2;
        const intptr_t id = sphere_first ? c.b2 : c.b1;
        const SphereAnswer& a = answers[static_cast<std::size_t>(s)];
        // FCL's normal runs from the sphere to the other object; here from o1 to o2.
        const Eigen::Vector3d n = sphere_first ? c.normal : Eigen::Vector3d(-c.normal);
        bool matched = false;
        for (std::size_t h = 0; h < a.hits.size() && !matched; ++h) {
          const SphereAnswer::Hit& hit = a.hits[h];
          if (used[static_cast<std::size_t>(s)][h]) continue;
          if (hit.id != kAnyId && hit.id != id) continue;
          if (std::abs(hit.depth - c.penetration_depth) > tol) continue;
          if (hit.normal.norm() > 0.5 && (hit.normal - n).norm() > 1e-6) continue;
          used[static_cast<std::size_t>(s)][h] = matched = true;
        }
        CHECK(matched);
        CHECK(c.normal.norm() == Approx(1.0));
      }
      if (sphere_first) ++colliding;
    }
  }
}

}  // namespace

TEST_CASE("Sphere set against every FCL primitive matches FCL's sphere narrowphase",
          "[fcl][primitives]") {
  auto verts = std::make_shared<std::vector<Eigen::Vector3d>>(std::vector<Eigen::Vector3d>{
      {-0.9, -0.7, -0.5}, {0.9, -0.7, -0.5}, {0.0, 1.0, -0.5}, {0.0, 0.0, 1.1}});
  auto faces = std::make_shared<std::vector<int>>(
      std::vector<int>{3, 0, 2, 1, 3, 0, 1, 3, 3, 1, 2, 3, 3, 2, 0, 3});
  struct Named {
    const char* name;
    std::shared_ptr<fcl::CollisionGeometryd> g;
  };
  const std::vector<Named> shapes = {
      {"box", std::make_shared<fcl::Boxd>(0.8, 0.5, 1.1)},
      {"sphere", std::make_shared<fcl::Sphered>(0.6)},
      {"ellipsoid", std::make_shared<fcl::Ellipsoidd>(0.5, 0.3, 0.7)},
      {"capsule", std::make_shared<fcl::Capsuled>(0.3, 0.9)},
      {"cone", std::make_shared<fcl::Coned>(0.7, 1.4)},
      {"cylinder", std::make_shared<fcl::Cylinderd>(0.4, 0.8)},
      {"convex", std::make_shared<fcl::Convexd>(verts, 4, faces, true)},
      {"plane", std::make_shared<fcl::Planed>(Eigen::Vector3d(0.3, -0.2, 1.0).normalized(), 0.1)},
      {"halfspace",
       std::make_shared<fcl::Halfspaced>(Eigen::Vector3d(-0.5, 0.2, 1.0).normalized(), -0.2)},
  };
  std::mt19937 rng(21);
  for (const Named& shape : shapes) {
    INFO(shape.name);
    const bool flat =
        shape.g->getNodeType() == fcl::GEOM_PLANE || shape.g->getNodeType() == fcl::GEOM_HALFSPACE;
    // Shapes answered by libccd's GJK carry its accuracy: its distances change by up to
    // about 1e-4 between two frames of the same configuration (the oracle works in W,
    // the adapter in the shape's frame).
    const fcl::NODE_TYPE t = shape.g->getNodeType();
    const bool gjk = t == fcl::GEOM_ELLIPSOID || t == fcl::GEOM_CONE || t == fcl::GEOM_CONVEX;
    const double tol = gjk ? 1e-4 : 1e-9;
    int separated = 0, colliding = 0;
    for (int k = 0; k < 24; ++k) {
      const SphereSet set = mt::random_sphere_set(rng, 1 + rng() % 25, 0.5, 0.05, 0.25);
      auto g = std::make_shared<SphereSetGeometry>(set);
      const fcl::Transform3d X_WA = mt::random_pose(rng, 1.0);
      const fcl::Transform3d X_WB = mt::random_pose(rng, 1.0);
      std::vector<SphereAnswer> answers;
      for (const Sphere& sphere : set.spheres) {
        const mt::FclAnswer f = mt::fcl_sphere_answer(sphere, X_WA, shape.g.get(), X_WB, !flat);
        SphereAnswer a;
        if (f.collides) {
          a.signed_distance = -f.depth;
          a.hits.push_back({fcl::Contactd::NONE, f.depth, f.normal});
        } else if (flat) {
          // libfcl has no sphere-plane or sphere-halfspace distance: FCL's own
          // signedDistance of the shape, minus the radius.
          const Eigen::Vector3d c = X_WB.inverse() * (X_WA * sphere.center);
          const double sd =
              t == fcl::GEOM_PLANE
                  ? std::abs(static_cast<const fcl::Planed&>(*shape.g).signedDistance(c))
                  : static_cast<const fcl::Halfspaced&>(*shape.g).signedDistance(c);
          a.signed_distance = sd - sphere.radius;
        } else {
          a.signed_distance = f.distance;
          a.p_sphere = f.p_sphere;
          a.p_other = f.p_other;
        }
        answers.push_back(a);
      }
      check_against(g, X_WA, shape.g.get(), X_WB, tol, gjk ? 5e-3 : 1e-9, answers, separated,
                    colliding);
    }
    CHECK(separated > 2);
    CHECK(colliding > 2);
  }
}

TEST_CASE("Sphere set against BVHModels of every BV type matches sphere x triangle", "[fcl][bvh]") {
  const medspheres::TriangleMesh mesh = mt::bumpy_sphere(9, 13, 1.0);
  const std::vector<std::shared_ptr<fcl::CollisionGeometryd>> models = {
      mt::make_bvh<fcl::AABBd>(mesh),     mt::make_bvh<fcl::OBBd>(mesh),
      mt::make_bvh<fcl::RSSd>(mesh),      mt::make_bvh<fcl::kIOSd>(mesh),
      mt::make_bvh<fcl::OBBRSSd>(mesh),   mt::make_bvh<fcl::KDOPd<16>>(mesh),
      mt::make_bvh<fcl::KDOPd<18>>(mesh), mt::make_bvh<fcl::KDOPd<24>>(mesh),
  };
  std::mt19937 rng(22);
  for (const auto& model : models) {
    INFO("node type " << model->getNodeType());
    int separated = 0, colliding = 0;
    for (int k = 0; k < 16; ++k) {
      const SphereSet set = mt::random_sphere_set(rng, 1 + rng() % 40, 0.6, 0.05, 0.3);
      auto g = std::make_shared<SphereSetGeometry>(set);
      const fcl::Transform3d X_WA = mt::random_pose(rng, 1.4);
      const fcl::Transform3d X_WB = mt::random_pose(rng, 1.4);
      // FCL's sphere-triangle core over every triangle; the mesh is a surface.
      std::vector<SphereAnswer> answers;
      for (const Sphere& sphere : set.spheres) {
        const Eigen::Vector3d c = X_WA * sphere.center;
        SphereAnswer a;
        for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
          const double sd = mt::fcl_sphere_triangle_signed_distance(
              c, sphere.radius, X_WB * mesh.corner(t, 0), X_WB * mesh.corner(t, 1),
              X_WB * mesh.corner(t, 2));
          a.signed_distance = std::min(a.signed_distance, sd);
          if (sd <= 0.0) a.hits.push_back({static_cast<intptr_t>(t), -sd, Eigen::Vector3d::Zero()});
        }
        answers.push_back(a);
      }
      check_against(g, X_WA, model.get(), X_WB, 1e-9, 1e-9, answers, separated, colliding);
    }
    CHECK(separated > 2);
    CHECK(colliding > 2);
  }
}

TEST_CASE("Sphere set against an octree matches its occupied boxes", "[fcl][octree]") {
  auto tree = std::make_shared<octomap::OcTree>(0.125);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 400; ++k) {
    const octomap::point3d p(static_cast<float>(u(rng)), static_cast<float>(u(rng)),
                             static_cast<float>(0.3 * u(rng)));
    tree->updateNode(p, k % 5 != 0);  // some free cells
  }
  tree->updateInnerOccupancy();
  auto octree = std::make_shared<fcl::OcTreed>(tree);
  const std::vector<std::array<double, 6>> boxes = octree->toBoxes();
  REQUIRE(boxes.size() > 50);
  int separated = 0, colliding = 0;
  for (int k = 0; k < 20; ++k) {
    const SphereSet set = mt::random_sphere_set(rng, 1 + rng() % 20, 0.4, 0.03, 0.15);
    auto g = std::make_shared<SphereSetGeometry>(set);
    const fcl::Transform3d X_WA = mt::random_pose(rng, 1.2);
    const fcl::Transform3d X_WB = mt::random_pose(rng, 0.3);
    std::vector<SphereAnswer> answers;
    for (const Sphere& sphere : set.spheres) {
      SphereAnswer a;
      for (const auto& b : boxes) {
        const fcl::Boxd box(b[3], b[3], b[3]);
        fcl::Transform3d X_WC = X_WB;
        X_WC.translation() = X_WB * Eigen::Vector3d(b[0], b[1], b[2]);
        const mt::FclAnswer f = mt::fcl_sphere_answer(sphere, X_WA, &box, X_WC);
        if (f.signed_distance() < a.signed_distance) {
          a.signed_distance = f.signed_distance();
          a.p_sphere = f.collides ? Eigen::Vector3d::Constant(std::nan("")) : f.p_sphere;
          a.p_other = f.collides ? Eigen::Vector3d::Constant(std::nan("")) : f.p_other;
        }
        if (f.collides) a.hits.push_back({kAnyId, f.depth, f.normal});
      }
      answers.push_back(a);
    }
    check_against(g, X_WA, octree.get(), X_WB, 1e-9, 1e-9, answers, separated, colliding);
  }
  CHECK(separated > 2);
  CHECK(colliding > 2);
}
