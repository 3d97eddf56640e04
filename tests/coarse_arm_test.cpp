// The generated coarse arm (support/coarse_arm.h) as the URDF reader sees it: eleven closed
// link meshes of 32 to 300 triangles, seven revolute joints and a mimic gripper, the Panda-like
// chain's pose at q = 0 in closed form, and the same bytes on every write.
#include <algorithm>
#include <set>
#include <string>

#include <catch2/catch.hpp>

#include "medspheres/forward_kinematics.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"
#include "support/coarse_arm.h"
#include "support/temp_dir.h"

using namespace medspheres;
using medspheres::test::TempDir;

TEST_CASE("coarse arm: eleven closed link meshes of 32 to 300 triangles, read back", "[robot]") {
  TempDir dir;
  const UrdfRobot robot = read_urdf(test::write_coarse_arm(dir.path()));
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  const std::vector<test::CoarseArmLink> links = test::coarse_arm_links();
  REQUIRE(links.size() == test::kCoarseArmLinks);
  std::size_t with_geometry = 0, triangles = 0;
  for (const LinkSolid& s : solids) {
    if (s.empty()) {
      CHECK(s.link == "link8");
      continue;
    }
    const test::CoarseArmLink& l = links[with_geometry++];
    CHECK(s.link == l.name);
    REQUIRE(s.parts.size() == 1);
    CHECK(s.spheres.empty());
    const TriangleMesh placed = s.placed_mesh();
    CHECK(placed.triangles.size() >= 32);
    CHECK(placed.triangles.size() <= 300);
    CHECK(analyze_mesh(placed).is_closed_outward());
    REQUIRE(placed.num_vertices() == l.mesh.num_vertices());
    // The loader may reorder vertices and reads OBJ coordinates as floats: each vertex read
    // is within a float's rounding (of a metre) of some generated one.
    for (const Eigen::Vector3d& v : placed.vertices) {
      double nearest = 1.0;
      for (const Eigen::Vector3d& w : l.mesh.vertices) nearest = std::min(nearest, (v - w).norm());
      CHECK(nearest < 1e-7);
    }
    triangles += placed.triangles.size();
  }
  CHECK(with_geometry == test::kCoarseArmLinks);
  CHECK(triangles == 1472);
}

TEST_CASE("coarse arm: seven revolute joints, a mimic gripper, the chain's pose at q = 0",
          "[robot]") {
  TempDir dir;
  const UrdfRobot robot = read_urdf(test::write_coarse_arm(dir.path()));
  std::size_t revolute = 0, mimic = 0;
  for (const Joint& j : robot.model.joints) {
    revolute += j.type == JointType::kRevolute ? 1 : 0;
    if (j.mimic) {
      ++mimic;
      CHECK(j.mimic->joint == "finger_joint1");
    }
    if (j.type == JointType::kRevolute || j.type == JointType::kPrismatic) {
      REQUIRE(j.limits);
      CHECK(j.limits->lower < j.limits->upper);
    }
  }
  CHECK(revolute == test::kCoarseArmRevoluteJoints);
  CHECK(mimic == 1);
  const KinematicTree tree(robot.model);
  CHECK(tree.num_positions() == 8);  // seven revolute joints and finger_joint1
  // At q = 0 the chain stands upright: link5's origin 0.333 + 0.316 + 0.384 m above the
  // base, and link8 (the flange) 0.088 m forward and 0.107 m below it, its z axis down.
  const auto X = tree.link_poses(Eigen::VectorXd::Zero(8));
  const Eigen::Isometry3d& X_W5 = X[tree.link_index("link5")];
  const Eigen::Isometry3d& X_W8 = X[tree.link_index("link8")];
  CHECK((X_W5.translation() - Eigen::Vector3d(0, 0, 1.033)).norm() < 1e-12);
  CHECK((X_W8.translation() - Eigen::Vector3d(0.088, 0, 0.926)).norm() < 1e-12);
  CHECK((X_W8.linear().col(2) - Eigen::Vector3d(0, 0, -1)).norm() < 1e-12);
}

TEST_CASE("coarse arm: the same bytes on every write", "[robot]") {
  TempDir a, b;
  const std::string ua = test::write_coarse_arm(a.path());
  const std::string ub = test::write_coarse_arm(b.path());
  CHECK(test::read_file(ua) == test::read_file(ub));
  std::set<std::string> differ;
  for (const test::CoarseArmLink& l : test::coarse_arm_links()) {
    const std::string mesh = "meshes/" + l.name + ".obj";
    if (test::read_file(a.file(mesh)) != test::read_file(b.file(mesh))) differ.insert(mesh);
    CHECK(!test::read_file(a.file(mesh)).empty());
  }
  CHECK(differ.empty());
}
