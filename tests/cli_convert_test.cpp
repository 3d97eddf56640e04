// medspheres convert, run as a user runs it: every format to every other, and bad input.
#include <filesystem>
#include <random>
#include <string>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/io.h"
#include "medspheres/robot_file.h"
#include "support/robot_fixtures.h"
#include "support/robot_spheres_fixtures.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

using Catch::Matchers::Contains;
using medspheres::test::CommandResult;
using medspheres::test::identical;
using medspheres::test::run_cli;
using medspheres::test::shell_quote;
using medspheres::test::TempDir;
namespace formats = medspheres::formats;

namespace {

// The three-link arm with random inner and outer sets on every link but the tool.
medspheres::RobotModel arm_with_spheres() {
  medspheres::RobotModel m = medspheres::test::three_link_arm();
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-0.3, 0.3), r(0.001, 0.1);
  for (std::size_t i = 0; i + 1 < m.links.size(); ++i) {
    for (auto* set : {&m.links[i].spheres.inner, &m.links[i].spheres.outer})
      for (std::size_t k = 0; k < 3 + i; ++k)
        set->spheres.push_back({{u(rng), u(rng), u(rng)}, r(rng)});
  }
  m.links.back().note = "no collision geometry";
  return m;
}

const char* kArmUrdf = R"(<robot name="arm">
  <link name="base"><collision><geometry><box size="1 1 1"/></geometry></collision></link>
  <link name="l1"/><link name="l2"/><link name="l3"/><link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="2"/></joint>
  <joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.5" effort="100" velocity="0.1"/></joint>
  <joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/><axis xyz="0 1 0"/>
    <mimic joint="j1" multiplier="2" offset="0.1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="l3"/><child link="tool"/></joint>
</robot>
)";

std::string convert(const std::string& args) {
  const CommandResult r = run_cli("convert " + args);
  INFO(r.err);
  CHECK(r.exit_code == 0);
  return r.out;
}

}  // namespace

TEST_CASE("convert carries a robot's spheres through every per-link format unchanged",
          "[cli][convert]") {
  TempDir dir;
  const medspheres::RobotModel model = arm_with_spheres();
  const std::string robot = dir.file("arm.robot.json");
  medspheres::save_robot(model, robot);
  const std::string urdf = dir.write("arm.urdf.in", kArmUrdf);
  const formats::RobotSpheres outer = formats::robot_spheres(model);
  const formats::RobotSpheres inner = formats::robot_spheres(model, formats::SphereChoice::kInner);
  REQUIRE(outer.size() == 4);

  // robot -> cuRobo -> XRDF -> SRDF -> foam -> URDF -> cuRobo again: one chain, each step
  // reading the previous step's output.
  std::string previous = robot;
  for (const char* name : {"a.yml", "a.xrdf", "a.srdf", "a.foam.json", "a.urdf", "b.yaml"}) {
    const std::string out = dir.file(name);
    CHECK_THAT(
        convert(shell_quote(previous) + " " + shell_quote(out) + " --urdf " + shell_quote(urdf)),
        Contains("4 links"));
    CHECK(identical(formats::read_sphere_document(out).links, outer));
    previous = out;
  }
  // The inner set on request; the robot file itself through convert is the same model.
  convert(shell_quote(robot) + " " + shell_quote(dir.file("in.xrdf")) + " --set inner");
  CHECK(identical(formats::read_sphere_document(dir.file("in.xrdf")).links, inner));
  convert(shell_quote(robot) + " " + shell_quote(dir.file("copy.robot.json")));
  CHECK(medspheres::read_text_file(dir.file("copy.robot.json")) ==
        medspheres::robot_to_json(model));
}

TEST_CASE("convert between one-set and per-link files with --link", "[cli][convert]") {
  TempDir dir;
  const medspheres::RobotModel model = arm_with_spheres();
  const std::string robot = dir.file("arm.robot.json");
  medspheres::save_robot(model, robot);
  const formats::RobotSpheres l2{{"l2", model.links[2].spheres.outer.spheres}};
  for (const char* name : {"l2.sph", "l2.spheres.json", "l2.foam.json"}) {
    convert(shell_quote(robot) + " " + shell_quote(dir.file(name)) + " --link l2");
    const formats::SphereDocument d = formats::read_sphere_document(dir.file(name));
    REQUIRE(d.set);
    CHECK(identical({{"l2", d.set->spheres}}, l2));
    // And back into a per-link format as the link it names.
    const std::string yml = dir.file(std::string(name) + ".yml");
    convert(shell_quote(dir.file(name)) + " " + shell_quote(yml) + " --link l2");
    CHECK(identical(formats::read_sphere_document(yml).links, l2));
  }
  // The .sph root level on request.
  convert(shell_quote(dir.file("l2.sph")) + " " + shell_quote(dir.file("root.json")) +
          " --level 0");
  CHECK(formats::read_sphere_document(dir.file("root.json")).set->size() == 1);
  // The library refuses a level below -1 (the last) by name; --level's range refuses it first.
  formats::ReadOptions below;
  below.level = -3;
  try {
    formats::read_sphere_document(dir.file("l2.sph"), std::nullopt, below);
    FAIL("level -3 was read");
  } catch (const medspheres::InputError& e) {
    CHECK(e.field() == "level");
  }
}

TEST_CASE("convert rejects bad input with exit 2, a message and no output", "[cli][convert]") {
  TempDir dir;
  const std::string robot = dir.file("arm.robot.json");
  medspheres::save_robot(arm_with_spheres(), robot);
  const std::string kept = dir.write("kept.yml", "untouched");
  auto fails = [&](const std::string& args, const std::string& message, const std::string& out) {
    const CommandResult r = run_cli("convert " + args);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(message));
    if (out == kept)
      CHECK(medspheres::read_text_file(kept) == "untouched");
    else
      CHECK(!std::filesystem::exists(out));
  };
  const std::string out = dir.file("out.sph");
  fails(shell_quote(robot) + " " + shell_quote(out), "--link", out);
  fails(shell_quote(robot) + " " + shell_quote(out) + " --link ghost", "\"ghost\"", out);
  // A per-link output takes every link: a link named there would go unused.
  for (const std::string per_link : {"r.yml", "r.xrdf", "r.srdf"})
    fails(shell_quote(robot) + " " + shell_quote(dir.file(per_link)) + " --link l2",
          "--link: the input has spheres per link", dir.file(per_link));
  fails(shell_quote(robot) + " " + shell_quote(dir.file("x.txt")), "x.txt", dir.file("x.txt"));
  fails(shell_quote(robot) + " " + shell_quote(dir.file("a.urdf")), "--urdf", dir.file("a.urdf"));
  fails(shell_quote(robot) + " " + shell_quote(out) + " --to nope", "unknown format", out);
  const std::string bad =
      dir.write("bad.yml", "collision_spheres: {l1: [{center: [0, 0], radius: 1}]}");
  fails(shell_quote(bad) + " " + shell_quote(kept), "bad.yml", kept);
  fails(shell_quote(bad) + " " + shell_quote(dir.file("r.robot.json")), "bad.yml",
        dir.file("r.robot.json"));
  const std::string yml = dir.file("ok.yml");
  convert(shell_quote(robot) + " " + shell_quote(yml));
  fails(shell_quote(yml) + " " + shell_quote(dir.file("r.robot.json")), "kinematic tree",
        dir.file("r.robot.json"));
  fails(shell_quote(dir.file("missing.yml")) + " " + shell_quote(kept), "missing.yml", kept);
  // A set without spheres has no .sph: the message names the file, not only the format.
  const std::string empty = dir.write("empty.json", R"({"spheres": []})");
  fails(shell_quote(empty) + " " + shell_quote(out), out + ": no spheres to write", out);
}

TEST_CASE("convert writes no XRDF for a robot without an actuated joint", "[cli][convert]") {
  TempDir dir;
  medspheres::RobotModel gripper = medspheres::test::three_link_arm();
  for (medspheres::Joint& j : gripper.joints) {
    j.type = medspheres::JointType::kFixed;
    j.mimic.reset();
    j.limits.reset();
  }
  for (medspheres::Link& l : gripper.links)
    l.spheres.outer.spheres.push_back({{0.0, 0.0, 0.1}, 0.05});
  const std::string robot = dir.file("gripper.robot.json");
  medspheres::save_robot(gripper, robot);
  const CommandResult r =
      run_cli("convert " + shell_quote(robot) + " " + shell_quote(dir.file("g.xrdf")));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("--to") && Contains("no actuated joint"));
  CHECK(!std::filesystem::exists(dir.file("g.xrdf")));
  // The cuRobo YAML carries the same spheres.
  convert(shell_quote(robot) + " " + shell_quote(dir.file("g.yml")));
  const auto read = formats::read_link_sphere_map(dir.file("g.yml"), "in");
  CHECK(read.size() == gripper.links.size());
}
