// Baking robots: every inner sphere inside its link's solid, placed by a transform written
// out here; budgets; shared bakes; the same spheres for every number of jobs.
#include <algorithm>
#include <filesystem>
#include <map>
#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/error.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/robot_bake/robot_bake.h"
#include "medspheres/robot_bake/robot_fit.h"
#include "support/sanitizer_build.h"
#include "support/urdf_fixtures.h"

using namespace medspheres;
using medspheres::test::TempDir;

namespace {

UrdfRobot read_arm(const TempDir& dir) {
  UrdfReadOptions options;
  options.packages.explicit_dirs["arm_pkg"] = (dir.path() / "pkg/arm_pkg").string();
  return read_urdf(test::write_arm(dir), options);
}

TriangleMesh moved(TriangleMesh m, const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
  for (Eigen::Vector3d& v : m.vertices) v = r * v + t;
  return m;
}

TriangleMesh joined(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh out = a;
  const int base = static_cast<int>(a.vertices.size());
  out.vertices.insert(out.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const auto& t : b.triangles)
    out.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  return out;
}

// The arm's link solids in their link frames, built here from the URDF's numbers.
std::map<std::string, TriangleMesh> arm_solids_by_hand(const TempDir& dir) {
  std::map<std::string, TriangleMesh> out;
  const TriangleMesh cylinder = make_cylinder(0.03, 0.06, kCylinderSlices);
  out["base"] = joined(make_box({0.1, 0.05, 0.025}, 1),
                       moved(cylinder, test::rpy_matrix(0, 1.5707963267948966, 0), {0, 0, 0.05}));
  TriangleMesh forearm = load_mesh((dir.path() / "meshes/forearm.obj").string()).mesh;
  for (Eigen::Vector3d& v : forearm.vertices) v = v.cwiseProduct(Eigen::Vector3d(2, 0.5, 1.5));
  out["forearm"] = moved(forearm, test::rpy_matrix(0.3, -0.4, 0.9), {0.1, -0.05, 0.2});
  out["hand"] = load_mesh((dir.path() / "pkg/arm_pkg/meshes/hand.obj").string()).mesh;
  return out;
}

// Every sphere inside the solid: its centre inside (winding number) and no triangle
// nearer than its radius; or the hand's sphere primitive itself.
void check_inside(const RobotModel& model, const std::map<std::string, TriangleMesh>& solids) {
  for (const Link& link : model.links) {
    INFO("link " << link.name);
    const auto it = solids.find(link.name);
    if (it == solids.end()) {
      CHECK(link.spheres.inner.empty());
      continue;
    }
    const MeshQuery query(it->second);
    std::size_t primitives = 0;
    for (const Sphere& s : link.spheres.inner.spheres) {
      if (link.name == "hand" && s.center == Eigen::Vector3d(0, 0, 0.06) && s.radius == 0.015) {
        ++primitives;
        continue;
      }
      CHECK(query.winding_number(s.center) > 0.5);
      CHECK(query.closest_point(s.center).distance() >= s.radius);
    }
    CHECK(primitives == (link.name == "hand" ? 1u : 0u));
    CHECK(link.spheres.inner.size() > primitives);
  }
}

RobotBakeOptions budget_options(std::size_t per_link, int jobs) {
  RobotBakeOptions options;
  options.budget.per_link = per_link;
  options.jobs = jobs;
  options.request.measure = false;
  return options;
}

}  // namespace

TEST_CASE("robot bake: every inner sphere lies inside its link's solid", "[robot][bake]") {
  TempDir dir;
  const UrdfRobot robot = read_arm(dir);
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  RobotBakeOptions options = budget_options(12, 1);
  options.request.measure = true;
  const RobotBakeResult result = bake_robot(robot, solids, options);
  REQUIRE(result.model.links.size() == 4);
  check_inside(result.model, arm_solids_by_hand(dir));
  for (const LinkBakeStats& s : result.links) {
    INFO(s.link);
    CHECK(s.spheres <= 12);
    CHECK(s.spheres == result.model.find_link(s.link)->spheres.inner.size());
  }
  CHECK(result.links[3].note == "no collision geometry");
  CHECK(result.links[2].budget == std::optional<std::size_t>(11));  // one for the primitive
  CHECK(result.links[1].nerr_kind == "exact");
  CHECK(result.links[1].nerr > 0.0);
  CHECK(result.links[1].nerr < 1.0);
}

TEST_CASE("robot bake: the same spheres for 1 and 2 jobs, bit for bit", "[robot][bake]") {
  TempDir dir;
  const UrdfRobot robot = read_arm(dir);
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  // 8 spheres a link in the sanitizer builds, where the bakes take most of the time; the
  // comparison holds at any budget.
  const std::size_t budget = test::kSanitizerBuild ? 8 : 20;
  const RobotBakeResult one = bake_robot(robot, solids, budget_options(budget, 1));
  const RobotBakeResult two = bake_robot(robot, solids, budget_options(budget, 2));
  for (std::size_t i = 0; i < one.model.links.size(); ++i) {
    const auto& a = one.model.links[i].spheres.inner.spheres;
    const auto& b = two.model.links[i].spheres.inner.spheres;
    REQUIRE(a.size() == b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
      CHECK(a[k].center == b[k].center);
      CHECK(a[k].radius == b[k].radius);
    }
  }
}

TEST_CASE("robot bake: links with the same mesh and scale are baked once", "[robot][bake]") {
  TempDir dir;
  dir.write("part.obj", test::to_obj(make_capsule(0.02, 0.04, 16, 4)));
  const UrdfRobot robot = read_urdf(dir.write("twins.urdf", R"(<robot name="twins">
  <link name="a"><collision><geometry><mesh filename="part.obj"/></geometry></collision></link>
  <link name="b"><collision><origin xyz="0.5 0 0" rpy="0.2 0.3 1.1"/>
    <geometry><mesh filename="part.obj"/></geometry></collision></link>
  <joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>
</robot>)"));
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  const RobotBakeResult result = bake_robot(robot, solids, budget_options(10, 2));
  CHECK(result.links[0].baked_as.empty());
  CHECK(result.links[1].baked_as == "a");
  const auto& a = result.model.links[0].spheres.inner.spheres;
  const auto& b = result.model.links[1].spheres.inner.spheres;
  REQUIRE(a.size() == b.size());
  const Eigen::Isometry3d x = solids[1].parts[0].origin;
  const MeshQuery query_b(solids[1].placed_mesh());
  for (std::size_t k = 0; k < a.size(); ++k) {
    CHECK((x * a[k].center - b[k].center).norm() < 1e-15);
    CHECK(b[k].radius < a[k].radius);  // shrunk for the rounding of the move
    CHECK(b[k].radius > a[k].radius * (1 - 1e-12));
    CHECK(query_b.winding_number(b[k].center) > 0.5);
    CHECK(query_b.closest_point(b[k].center).distance() >= b[k].radius);
  }
}

TEST_CASE("robot budgets: shared by surface area, overrides, at least one each", "[robot]") {
  auto box_link = [](const std::string& name, double side, std::size_t primitives) {
    LinkSolid s;
    s.link = name;
    LinkSolidPart part;
    part.mesh = make_box(Eigen::Vector3d::Constant(side / 2), 1);  // area 6 side^2
    s.parts.push_back(part);
    for (std::size_t k = 0; k < primitives; ++k) s.spheres.push_back({Eigen::Vector3d::Zero(), 1});
    return s;
  };
  LinkSolid only_spheres;
  only_spheres.link = "feet";
  only_spheres.spheres.assign(3, Sphere{Eigen::Vector3d::Zero(), 1});
  // Areas 6, 24, 54 (sides 1, 2, 3), total 84.
  const std::vector<LinkSolid> solids = {box_link("s1", 1, 0), box_link("s2", 2, 2),
                                         box_link("s3", 3, 0), only_spheres, LinkSolid{}};
  RobotBudget budget;
  budget.total = 50;
  // 50 - 3 (feet) - 2 (s2's primitives) = 45: 1 each, 42 shared 6:24:54, i.e. 3, 12, 27.
  auto k = link_bake_budgets(solids, budget, "r.urdf");
  CHECK(k[0] == std::optional<std::size_t>(4));
  CHECK(k[1] == std::optional<std::size_t>(13));
  CHECK(k[2] == std::optional<std::size_t>(28));
  CHECK_FALSE(k[3]);
  CHECK_FALSE(k[4]);
  // 40: 35 to share, 32 by area: 2.29, 9.14, 20.57 -> 2, 9, 20 and the last to s3 (0.57).
  budget.total = 40;
  k = link_bake_budgets(solids, budget, "r.urdf");
  CHECK(*k[0] + *k[1] + *k[2] == 35);
  CHECK(k[0] == std::optional<std::size_t>(3));
  CHECK(k[1] == std::optional<std::size_t>(10));
  CHECK(k[2] == std::optional<std::size_t>(22));
  // An override takes its link out of the sharing.
  budget.links["s3"] = 5;
  k = link_bake_budgets(solids, budget, "r.urdf");
  CHECK(k[2] == std::optional<std::size_t>(5));
  CHECK(*k[0] + *k[1] == 40 - 3 - 2 - 5);
  budget.total = 11;  // 3 + 2 + 5 fixed, two links to bake need 2 more
  CHECK_THROWS_AS(link_bake_budgets(solids, budget, "r.urdf"), InputError);
  budget.total = 12;
  k = link_bake_budgets(solids, budget, "r.urdf");
  CHECK(k[0] == std::optional<std::size_t>(1));
  CHECK(k[1] == std::optional<std::size_t>(1));
  RobotBudget bad;
  bad.links["nowhere"] = 3;
  CHECK_THROWS_AS(link_bake_budgets(solids, bad, "r.urdf"), InputError);
  bad.links = {{"feet", 3}};
  CHECK_THROWS_AS(link_bake_budgets(solids, bad, "r.urdf"), InputError);
  RobotBudget per;
  per.per_link = 2;
  k = link_bake_budgets(solids, per, "r.urdf");
  CHECK(k[0] == std::optional<std::size_t>(2));
  CHECK(k[1] == std::optional<std::size_t>(1));  // 2 minus its 2 primitives, at least 1
  per.total = 10;
  CHECK_THROWS_AS(link_bake_budgets(solids, per, "r.urdf"), InputError);
}

TEST_CASE("robot fit: each link against its own solid, primitives exact", "[robot][bake]") {
  TempDir dir;
  const UrdfRobot robot = read_arm(dir);
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  const RobotBakeResult result = bake_robot(robot, solids, budget_options(10, 1));
  std::map<std::string, SphereSet> spheres;
  for (const Link& l : result.model.links) spheres[l.name] = l.spheres.inner;
  FitOptions fit;
  fit.volume_samples = 20000;
  fit.surface_samples = 2000;
  const std::vector<LinkFit> fits = evaluate_robot_fit(solids, spheres, "arm.json", fit);
  REQUIRE(fits.size() == 4);
  for (int i = 0; i < 3; ++i) {
    INFO(fits[i].link);
    REQUIRE(fits[i].fit);
    CHECK(fits[i].fit->volume.protruding == 0);  // inner sets: nothing sticks out
  }
  CHECK(fits[2].primitives == 1);
  CHECK_FALSE(fits[3].fit);
  // The forearm's spheres moved by 1 cm stick out of its solid.
  spheres["forearm"].spheres[0].center.x() += 0.01;
  const std::vector<LinkFit> off = evaluate_robot_fit(solids, spheres, "arm.json", fit);
  CHECK(off[1].fit->volume.protruding >= 1);
  spheres["elbow"] = SphereSet{};
  CHECK_THROWS_AS(evaluate_robot_fit(solids, spheres, "arm.json", fit), InputError);
}

#ifdef MEDSPHERES_SHARED_MESHES
TEST_CASE("the Unitree G1 bakes, every inner sphere inside its link", "[robot][bake][shared]") {
  const std::string urdf =
      std::string(MEDSPHERES_SHARED_MESHES) + "/../robots/unitree_g1/g1_29dof_rev_1_0.urdf";
  if (!std::filesystem::exists(urdf)) return;  // an older ../shared without robots
  const UrdfRobot robot = read_urdf(urdf);
  REQUIRE(robot.links.size() == 40);
  std::vector<LinkSolid> solids = load_link_solids(robot);
  // Every fourth link in the sanitizer builds, where a link's bake costs ten times more (the
  // rest are links without a solid there); the release build bakes all 40.
  if (test::kSanitizerBuild)
    for (std::size_t i = 0; i < solids.size(); ++i)
      if (i % 4 != 0) solids[i] = LinkSolid{solids[i].link, {}, {}};
  const RobotBakeResult result = bake_robot(robot, solids, budget_options(16, 0));
  std::size_t baked = 0;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const Link& link = result.model.links[i];
    INFO("link " << link.name);
    if (solids[i].empty()) {
      CHECK(link.spheres.inner.empty());
      continue;
    }
    REQUIRE(!link.spheres.inner.empty());
    CHECK(link.spheres.inner.size() <= std::max<std::size_t>(16, solids[i].spheres.size() + 1));
    if (solids[i].parts.empty()) continue;
    ++baked;
    const MeshQuery query(solids[i].placed_mesh(), MeshQueryOptions{2.0, true});
    for (const Sphere& s : link.spheres.inner.spheres) {
      const bool primitive = std::any_of(
          solids[i].spheres.begin(), solids[i].spheres.end(),
          [&](const Sphere& p) { return p.center == s.center && p.radius == s.radius; });
      if (primitive) continue;
      CHECK(query.winding_number(s.center) > 0.5);
      CHECK(query.closest_point(s.center).distance() >= s.radius);
    }
  }
  CHECK(baked > (test::kSanitizerBuild ? 5 : 20));
}
#endif

namespace {

// Points of a cylinder's true surface (axis z, centred at 0): a grid over the side and
// over each disc, the rims included.
std::vector<Eigen::Vector3d> cylinder_surface_points(double r, double half_length) {
  std::vector<Eigen::Vector3d> out;
  const int around = 720;
  for (int i = 0; i < around; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * (i + 0.5) / around;
    const Eigen::Vector2d u(std::cos(a), std::sin(a));
    for (int k = 0; k <= 40; ++k)
      out.emplace_back(r * u.x(), r * u.y(), half_length * (k / 20.0 - 1));
    for (int k = 0; k <= 10; ++k)
      for (const double z : {-half_length, half_length})
        out.emplace_back(r * k / 10.0 * u.x(), r * k / 10.0 * u.y(), z);
  }
  return out;
}

// Points of a capsule's true surface (axis z): the side and two hemispheres.
std::vector<Eigen::Vector3d> capsule_surface_points(double r, double half_length) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < 360; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * (i + 0.5) / 360;
    for (int k = 0; k <= 90; ++k) {
      const double b = 3.14159265358979323846 / 2 * k / 90;
      for (const double side : {-1.0, 1.0})
        out.emplace_back(r * std::cos(b) * std::cos(a), r * std::cos(b) * std::sin(a),
                         side * (half_length + r * std::sin(b)));
    }
  }
  return out;
}

}  // namespace

TEST_CASE("meshed primitives: the surface gap bounds the true surface's distance to the mesh",
          "[robot]") {
  LinkPart cylinder;
  cylinder.shape = PartShape::kCylinder;
  cylinder.size = {0.03, 0.03, 0.12};
  LinkPart capsule = cylinder;
  capsule.shape = PartShape::kCapsule;
  for (const LinkPart& part : {cylinder, capsule}) {
    UrdfRobot robot;
    robot.path = "gap.urdf";
    robot.links.push_back({});
    robot.links[0].name = "l";
    robot.links[0].parts.push_back(part);
    const std::vector<LinkSolid> solids = load_link_solids(robot);
    REQUIRE(solids.size() == 1);
    const LinkSolidPart& meshed = solids[0].parts.at(0);
    INFO(meshed.source);
    const bool is_cylinder = part.shape == PartShape::kCylinder;
    const std::vector<Eigen::Vector3d> points =
        is_cylinder ? cylinder_surface_points(0.03, 0.06) : capsule_surface_points(0.03, 0.06);
    const MeshQuery query(meshed.mesh);
    double worst = 0.0;
    for (const Eigen::Vector3d& p : points)
      worst = std::max(worst, query.closest_point(p).distance());
    CHECK(worst <= meshed.surface_gap);
    CHECK(worst >= 0.5 * meshed.surface_gap);  // the bound is not loose
    if (is_cylinder)
      CHECK(meshed.surface_gap ==
            Approx(0.03 * (1 - std::cos(3.14159265358979323846 / kCylinderSlices))));
    CHECK(solids[0].surface_gap() == meshed.surface_gap);
  }
}

TEST_CASE("robot bake: the outer set covers a cylinder's true surface, not only its mesh",
          "[robot][bake]") {
  TempDir dir;
  const UrdfRobot robot = read_urdf(dir.write("rod.urdf", R"(<?xml version="1.0"?>
<robot name="rod">
  <link name="rod">
    <collision>
      <origin xyz="0 0 0.05" rpy="0 1.5707963267948966 0"/>
      <geometry><cylinder radius="0.03" length="0.12"/></geometry>
    </collision>
  </link>
</robot>
)"));
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  origin.linear() = test::rpy_matrix(0, 1.5707963267948966, 0);
  origin.translation() = Eigen::Vector3d(0, 0, 0.05);
  for (const std::size_t budget : {8, 24}) {
    INFO(budget << " spheres");
    const RobotBakeResult result =
        bake_robot(robot, load_link_solids(robot), budget_options(budget, 1));
    const Link& link = result.model.links.at(0);
    REQUIRE(!link.spheres.outer.empty());
    CHECK(link.spheres.outer_certificate_json.find("\"primitive_surface_gap\":") !=
          std::string::npos);
    // the certificate's own keys (cover_certificate_json), then what the robot file adds
    const nlohmann::json cert = nlohmann::json::parse(link.spheres.outer_certificate_json);
    for (const char* key : {"certified", "triangles", "uncertified_triangles",
                            "proven_uncovered_triangles", "pieces_tested", "max_depth",
                            "surface_covered", "interior_certified", "moved_to_link_frame"})
      CHECK(cert.contains(key));
    CHECK(cert["surface_covered"] == cert["certified"]);
    std::size_t outside = 0;
    for (const Eigen::Vector3d& p : cylinder_surface_points(0.03, 0.06)) {
      const Eigen::Vector3d q = origin * p;
      bool in = false;
      for (const Sphere& s : link.spheres.outer.spheres)
        in = in || (q - s.center).norm() <= s.radius;
      outside += in ? 0 : 1;
    }
    CHECK(outside == 0);
  }
}
