// fcl_from_scene (medspheres/fcl/fcl_from_scene.h) against closed forms: FCL's distance from
// a small ball at seeded points to each object it makes is the point's distance to the
// Scene's obstacle, written here from the Scene's conventions (a capsule's and a
// cylinder's axis along z, `length` the segment's; a mesh by the point-triangle oracle);
// and scene_from_fcl of the objects gives the Scene back.

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <fcl/fcl.h>
#include <catch2/catch.hpp>

#include "medspheres/fcl/fcl_from_scene.h"
#include "medspheres/fcl/scene_from_fcl.h"
#include "medspheres/mesh/mesh_generators.h"
#include "support/check_fixtures.h"
#include "support/point_triangle_oracle.h"

using namespace medspheres;
namespace mf = medspheres::fcl;
using check::ShapeKind;
using test::pose_of;

namespace {

check::Scene every_kind() {
  check::Scene s;
  s.add_sphere({-0.4, 0.4, 0.6}, 0.12, "ball");
  s.add_box({0.3, 0.2, 0.4}, pose_of({0.5, 0.2, 0.3}, 0.2, 0.0, 0.5), "crate");
  s.add_capsule(0.06, 0.5, pose_of({0.1, -0.5, 0.5}, 0.7), "pole");
  s.add_cylinder(0.08, 0.4, pose_of({-0.5, -0.3, 0.3}, 0.0, 0.9), "can");
  s.add_mesh(make_icosphere(0.15, 1), pose_of({0.3, 0.5, 0.9}, 0.3), "bowl");
  s.add_cells({{0.7, 0.0, 0.9}, {0.74, 0.0, 0.9}, {0.7, 0.04, 0.94}}, 0.04, "octomap");
  return s;
}

// The distance from p (in O) to the obstacle, outside it.
double box_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& half) {
  return (p.cwiseAbs() - half).cwiseMax(0.0).norm();
}
double axial_distance(const Eigen::Vector3d& p, double r, double length, bool capsule) {
  const double h = std::abs(p.z()) - length / 2, rho = std::hypot(p.x(), p.y());
  if (capsule) return std::hypot(rho, std::max(h, 0.0)) - r;
  return std::hypot(std::max(rho - r, 0.0), std::max(h, 0.0));
}
double closed_form(const check::SceneObject& o, const Eigen::Vector3d& p_W) {
  const Eigen::Vector3d p = o.X_WO.inverse() * p_W;
  switch (o.kind) {
    case ShapeKind::sphere:
      return p.norm() - o.radius;
    case ShapeKind::box:
      return box_distance(p, o.size / 2);
    case ShapeKind::capsule:
      return axial_distance(p, o.radius, o.length, true);
    case ShapeKind::cylinder:
      return axial_distance(p, o.radius, o.length, false);
    case ShapeKind::mesh:
      return test::oracle_mesh_distance(o.mesh, p);
    default:
      FAIL("not a single obstacle");
      return 0;
  }
}

double fcl_distance(const ::fcl::CollisionObjectd& o, const Eigen::Vector3d& p, double ball) {
  const ::fcl::CollisionObjectd probe(std::make_shared<::fcl::Sphered>(ball), pose_of(p));
  ::fcl::DistanceRequestd request;
  ::fcl::DistanceResultd result;
  ::fcl::distance(&o, &probe, request, result);
  return result.min_distance + ball;
}

}  // namespace

TEST_CASE("fcl_from_scene: each obstacle at the distances of its closed form", "[fcl_from_scene]") {
  const check::Scene scene = every_kind();
  const mf::FclObjects objs = mf::fcl_from_scene(scene);
  REQUIRE(objs.objects.size() == 5 + 3);  // the three cells one box each
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr double kBall = 0.005;
  int judged = 0;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), 0.6 + 0.6 * u(rng));
    for (std::size_t k = 0; k < objs.objects.size(); ++k) {
      double expected = 0;
      if (k < 5) {
        expected = closed_form(scene.objects()[k], p);
      } else {
        const check::SceneObject& cells = scene.objects()[5];
        expected = box_distance(p - cells.points[k - 5], Eigen::Vector3d::Constant(0.02));
      }
      if (expected < 2 * kBall) continue;  // FCL reports no distance for touching shapes
      ++judged;
      INFO("object " << k << " at " << p.transpose());
      CHECK(fcl_distance(*objs.objects[k], p, kBall) == Approx(expected).margin(1e-6));
    }
  }
  CHECK(judged > 2000);
}

TEST_CASE("fcl_from_scene: scene_from_fcl gives the obstacles back", "[fcl_from_scene]") {
  const check::Scene scene = every_kind();
  const mf::FclObjects objs = mf::fcl_from_scene(scene);
  const mf::FclScene back = mf::scene_from_fcl(objs.objects);
  REQUIRE(back.scene.size() == 8);
  for (std::size_t k = 0; k < 8; ++k) {
    const check::SceneObject& b = back.scene.objects()[k];
    CHECK(back.source[k] == k);
    if (k >= 5) {  // a cell as a box of its side at its centre
      CHECK(b.kind == ShapeKind::box);
      CHECK(b.size == Eigen::Vector3d::Constant(0.04));
      CHECK(b.X_WO.translation() == scene.objects()[5].points[k - 5]);
      CHECK(b.X_WO.linear().isIdentity(0.0));
      continue;
    }
    const check::SceneObject& a = scene.objects()[k];
    CHECK(b.kind == a.kind);
    CHECK(b.X_WO.matrix() == a.X_WO.matrix());
    CHECK(b.size == a.size);
    CHECK(b.radius == a.radius);
    CHECK(b.length == a.length);
    CHECK(b.mesh.vertices == a.mesh.vertices);
    CHECK(b.mesh.triangles == a.mesh.triangles);
  }
}

TEST_CASE("fcl_from_scene: a point cloud is refused, named", "[fcl_from_scene]") {
  check::Scene scene = every_kind();
  scene.add_points({{0, 0, 1}, {0, 0.1, 1}}, "lidar");
  try {
    mf::fcl_from_scene(scene);
    FAIL("no error");
  } catch (const std::invalid_argument& e) {
    CHECK_THAT(e.what(), Catch::Contains("scene object 6 \"lidar\"") &&
                             Catch::Contains("point cloud") && Catch::Contains("cells"));
  }
}
