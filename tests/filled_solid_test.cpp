// The filled solid of a thin-walled cup (a closed mesh whose material is a thin shell around
// a cavity open at the top), against its closed form: the cylinder it walls. Then a robot
// whose one link is that cup: its inner set fills the filled solid, its covering set covers
// the cup's real surface, and certified queries bound the real solid by its surface points.
#include <cmath>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/check/robot_checker.h"
#include "medspheres/check/scene.h"
#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/mesh/filled_solid.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_bake/robot_bake.h"
#include "medspheres/robot_file.h"
#include "support/mesh_writers.h"
#include "support/random_points.h"
#include "support/temp_dir.h"

using namespace medspheres;
using test::TempDir;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSlices = 48;
// The cup: outer radius R, height H, walls and bottom of thickness W, open at z = H.
constexpr double kR = 0.5, kH = 2.0, kW = 0.03;

// The closed profile (r, z) turned about the z axis (kSlices-gon rings; r = 0: a pole),
// outward wound.
TriangleMesh revolve(const std::vector<Eigen::Vector2d>& profile) {
  TriangleMesh m;
  std::vector<std::vector<int>> rings;
  for (const Eigen::Vector2d& p : profile) {
    std::vector<int> ring;
    if (p.x() == 0.0) {
      ring.assign(kSlices, static_cast<int>(m.vertices.size()));
      m.vertices.emplace_back(0.0, 0.0, p.y());
    } else {
      for (int k = 0; k < kSlices; ++k) {
        const double a = 2.0 * kPi * k / kSlices;
        ring.push_back(static_cast<int>(m.vertices.size()));
        m.vertices.emplace_back(p.x() * std::cos(a), p.x() * std::sin(a), p.y());
      }
    }
    rings.push_back(ring);
  }
  for (std::size_t i = 0; i + 1 < rings.size(); ++i)
    for (int k = 0; k < kSlices; ++k) {
      const int k1 = (k + 1) % kSlices;
      const int a = rings[i][k], b = rings[i][k1], c = rings[i + 1][k1], d = rings[i + 1][k];
      if (a != b) m.triangles.push_back({a, b, c});
      if (c != d) m.triangles.push_back({a, c, d});
    }
  if (analyze_mesh(m).signed_volume < 0.0)
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

TriangleMesh cup() {
  return revolve({{0.0, 0.0}, {kR, 0.0}, {kR, kH}, {kR - kW, kH}, {kR - kW, kW}, {0.0, kW}});
}

// The area of the kSlices-gon inscribed in the circle of radius r.
double polygon_area(double r) {
  return 0.5 * kSlices * r * r * std::sin(2.0 * kPi / kSlices);
}

}  // namespace

TEST_CASE("filled solid: a thin-walled cup fills to the cylinder it walls", "[filled]") {
  const TriangleMesh mesh = cup();
  const MeshReport report = analyze_mesh(mesh);
  REQUIRE(report.is_closed_outward());
  // The shell's volume, closed form: the outer prism less the cavity's.
  const double shell = polygon_area(kR) * kH - polygon_area(kR - kW) * (kH - kW);
  CHECK(report.signed_volume == Approx(shell).epsilon(1e-9));
  const double cylinder = polygon_area(kR) * kH;

  const RobustSolid filled = make_filled_solid(mesh, "cup");
  const MeshReport filled_report = analyze_mesh(filled.mesh);
  REQUIRE(filled_report.is_closed_outward());
  // A ball of radius t >= L/2 = 1 on the rim (radius < 0.5) dips at most
  // 1 - sqrt(1 - 0.25) < 0.134 into the cavity, and the walls stick out by less than
  // (1 + sqrt(3)/2 + sqrt(3)) h (robust_solid.h).
  const double h = filled.cell;
  const double out = (1.0 + std::sqrt(3.0) / 2.0 + std::sqrt(3.0)) * h;
  CHECK(filled_report.signed_volume >= polygon_area(kR - kW) * (kH - 0.134));
  CHECK(filled_report.signed_volume <= kPi * (kR + out) * (kR + out) * (kH + 2.0 * out));
  CHECK(is_thin_shell(report.signed_volume, filled_report.signed_volume));
  CHECK_FALSE(is_thin_shell(cylinder, filled_report.signed_volume));
  CHECK(is_thin_shell(shell_fraction(mesh, report, "cup")));

  // Monte Carlo: the cavity below the dent is inside; points farther out than the walls
  // reach are outside.
  const MeshQuery query(filled.mesh);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    const double r = (kR - kW) * std::cos(kPi / kSlices) * std::sqrt(u01(rng));
    const double a = 2.0 * kPi * u01(rng);
    const Eigen::Vector3d p(r * std::cos(a), r * std::sin(a), kW + (kH - 0.134 - kW) * u01(rng));
    INFO("cavity point " << p.transpose());
    REQUIRE(query.inside(p));
    const double far = kR + out + 1e-9;
    const Eigen::Vector3d q(far * std::cos(a), far * std::sin(a), kH * u01(rng));
    INFO("outside point " << q.transpose());
    REQUIRE_FALSE(query.inside(q));
  }
}

TEST_CASE("filled solid: a solid cylinder is no thin shell", "[filled]") {
  const TriangleMesh mesh = make_cylinder(kR, 0.5 * kH, kSlices);
  const RobustSolid filled = make_filled_solid(mesh, "cylinder");
  const MeshReport report = analyze_mesh(mesh);
  CHECK_FALSE(is_thin_shell(report.signed_volume, analyze_mesh(filled.mesh).signed_volume));
  const double fraction = shell_fraction(mesh, report, "cylinder");
  CHECK(fraction > 0.5);
  CHECK_FALSE(is_thin_shell(fraction));
  CHECK_FALSE(is_thin_shell(0.0, 1.0));
  CHECK_FALSE(is_thin_shell(std::nan(""), 1.0));
}

TEST_CASE("filled solid: a robot's thin-shelled link", "[filled][robot]") {
  TempDir dir;
  const TriangleMesh mesh = cup();
  dir.write("cup.stl", test::to_stl_binary(mesh));
  const std::string urdf = dir.write("cup.urdf", R"(<?xml version="1.0"?>
<robot name="cup">
  <link name="cup">
    <collision><geometry><mesh filename="cup.stl"/></geometry></collision>
  </link>
</robot>
)");
  const UrdfRobot robot = read_urdf(urdf);
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  RobotBakeOptions options;
  options.budget.per_link = 32;
  options.request.record_seconds = false;
  options.fill_thin_shells = true;
  const RobotBakeResult after = bake_robot(robot, solids, options);
  options.fill_thin_shells = false;
  const RobotBakeResult before = bake_robot(robot, solids, options);
  REQUIRE(after.links.size() == 1);
  const LinkBakeStats& s = after.links[0];
  INFO("note: " << s.note << "; nerr " << s.nerr << " (real solid: " << before.links[0].nerr
                << ")");
  CHECK(s.note.find("filled solid") != std::string::npos);
  CHECK(before.links[0].note.find("filled solid") == std::string::npos);
  CHECK(s.nerr_kind == "exact");
  CHECK(s.nerr <= 0.3);  // the issue's target at 32 spheres
  CHECK(before.links[0].nerr > 0.5);
  CHECK(s.spheres <= 32);
  CHECK(s.inner_filled);
  CHECK_FALSE(before.links[0].inner_filled);
  const nlohmann::json meta = nlohmann::json::parse(after.model.metadata_json);
  CHECK(meta["links"]["cup"]["inner_solid"] == "filled");
  CHECK_FALSE(
      nlohmann::json::parse(before.model.metadata_json)["links"]["cup"].contains("inner_solid"));

  // Every inner ball lies inside the filled solid; some sit in the cavity, outside the
  // cup's material.
  const LinkSpheres& sets = after.model.links[0].spheres;
  CHECK(medspheres::fcl::records_filled_inner(sets.inner.metadata_json));
  CHECK_FALSE(medspheres::fcl::records_filled_inner(sets.outer.metadata_json));
  CHECK_FALSE(
      medspheres::fcl::records_filled_inner(before.model.links[0].spheres.inner.metadata_json));
  const MeshQuery filled(make_filled_solid(mesh, "cup").mesh), real(mesh);
  std::size_t in_cavity = 0;
  for (const Sphere& b : sets.inner.spheres) {
    CHECK(filled.inside(b.center));
    CHECK(filled.closest_point(b.center).distance() >= b.radius);
    in_cavity += !real.inside(b.center);
  }
  CHECK(in_cavity > 0);

  // The covering set is certified on the real surface, and covers sampled points of it.
  CHECK(s.outer_certified);
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::size_t> pick(0, mesh.triangles.size() - 1);
  for (int i = 0; i < 3000; ++i) {
    const auto& t = mesh.triangles[pick(rng)];
    const Eigen::Vector3d p = test::random_point_on_triangle(
        mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]], rng);
    bool covered = false;
    for (const Sphere& b : sets.outer.spheres) covered |= (p - b.center).norm() <= b.radius;
    INFO("surface point " << p.transpose());
    REQUIRE(covered);
  }

  // Certified queries bound the real solid from inside by its surface points alone.
  const medspheres::fcl::BoundedGeometry with_mesh = medspheres::fcl::BoundedGeometry::from_link(
      "cup", sets, medspheres::fcl::make_mesh_model(mesh));
  CHECK(with_mesh.inner().num_spheres() == mesh.vertices.size());
  for (std::size_t i = 0; i < with_mesh.inner().num_spheres(); ++i)
    REQUIRE(with_mesh.inner().sphere(i).radius == 0.0);
  const medspheres::fcl::BoundedGeometry real_inner = medspheres::fcl::BoundedGeometry::from_link(
      "cup", before.model.links[0].spheres, medspheres::fcl::make_mesh_model(mesh));
  CHECK(real_inner.inner().num_spheres() ==
        mesh.vertices.size() + before.model.links[0].spheres.inner.size());
}

TEST_CASE("filled solid: the mark survives the robot file, and certified checks heed it",
          "[filled][robot]") {
  TempDir dir;
  const TriangleMesh mesh = cup();
  dir.write("cup.stl", test::to_stl_binary(mesh));
  const std::string urdf = dir.write("cup.urdf", R"(<?xml version="1.0"?>
<robot name="cup"><link name="cup">
  <collision><geometry><mesh filename="cup.stl"/></geometry></collision>
</link></robot>
)");
  const UrdfRobot robot = read_urdf(urdf);
  RobotBakeOptions options;
  options.budget.per_link = 32;
  options.fill_thin_shells = true;
  const RobotBakeResult baked = bake_robot(robot, load_link_solids(robot), options);
  const RobotModel loaded = parse_robot(robot_to_json(baked.model), "cup.robot.json");
  REQUIRE(loaded.links[0].spheres.inner_filled);
  RobotModel unmarked = loaded;
  unmarked.links[0].spheres.inner_filled = false;
  CHECK_FALSE(parse_robot(robot_to_json(unmarked), "x").links[0].spheres.inner_filled);
  CHECK_THROWS_WITH(parse_robot(std::regex_replace(robot_to_json(baked.model),
                                                   std::regex("\"filled\""), "\"hollow\""),
                                "cup.robot.json"),
                    Catch::Contains("cup.robot.json") && Catch::Contains("inner_solid"));

  // Without a mesh the filled balls are left out: the link has no inner bounds.
  CHECK(medspheres::fcl::BoundedGeometry::from_link("cup", loaded.links[0].spheres)
            .inner()
            .num_spheres() == 0);
  CHECK(medspheres::fcl::BoundedGeometry::from_link("cup", unmarked.links[0].spheres)
            .inner()
            .num_spheres() == unmarked.links[0].spheres.inner.size());

  // A ball in the cavity, about a filled inner ball's centre, 5 mm clear of the material
  // (so the covering balls, which stick out into the cavity, do not prove it free): the
  // unmarked robot claims a collision, the marked one never does.
  const MeshQuery real(mesh);
  const Sphere* deepest = nullptr;
  double clear = 0.0;
  for (const Sphere& b : loaded.links[0].spheres.inner.spheres) {
    const double d = real.closest_point(b.center).distance();
    if (!real.inside(b.center) && d > clear) clear = d, deepest = &b;
  }
  REQUIRE(deepest != nullptr);
  REQUIRE(clear > 0.02);
  check::Scene scene;
  scene.add_sphere(deepest->center, clear - 0.005, "in the cavity");
  const double q[1] = {0.0};
  CHECK(check::RobotChecker(unmarked, scene).check(q, check::Mode::bounds) ==
        check::Verdict::colliding);
  CHECK(check::RobotChecker(loaded, scene).check(q, check::Mode::bounds) !=
        check::Verdict::colliding);
}
