// Contact-aware covers (contact_regions.h) on a generated robot: a box "a" and, two revolute
// joints away (so the pair is checked, not adjacent), a bar "b" that swings in front of a's
// +x face. Oracles: the closed-form distance to a's box (every region point of a lies
// within the band of a's surface, and on its +x side, the only side b reaches); the covers
// baked again stay certified, and a's balls that reach the region stick out less there than
// those of the first bake (closed-form protrusion).
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/robot_bake/contact_regions.h"
#include "medspheres/robot_bake/robot_bake.h"
#include "medspheres/robot_bake/robot_planner_setup.h"
#include "support/temp_dir.h"

using namespace medspheres;
using medspheres::test::TempDir;

namespace {

const Eigen::Vector3d kHalfA(0.2, 0.2, 0.2);

std::string box_link(const std::string& name, const std::string& size, const std::string& xyz) {
  return "<link name=\"" + name + "\"><collision><origin xyz=\"" + xyz +
         "\"/><geometry><box size=\"" + size + "\"/></geometry></collision></link>\n";
}

std::string revolute(const std::string& name, const std::string& parent, const std::string& child,
                     const std::string& xyz, const std::string& limits) {
  return "<joint name=\"" + name + "\" type=\"revolute\"><parent link=\"" + parent +
         "\"/><child link=\"" + child + "\"/><origin xyz=\"" + xyz +
         "\"/><axis xyz=\"0 0 1\"/><limit " + limits + " effort=\"1\" velocity=\"1\"/></joint>\n";
}

// a: the box at the origin; m: a small box on the first joint's axis, 0.15 in front of a's
// +x face; b: a bar 0.15 off the second joint's axis, which swings within reach of the face.
std::string robot_urdf() {
  return "<?xml version=\"1.0\"?>\n<robot name=\"contact_pair\">\n" +
         box_link("a", "0.4 0.4 0.4", "0 0 0") + box_link("m", "0.02 0.02 0.02", "0 0 0") +
         box_link("b", "0.06 0.06 0.3", "0 0.15 0") +
         revolute("j1", "a", "m", "0.37 0 0", "lower=\"-0.3\" upper=\"0.3\"") +
         revolute("j2", "m", "b", "0 0 0", "lower=\"-3.14\" upper=\"3.14\"") + "</robot>\n";
}

// Signed distance to a's box surface, positive inside (closed form).
double box_depth(const Eigen::Vector3d& c) {
  const Eigen::Vector3d q = c.cwiseAbs() - kHalfA;
  if ((q.array() <= 0.0).all()) return -q.maxCoeff();
  return -q.cwiseMax(0.0).norm();
}

// The largest protrusion (closed form) of the balls that reach the region \p w.
double region_protrusion(const std::vector<Sphere>& balls, const ProtrusionWeights& w) {
  double top = 0.0;
  for (const Sphere& s : balls)
    for (const Eigen::Vector3d& p : w.points)
      if ((p - s.center).norm() <= s.radius + w.reach) {
        top = std::max(top, s.radius - box_depth(s.center));
        break;
      }
  return top;
}

}  // namespace

TEST_CASE("contact regions: where the partner comes, and covers tighter there", "[contact]") {
  const TempDir dir;
  const UrdfRobot robot = read_urdf(dir.write("contact_pair.urdf", robot_urdf()));
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  RobotBakeOptions bake;
  bake.budget.per_link = 24;
  bake.request.measure = false;
  bake.jobs = 2;
  const RobotBakeResult first = bake_robot(robot, solids, bake);
  PlannerRequest planner;
  planner.self_collision.samples = 400;
  planner.self_collision.threads = 2;
  const PlannerSetup setup =
      make_planner_setup(first.model, solids, formats::SphereChoice::kOuter, planner);
  const auto checked =
      std::find_if(setup.self_collision->pairs.begin(), setup.self_collision->pairs.end(),
                   [](const LinkPairClass& p) { return p.link1 == "a" && p.link2 == "b"; });
  REQUIRE(checked != setup.self_collision->pairs.end());
  REQUIRE_FALSE(checked->ignored);

  ContactOptions contact;
  contact.samples = 300;
  contact.band = 0.02;
  contact.weight = 6.0;
  contact.threads = 2;
  const auto regions = contact_regions(first.model, solids, *setup.self_collision, {}, contact);
  REQUIRE(regions.count("a"));
  const ProtrusionWeights& ra = regions.at("a");
  CHECK(ra.weight == 6.0);
  CHECK(ra.points.size() > 10);
  for (const Eigen::Vector3d& p : ra.points) {
    CHECK(std::abs(box_depth(p)) <= contact.band + 1e-9);
    CHECK(p.x() >= kHalfA.x() - contact.band - 1e-9);
  }
  // Where the partner comes often: a subset of the region.
  ContactOptions often = contact;
  often.min_share = 0.02;
  const auto frequent = contact_regions(first.model, solids, *setup.self_collision, {}, often);
  REQUIRE(frequent.count("a"));
  CHECK(frequent.at("a").points.size() < ra.points.size());
  for (const Eigen::Vector3d& p : frequent.at("a").points)
    CHECK(std::find(ra.points.begin(), ra.points.end(), p) != ra.points.end());
  // The same regions for any thread count.
  contact.threads = 1;
  const auto one = contact_regions(first.model, solids, *setup.self_collision, {}, contact);
  REQUIRE(one.at("a").points.size() == ra.points.size());
  CHECK(std::equal(ra.points.begin(), ra.points.end(), one.at("a").points.begin()));

  const RobotBakeResult again = rebake_contact_aware(
      robot, solids, bake, first, formats::SphereChoice::kOuter, planner, contact);
  for (const LinkBakeStats& s : again.links) {
    INFO(s.link);
    CHECK(s.outer_certified);
    CHECK(s.outer_spheres <= 24);
  }
  const std::vector<Sphere>& before = first.model.links[0].spheres.outer.spheres;
  const std::vector<Sphere>& after = again.model.links[0].spheres.outer.spheres;
  const double p0 = region_protrusion(before, ra), p1 = region_protrusion(after, ra);
  INFO("a's balls in the region stick out " << p0 << " at first, " << p1 << " after");
  CHECK(p1 < 0.75 * p0);
}

TEST_CASE("contact options out of range are refused, naming the option", "[contact]") {
  ContactOptions o;
  o.band = 0.0;
  CHECK_THROWS_WITH(validate(o), Catch::Contains("contact_band"));
  o = {};
  o.weight = 0.5;
  CHECK_THROWS_WITH(validate(o), Catch::Contains("contact_weight"));
  o = {};
  o.min_share = 1.5;
  CHECK_THROWS_WITH(validate(o), Catch::Contains("contact_min_share"));
  o = {};
  o.samples = 0;
  CHECK_THROWS_WITH(validate(o), Catch::Contains("contact_samples"));
}
