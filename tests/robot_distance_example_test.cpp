// examples/robot_distance.cpp, the README tour's FCL pose example, run on a robot file written
// here: its distances against the closed form (sphere centre to box, minus the radius),
// with the link poses worked out by hand.
#include <cmath>
#include <cstdlib>
#include <string>

#include <catch2/catch.hpp>

#include "medspheres/robot_file.h"
#include "support/robot_fixtures.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

using medspheres::JointType;
using medspheres::RobotModel;
using medspheres::Sphere;
using medspheres::test::make_joint;
using medspheres::test::make_link;
using medspheres::test::run_command;
using medspheres::test::shell_quote;
using medspheres::test::TempDir;

namespace {

// base (one inner sphere r 0.1 at the origin) -j1: revolute about z at (0, 0, 0.5)-> arm
// (covering sphere r 0.05 at (0.3, 0, 0), inner r 0.04 there) -j2: prismatic along x at
// (0.6, 0, 0)-> slider (inner sphere r 0.02 at its origin) -fixed-> tip (no spheres).
RobotModel two_link_arm() {
  RobotModel m;
  m.name = "example_arm";
  m.root_link = "base";
  for (const char* n : {"base", "arm", "slider", "tip"}) m.links.push_back(make_link(n));
  m.links[0].spheres.inner.spheres = {Sphere{{0, 0, 0}, 0.1}};
  m.links[1].spheres.outer.spheres = {Sphere{{0.3, 0, 0}, 0.05}};
  m.links[1].spheres.inner.spheres = {Sphere{{0.3, 0, 0}, 0.04}};
  m.links[2].spheres.inner.spheres = {Sphere{{0, 0, 0}, 0.02}};
  m.links[3].note = "no collision geometry";
  m.joints.push_back(make_joint("j1", JointType::kRevolute, "base", "arm", {0, 0, 0.5}));
  m.joints.push_back(
      make_joint("j2", JointType::kPrismatic, "arm", "slider", {0.6, 0, 0}, {1, 0, 0}));
  m.joints.push_back(make_joint("j3", JointType::kFixed, "slider", "tip", {0, 0, 0.1}));
  return m;
}

// Distance from a ball to an axis-aligned cube (centre c, side a), ball outside the cube.
double ball_to_cube(const Eigen::Vector3d& p, double r, const Eigen::Vector3d& c, double a) {
  const Eigen::Vector3d d = ((p - c).cwiseAbs().array() - a / 2).max(0.0).matrix();
  return d.norm() - r;
}

// The robot's distance at (q1, q2), link poses by hand: the arm turned by q1 about z at
// height 0.5; the slider q2 further out along the arm.
double oracle(double q1, double q2, const Eigen::Vector3d& c, double a) {
  const Eigen::Vector3d along(std::cos(q1), std::sin(q1), 0);
  const Eigen::Vector3d shoulder(0, 0, 0.5);
  return std::min({ball_to_cube({0, 0, 0}, 0.1, c, a),
                   ball_to_cube(shoulder + 0.3 * along, 0.05, c, a),  // the covering set
                   ball_to_cube(shoulder + (0.6 + q2) * along, 0.02, c, a)});
}

double run_example(const std::string& robot, const Eigen::Vector3d& c, double a, double q1,
                   double q2) {
  char args[256];
  std::snprintf(args, sizeof args, " %.17g %.17g %.17g %.17g %.17g %.17g", c.x(), c.y(), c.z(), a,
                q1, q2);
  const auto r =
      run_command(shell_quote(MEDSPHERES_ROBOT_DISTANCE) + " " + shell_quote(robot) + args);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  REQUIRE(r.out.rfind("distance ", 0) == 0);
  CHECK(r.out.find("joint j1\njoint j2\n") != std::string::npos);
  return std::strtod(r.out.c_str() + 9, nullptr);
}

}  // namespace

TEST_CASE("robot_distance: FCL distance of the posed robot to a box, against the closed form",
          "[example]") {
  TempDir dir;
  const std::string robot = dir.file("arm.robot.json");
  medspheres::save_robot(two_link_arm(), robot);
  struct Case {
    Eigen::Vector3d c;
    double a, q1, q2;
  };
  const Case cases[] = {{{0, 0.9, 0.5}, 0.2, M_PI / 2, 0.0},    // the arm turned towards it
                        {{0, 0.6, 0.5}, 0.2, 0.0, 0.0},         // the arm turned away
                        {{0.5, 0.5, 0.6}, 0.1, 0.7, 0.05},      // the slider nearest
                        {{-0.4, -0.3, -0.2}, 0.3, -2.0, 0.1}};  // the base nearest
  for (const Case& k : cases) {
    const double want = oracle(k.q1, k.q2, k.c, k.a);
    INFO("q = (" << k.q1 << ", " << k.q2 << "), expected " << want);
    REQUIRE(want > 0.01);
    CHECK(std::abs(run_example(robot, k.c, k.a, k.q1, k.q2) - want) < 1e-9);
  }
}

TEST_CASE("robot_distance: bad input exits 2 naming it", "[example]") {
  TempDir dir;
  const std::string robot = dir.file("arm.robot.json");
  medspheres::save_robot(two_link_arm(), robot);
  const std::string exe = shell_quote(MEDSPHERES_ROBOT_DISTANCE) + " ";
  auto r = run_command(exe + shell_quote(dir.file("missing.robot.json")) + " 0 0 0 1");
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("missing.robot.json") != std::string::npos);
  r = run_command(exe + shell_quote(robot) + " 0 0 0 -1");
  CHECK(r.exit_code == 2);
  r = run_command(exe + shell_quote(robot) + " 0 0 0 1 0.1 0.2 0.3");  // three positions
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("3 joint positions for 2") != std::string::npos);
}
