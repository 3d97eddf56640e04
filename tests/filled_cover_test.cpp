// The covering set of a thin open shell (an open box whose walls are 6 mm thick) baked on its
// filled solid (`robot --fill-covers`): certified on the real surface (the certificate run
// again here, and seeded surface points inside the union), and sticking out of the box's
// outside less than the cover of the thin material, by closed-form distances to the box.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/mesh/filled_solid.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_query.h"
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

// The box's outside: [-kA, kA] x [-kB, kB] x [0, kH]; walls and bottom kW thick, open at
// z = kH.
constexpr double kA = 0.2, kB = 0.15, kH = 0.2, kW = 0.006;

// The axis-aligned box [lo, hi] as a closed mesh.
TriangleMesh slab(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh m = make_box(0.5 * (hi - lo));
  for (Eigen::Vector3d& v : m.vertices) v += 0.5 * (lo + hi);
  return m;
}

void append(TriangleMesh& to, const TriangleMesh& m) {
  const int base = static_cast<int>(to.vertices.size());
  to.vertices.insert(to.vertices.end(), m.vertices.begin(), m.vertices.end());
  for (const auto& t : m.triangles) to.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

// The open box: a bottom and four walls, closed slabs that touch and do not overlap.
TriangleMesh open_box() {
  TriangleMesh m;
  append(m, slab({-kA, -kB, 0.0}, {kA, kB, kW}));
  append(m, slab({-kA, -kB, kW}, {-kA + kW, kB, kH}));
  append(m, slab({kA - kW, -kB, kW}, {kA, kB, kH}));
  append(m, slab({-kA + kW, -kB, kW}, {kA - kW, -kB + kW, kH}));
  append(m, slab({-kA + kW, kB - kW, kW}, {kA - kW, kB, kH}));
  return m;
}

// Signed distance from p to the box's outside (closed form).
double box_distance(const Eigen::Vector3d& p) {
  const Eigen::Vector3d centre(0.0, 0.0, 0.5 * kH), half(kA, kB, 0.5 * kH);
  const Eigen::Vector3d q = (p - centre).cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

// An upper bound on how far a point of the balls lies outside the box: the distance is
// 1-Lipschitz, so no point of a ball is farther out than its centre's signed distance plus
// its radius.
double outward_upper(const std::vector<Sphere>& balls) {
  double out = 0.0;
  for (const Sphere& b : balls) out = std::max(out, box_distance(b.center) + b.radius);
  return out;
}

// A lower bound on the same: the farthest of 2000 points on each ball's sphere (Fibonacci
// directions).
double outward_lower(const std::vector<Sphere>& balls) {
  constexpr int kDirections = 2000;
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  double out = 0.0;
  for (const Sphere& b : balls)
    for (int k = 0; k < kDirections; ++k) {
      const double z = 1.0 - 2.0 * (k + 0.5) / kDirections, r = std::sqrt(1.0 - z * z);
      const Eigen::Vector3d u(r * std::cos(golden * k), r * std::sin(golden * k), z);
      out = std::max(out, box_distance(b.center + b.radius * u));
    }
  return out;
}

bool records_filled_cover(const LinkSpheres& sets) {
  return sets.outer.metadata_json.find("\"cover_solid\":\"filled\"") != std::string::npos;
}

}  // namespace

TEST_CASE("filled covers: a thin open shell's cover on its filled solid", "[filled][robot]") {
  TempDir dir;
  const TriangleMesh mesh = open_box();
  dir.write("open_box.stl", test::to_stl_binary(mesh));
  // A second link, a solid block, is no thin shell: its cover is the same either way.
  const std::string urdf = dir.write("box.urdf", R"(<?xml version="1.0"?>
<robot name="box">
  <link name="shell">
    <collision><geometry><mesh filename="open_box.stl"/></geometry></collision>
  </link>
  <link name="block">
    <collision><geometry><box size="0.1 0.2 0.05"/></geometry></collision>
  </link>
  <joint name="j" type="fixed">
    <parent link="shell"/><child link="block"/><origin xyz="1 0 0"/>
  </joint>
</robot>
)");
  const UrdfRobot robot = read_urdf(urdf);
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  RobotBakeOptions options;
  options.budget.per_link = 32;
  options.request.record_seconds = false;
  options.request.measure = false;
  options.fill_cover_resolution = kFillResolution;  // cheaper than the robot command's
  const RobotBakeResult thin = bake_robot(robot, solids, options);
  options.fill_thin_shell_covers = true;
  const RobotBakeResult filled = bake_robot(robot, solids, options);
  REQUIRE(filled.model.links.size() == 2);
  REQUIRE(filled.model.links[0].name == "shell");
  const LinkSpheres& f = filled.model.links[0].spheres;
  const LinkSpheres& t = thin.model.links[0].spheres;
  CHECK(records_filled_cover(f));
  CHECK_FALSE(records_filled_cover(t));
  CHECK_FALSE(records_filled_cover(filled.model.links[1].spheres));
  CHECK(filled.links[0].outer_filled);
  CHECK_FALSE(filled.links[1].outer_filled);
  CHECK_FALSE(thin.links[0].outer_filled);
  // The robot file records it in the link's entry of the robot's metadata, and reads back.
  const RobotModel loaded = parse_robot(robot_to_json(filled.model), "box.robot.json");
  CHECK(nlohmann::json::parse(loaded.metadata_json)["links"]["shell"]["cover_solid"] == "filled");
  CHECK_FALSE(
      nlohmann::json::parse(thin.model.metadata_json)["links"]["shell"].contains("cover_solid"));
  const std::vector<Sphere>& block_f = filled.model.links[1].spheres.outer.spheres;
  const std::vector<Sphere>& block_t = thin.model.links[1].spheres.outer.spheres;
  REQUIRE(block_f.size() == block_t.size());
  for (std::size_t i = 0; i < block_f.size(); ++i) {
    CHECK(block_f[i].center == block_t[i].center);
    CHECK(block_f[i].radius == block_t[i].radius);
  }
  CHECK(f.outer.size() <= 32);

  // Certified on the real surface: the bake's verdict, the certificate again, and seeded
  // points of the real surface inside the union.
  CHECK(filled.links[0].outer_certified);
  CHECK(certify_cover(mesh, f.outer.spheres).certified);
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<std::size_t> pick(0, mesh.triangles.size() - 1);
  for (int i = 0; i < 3000; ++i) {
    const std::size_t k = pick(rng);
    const Eigen::Vector3d p = test::random_point_on_triangle(mesh.corner(k, 0), mesh.corner(k, 1),
                                                             mesh.corner(k, 2), rng);
    const bool covered =
        std::any_of(f.outer.spheres.begin(), f.outer.spheres.end(),
                    [&](const Sphere& b) { return (p - b.center).norm() <= b.radius; });
    INFO("surface point " << p.transpose());
    REQUIRE(covered);
  }

  // The balls sit in the cavity, and stick out of the box's outside less than the thin
  // material's cover: an upper bound of the one below a lower bound of the other.
  const MeshQuery real(mesh);
  std::size_t in_cavity = 0;
  for (const Sphere& b : f.outer.spheres)
    in_cavity += box_distance(b.center) < 0.0 && !real.inside(b.center);
  CHECK(in_cavity > 0);
  const double filled_out = outward_upper(f.outer.spheres),
               thin_out = outward_lower(t.outer.spheres);
  INFO(f.outer.size() << " and " << t.outer.size()
                      << " balls; outside the box: filled cover at most " << filled_out
                      << ", thin cover at least " << thin_out);
  CHECK(filled_out < thin_out);
  // The filled solid's own excess over convex parts is below 0.075 L (filled_solid.h), and the
  // cover adds its seams: together well under the thin cover's (here at most 0.050 against at
  // least 0.078 with all 32 of the thin cover's balls; before the bake's fill the thin cover
  // kept 4 balls and stuck out at least 0.101, and this bound was half of that).
  CHECK(filled_out < 0.7 * thin_out);
}
