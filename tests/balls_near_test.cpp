// balls_near (balls_near.h), robot_collide's skip of scene pairs: a ball is reported
// beyond the margin only when brute force over the geometry's primitives (every
// occupied octree cell, every mesh triangle, the box) puts it farther than the margin; and
// it is reported for balls inside an octree's root cube but away from its cells.

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include <fcl/fcl.h>
#include <octomap/octomap.h>
#include <catch2/catch.hpp>

#include "medspheres/fcl/balls_near.h"
#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/point_triangle.h"
#include "support/sphere_fixtures.h"

namespace mt = medspheres::test;
namespace mf = medspheres::fcl;

namespace {

// Distance from p (frame of the box, centred at the origin) to a solid box of half sides h.
double box_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& h) {
  return (p.cwiseAbs() - h).cwiseMax(0.0).norm();
}

// Brute force: the distance from p_W to the object's geometry (boxes and octree cells as
// solids, meshes as surfaces, as FCL's distance sees them).
double brute_distance(const fcl::CollisionObjectd& o, const Eigen::Vector3d& p_W) {
  const Eigen::Vector3d p = o.getTransform().inverse() * p_W;
  const fcl::CollisionGeometryd* g = o.collisionGeometry().get();
  double best = std::numeric_limits<double>::infinity();
  if (const auto* box = dynamic_cast<const fcl::Boxd*>(g)) return box_distance(p, 0.5 * box->side);
  if (const auto* tree = dynamic_cast<const fcl::OcTreed*>(g)) {
    for (const auto& b : tree->toBoxes())  // x, y, z, size, ...
      best = std::min(best, box_distance(p - Eigen::Vector3d(b[0], b[1], b[2]),
                                         Eigen::Vector3d::Constant(0.5 * b[3])));
    return best;
  }
  const auto& m = dynamic_cast<const mf::MeshModel&>(*g);
  for (int t = 0; t < m.num_tris; ++t) {
    const fcl::Triangle& tri = m.tri_indices[t];
    const Eigen::Vector3d q = medspheres::closest_point_on_triangle(
        p, m.vertices[tri[0]], m.vertices[tri[1]], m.vertices[tri[2]]);
    best = std::min(best, (q - p).norm());
  }
  return best;
}

std::shared_ptr<fcl::OcTreed> clustered_octree(std::mt19937& rng) {
  // Two clusters on either side of the origin: the root's smallest cell holding every
  // occupied cell is the whole root cube.
  auto tree = std::make_shared<octomap::OcTree>(0.05);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int k = 0; k < 300; ++k) {
    const double cx = k % 2 == 0 ? 1.0 : -1.0;
    tree->updateNode(octomap::point3d(static_cast<float>(cx + u(rng)), static_cast<float>(u(rng)),
                                      static_cast<float>(u(rng))),
                     true);
  }
  tree->updateInnerOccupancy();
  return std::make_shared<fcl::OcTreed>(tree);
}

std::shared_ptr<mf::MeshModel> mesh_model(const medspheres::TriangleMesh& mesh) {
  auto m = std::make_shared<mf::MeshModel>();
  m->beginModel();
  for (const auto& f : mesh.triangles)
    m->addTriangle(mesh.vertices[f[0]], mesh.vertices[f[1]], mesh.vertices[f[2]]);
  m->endModel();
  return m;
}

}  // namespace

TEST_CASE("balls_near only skips balls farther than the margin from the geometry",
          "[bounds][robot]") {
  std::mt19937 rng(31);
  const auto octree = clustered_octree(rng);
  const auto mesh = mesh_model(medspheres::make_torus(0.4, 0.15, 24, 12));
  const auto box = std::make_shared<fcl::Boxd>(0.6, 0.3, 0.2);
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
  objects.push_back(std::make_unique<fcl::CollisionObjectd>(octree, mt::random_pose(rng, 0.3)));
  objects.push_back(std::make_unique<fcl::CollisionObjectd>(mesh, mt::random_pose(rng, 0.5)));
  objects.push_back(std::make_unique<fcl::CollisionObjectd>(box, mt::random_pose(rng, 0.5)));
  std::uniform_real_distribution<double> u(-1.6, 1.6), r(0.0, 0.3);
  const double margin = 0.02;
  for (const auto& object : objects) {
    const fcl::CollisionObjectd& o = *object;
    int skipped = 0, near = 0, skipped_in_aabb = 0;
    std::vector<medspheres::Sphere> balls;
    for (int k = 0; k < 1000; ++k)
      balls.push_back({Eigen::Vector3d(u(rng), u(rng), u(rng)), r(rng)});
    const std::vector<char> found = mf::balls_near(o, balls, margin);
    REQUIRE(found.size() == balls.size());
    for (std::size_t k = 0; k < balls.size(); ++k) {
      const Eigen::Vector3d c = balls[k].center;
      const double radius = balls[k].radius;
      const double gap = brute_distance(o, c) - radius;
      const bool beyond = !found[k];
      // One ball at a time gives the same answer (the search is shared, not its result).
      CHECK(mf::balls_near(o, {balls[k]}, margin)[0] == found[k]);
      INFO("object type " << o.getNodeType() << " ball " << c.transpose() << " r " << radius
                          << " gap " << gap);
      if (beyond) CHECK(gap > margin);
      skipped += beyond ? 1 : 0;
      near += gap <= margin ? 1 : 0;
      const fcl::AABBd& a = o.collisionGeometry()->aabb_local;
      const Eigen::Vector3d p = o.getTransform().inverse() * c;
      if (beyond && (p.array() >= a.min_.array()).all() && (p.array() <= a.max_.array()).all())
        ++skipped_in_aabb;
    }
    CHECK(skipped > 100);
    CHECK(near > 5);
    if (o.getNodeType() == fcl::GEOM_OCTREE) CHECK(skipped_in_aabb > 100);
  }
  // An unbounded object (a half-space: infinite AABB) keeps every ball, even far ones.
  const fcl::CollisionObjectd half(
      std::make_shared<fcl::Halfspaced>(Eigen::Vector3d::UnitZ(), 0.0));
  CHECK(mf::balls_near(half, {{Eigen::Vector3d(0, 0, 50), 0.1}, {Eigen::Vector3d(0, 0, -5), 0.1}},
                       0.0) == std::vector<char>{1, 1});
}

TEST_CASE("balls_apart and balls_within: certain answers on either side of the margin",
          "[bounds][robot]") {
  // Two unit balls whose centres are 3 apart: gap 1 (exact in doubles).
  const medspheres::Sphere a{Eigen::Vector3d(0, 0, 0), 1.0}, b{Eigen::Vector3d(3, 0, 0), 1.0};
  CHECK(mf::balls_apart(a, b, 0.5));
  CHECK_FALSE(mf::balls_within(a, b, 0.5));
  CHECK(mf::balls_within(a, b, 1.5));
  CHECK_FALSE(mf::balls_apart(a, b, 1.5));
  // At the margin itself neither is certain: the rounding allowance leaves it open.
  CHECK_FALSE(mf::balls_apart(a, b, 1.0));
  CHECK_FALSE(mf::balls_within(a, b, 1.0));
  // Never both, on seeded pairs against the gap in long double.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0), r(0.0, 1.0), m(0.0, 0.5);
  for (int k = 0; k < 2000; ++k) {
    const medspheres::Sphere p{Eigen::Vector3d(u(rng), u(rng), u(rng)), r(rng)};
    const medspheres::Sphere q{Eigen::Vector3d(u(rng), u(rng), u(rng)), r(rng)};
    const double margin = m(rng);
    const Eigen::Vector3d d = p.center - q.center;
    const long double gap = std::sqrt(static_cast<long double>(d.x()) * d.x() +
                                      static_cast<long double>(d.y()) * d.y() +
                                      static_cast<long double>(d.z()) * d.z()) -
                            p.radius - q.radius;
    CHECK_FALSE((mf::balls_apart(p, q, margin) && mf::balls_within(p, q, margin)));
    if (mf::balls_apart(p, q, margin)) CHECK(gap > margin);
    if (mf::balls_within(p, q, margin)) CHECK(gap <= margin);
  }
}
