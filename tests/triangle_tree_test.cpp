// TriangleTree and the sphere-set-to-mesh queries, against brute force over all
// sphere x triangle pairs with the 113-bit point-triangle oracle.

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/sphere_tree.h"
#include "medspheres/triangle_tree.h"
#include "support/point_triangle_oracle.h"
#include "support/sphere_fixtures.h"

using medspheres::BallProximity;
using medspheres::Rss;
using medspheres::Sphere;
using medspheres::SphereSet;
using medspheres::SphereTree;
using medspheres::TreeContact;
using medspheres::TreeDistance;
using medspheres::TriangleMesh;
using medspheres::TriangleTree;
namespace mt = medspheres::test;

TEST_CASE("ball_triangle_proximity follows the BallProximity convention", "[triangle_tree]") {
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  BallProximity p = medspheres::ball_triangle_proximity(Eigen::Vector3d(0.5, 0.5, 3), 1.0, a, b, c);
  CHECK(p.distance == 2.0);
  CHECK(p.normal == Eigen::Vector3d(0, 0, -1));
  p = medspheres::ball_triangle_proximity(Eigen::Vector3d(0.5, 0.5, 0.25), 1.0, a, b, c);
  CHECK(p.distance == -0.75);
  CHECK(p.normal == Eigen::Vector3d(0, 0, -1));
  // Centre on the triangle: minus the face normal (into an outward-wound solid).
  p = medspheres::ball_triangle_proximity(Eigen::Vector3d(0.5, 0.5, 0), 1.0, a, b, c);
  CHECK(p.distance == -1.0);
  CHECK(p.normal == Eigen::Vector3d(0, 0, -1));
  p = medspheres::ball_triangle_proximity(Eigen::Vector3d(-3, 0, 0), 0.5, a, b, c);
  CHECK(p.distance == 2.5);
  CHECK(p.normal == Eigen::Vector3d(1, 0, 0));
}

TEST_CASE("TriangleTree nodes contain their triangles", "[triangle_tree]") {
  const TriangleMesh mesh = mt::bumpy_sphere(14, 23, 1.3);
  const TriangleTree tree(mesh);
  CHECK(tree.num_triangles() == mesh.num_triangles());
  CHECK(tree.num_nodes() == 2 * mesh.num_triangles() - 1);
  std::vector<std::size_t> all = tree.triangles_below(0);
  std::sort(all.begin(), all.end());
  for (std::size_t i = 0; i < all.size(); ++i) CHECK(all[i] == i);
  for (std::size_t node = 0; node < tree.num_nodes(); ++node) {
    const Rss rss = tree.node_bounds(node);
    for (std::size_t t : tree.triangles_below(node)) {
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d q = rss.axis.transpose() * (mesh.corner(t, k) - rss.corner);
        const double x = std::clamp(q.x(), 0.0, rss.length[0]);
        const double y = std::clamp(q.y(), 0.0, rss.length[1]);
        CHECK(Eigen::Vector3d(q.x() - x, q.y() - y, q.z()).norm() <= rss.radius);
      }
    }
  }
  CHECK_THROWS_AS(tree.node_bounds(tree.num_nodes()), std::out_of_range);
}

TEST_CASE("TriangleTree rejects bad meshes and accepts empty ones", "[triangle_tree]") {
  TriangleMesh m;
  const TriangleTree empty(m);
  CHECK_FALSE(empty.root().has_value());
  m.vertices = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0)};
  m.triangles = {{0, 1, 3}};
  CHECK_THROWS_AS(TriangleTree(m), std::invalid_argument);
  m.triangles = {{0, 1, 2}};
  m.vertices[1].y() = std::nan("");
  CHECK_THROWS_AS(TriangleTree(m), std::invalid_argument);
  std::mt19937 rng(1);
  const SphereTree spheres(mt::random_sphere_set(rng, 5));
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  CHECK_FALSE(medspheres::distance(spheres, I, empty, I).found());
  CHECK_FALSE(medspheres::collide(spheres, I, empty, I));
}

TEST_CASE("Sphere tree to triangle mesh queries match brute force", "[triangle_tree]") {
  const TriangleMesh mesh = mt::bumpy_sphere(12, 17, 1.0);
  const TriangleTree tree(mesh);
  std::mt19937 rng(9);
  int separated = 0, touching = 0;
  for (int k = 0; k < 80; ++k) {
    medspheres::SphereTreeOptions options;
    options.kind =
        k % 2 ? medspheres::BoundingVolumeKind::ball : medspheres::BoundingVolumeKind::rss;
    options.max_leaf_size = 1 + k % 3;
    const SphereSet set = mt::random_sphere_set(rng, 1 + rng() % 60, 0.6, 0.02, 0.3);
    const SphereTree spheres(set, options);
    const Eigen::Isometry3d X_WA = mt::random_pose(rng, 1.5);
    const Eigen::Isometry3d X_WB = mt::random_pose(rng, 1.5);
    // Brute force, in W.
    double best = std::numeric_limits<double>::infinity();
    std::set<std::pair<std::intptr_t, std::intptr_t>> overlaps;
    for (std::size_t i = 0; i < set.size(); ++i) {
      const Eigen::Vector3d c = X_WA * set.spheres[i].center;
      for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
        const double sd = mt::oracle_distance(c, X_WB * mesh.corner(t, 0), X_WB * mesh.corner(t, 1),
                                              X_WB * mesh.corner(t, 2)) -
                          set.spheres[i].radius;
        best = std::min(best, sd);
        if (sd <= 0.0)
          overlaps.insert({static_cast<std::intptr_t>(i), static_cast<std::intptr_t>(t)});
      }
    }
    const double tol = 1e-12 * (4 + X_WA.translation().norm() + X_WB.translation().norm());
    const TreeDistance sd = medspheres::signed_distance(spheres, X_WA, tree, X_WB);
    CHECK(sd.distance == Approx(best).margin(tol));
    REQUIRE(sd.found());
    const Sphere& s = set.spheres[static_cast<std::size_t>(sd.sphere_a)];
    const Eigen::Vector3d c = X_WA * s.center;
    const std::size_t t = static_cast<std::size_t>(sd.primitive_b);
    const Eigen::Vector3d t0 = X_WB * mesh.corner(t, 0), t1 = X_WB * mesh.corner(t, 1),
                          t2 = X_WB * mesh.corner(t, 2);
    CHECK(mt::oracle_distance(c, t0, t1, t2) - s.radius == Approx(best).margin(tol));
    CHECK(mt::oracle_distance(sd.p_WPb, t0, t1, t2) <= tol);  // on the triangle
    CHECK((sd.p_WPb - c).norm() == Approx(s.radius + best).margin(tol));
    CHECK((sd.p_WPa - c).norm() == Approx(s.radius).margin(tol));
    const TreeDistance d = medspheres::distance(spheres, X_WA, tree, X_WB);
    if (best > tol) {
      ++separated;
      CHECK(d.distance == Approx(best).margin(tol));
      CHECK_FALSE(medspheres::collide(spheres, X_WA, tree, X_WB));
    } else {
      ++touching;
      CHECK(d.distance <= tol);
      CHECK(medspheres::collide(spheres, X_WA, tree, X_WB) == !overlaps.empty());
    }
    std::vector<TreeContact> cs;
    medspheres::contacts(spheres, X_WA, tree, X_WB, 1u << 30, cs);
    std::set<std::pair<std::intptr_t, std::intptr_t>> got;
    for (const TreeContact& ct : cs) {
      got.insert({ct.sphere_a, ct.primitive_b});
      CHECK(ct.depth >= 0.0);
      CHECK(ct.n_W.norm() == Approx(1.0));
    }
    CHECK(got == overlaps);
  }
  CHECK(separated > 10);
  CHECK(touching > 10);
}
