#include <filesystem>

#include <yaml-cpp/yaml.h>
#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/formats/curobo_yaml.h"
#include "medspheres/formats/foam_json.h"
#include "medspheres/formats/sph_file.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/formats/spherized_urdf.h"
#include "medspheres/formats/srdf_spheres.h"
#include "medspheres/formats/xrdf.h"
#include "medspheres/io.h"
#include "medspheres/robot_file.h"
#include "support/robot_fixtures.h"
#include "support/robot_spheres_fixtures.h"

using Catch::Matchers::Contains;
using medspheres::InputError;
using medspheres::Sphere;
using namespace medspheres::formats;
using medspheres::test::identical;
using medspheres::test::kAwkwardLink;
using medspheres::test::random_robot_spheres;

namespace {

std::string problem(void (*read)(const std::string&), const std::string& text) {
  try {
    read(text);
  } catch (const InputError& e) {
    CHECK(e.source() == "f");
    return e.problem();
  }
  return "";
}

}  // namespace

// Every writer prints numbers in their shortest exact form: read back, the spheres are
// bit-identical, which is the strongest "same to the printed precision".
TEST_CASE("every per-link writer read back by its reader gives the same spheres", "[formats]") {
  for (unsigned seed : {1u, 2u, 3u}) {
    const RobotSpheres s = random_robot_spheres(seed);
    CHECK(identical(parse_curobo_yaml(curobo_yaml_text(s, {"base", {}}), "f"), s));
    XrdfOptions xo;
    xo.joint_names = {"j1"};
    CHECK(identical(parse_xrdf(xrdf_text(s, xo), "f"), s));
    CHECK(identical(parse_srdf_spheres(srdf_spheres_text(s, "r<&>"), "f"), s));
    CHECK(identical(parse_foam_robot_json(foam_robot_json(s), "f"), s));
    // The URDF's link "no_spheres" keeps its own sphere collision, and reads back too.
    RobotSpheres urdf =
        parse_urdf_spheres(spherize_urdf(medspheres::test::awkward_urdf(), s, "f"), "f");
    REQUIRE(urdf.size() == 4);
    CHECK(urdf.back().link == "no_spheres");
    urdf.pop_back();
    CHECK(identical(urdf, s));
  }
}

TEST_CASE("every one-set writer read back by its reader gives the same spheres", "[formats]") {
  const std::vector<Sphere> s = random_robot_spheres(5)[1].spheres;
  const RobotSpheres one{{"x", s}};
  const auto foam = parse_foam_mesh_json(foam_mesh_json(s), "f");
  REQUIRE(foam.size() == 1);
  CHECK(!foam[0].mean.has_value());
  CHECK(identical({{"x", foam[0].spheres}}, one));
  const auto sph = parse_sph_levels(sph_text(s), "f");
  REQUIRE(sph.size() == 2);
  CHECK(identical({{"x", sph[1]}}, one));
  // The root encloses every sphere.
  REQUIRE(sph[0].size() == 1);
  for (const Sphere& t : s)
    CHECK((t.center - sph[0][0].center).norm() + t.radius <= sph[0][0].radius);
}

TEST_CASE("XRDF and cuRobo files have the layouts their tools read", "[formats]") {
  const RobotSpheres s = random_robot_spheres(9);
  const YAML::Node curobo = YAML::Load(curobo_yaml_text(s, {"base", {}}));
  CHECK(curobo["format_version"].as<double>() == 2.0);
  const YAML::Node k = curobo["robot_cfg"]["kinematics"];
  CHECK(k["base_link"].as<std::string>() == "base");
  CHECK(k["collision_link_names"][1].as<std::string>() == kAwkwardLink);
  CHECK(k["collision_spheres"]["tool"][0]["radius"].as<double>() == s[2].spheres[0].radius);
  XrdfOptions o;
  o.joint_names = {"j1", "j2"};
  const YAML::Node x = YAML::Load(xrdf_text(s, o));
  CHECK(x["format"].as<std::string>() == "xrdf");
  CHECK(x["format_version"].as<double>() == 1.0);
  CHECK(x["collision"]["geometry"].as<std::string>() == o.geometry_name);
  CHECK(x["self_collision"]["geometry"].as<std::string>() == o.geometry_name);
  CHECK(x["cspace"]["jerk_limits"].size() == 2);
  CHECK(x["geometry"][o.geometry_name]["spheres"]["base"].size() == 4);
  // cuRobo's XRDF loader: format_version a number (it compares it with 1.0), and
  // self_collision: ignore and default_joint_positions required.
  CHECK(x["format_version"].Tag() == "?");  // a plain scalar, not a quoted string
  CHECK(x["self_collision"]["ignore"].IsMap());
  CHECK(x["self_collision"]["ignore"].size() == 0);
  CHECK(x["default_joint_positions"]["j2"].as<double>() == 0.0);
  CHECK(!x["tool_frames"]);
  o.default_positions = {0.5, -1.25};
  o.tool_frames = {"tool"};
  o.self_collision_ignore = {{"base", {"tool", kAwkwardLink}}};
  const YAML::Node y = YAML::Load(xrdf_text(s, o));
  CHECK(y["default_joint_positions"]["j2"].as<double>() == -1.25);
  CHECK(y["tool_frames"].as<std::vector<std::string>>() == std::vector<std::string>{"tool"});
  CHECK(y["self_collision"]["ignore"]["base"].as<std::vector<std::string>>() ==
        std::vector<std::string>{"tool", kAwkwardLink});
  CHECK(identical(parse_xrdf(xrdf_text(s, o), "f"), s));
  CuroboOptions co{"base", o.self_collision_ignore};
  const YAML::Node c = YAML::Load(curobo_yaml_text(s, co));
  CHECK(c["robot_cfg"]["kinematics"]["self_collision_ignore"]["base"][1].as<std::string>() ==
        kAwkwardLink);
  CHECK(!curobo["robot_cfg"]["kinematics"]["self_collision_ignore"]);
}

TEST_CASE("SRDF: a lone zero-radius sphere means no spheres, as in srdfdom", "[formats]") {
  const RobotSpheres s{{"a", {}}, {"b", {{{1, 2, 3}, 0.5}}}};
  const std::string text = srdf_spheres_text(s, "r");
  CHECK_THAT(text, Contains("radius=\"0\""));
  CHECK(identical(parse_srdf_spheres(text, "f"), s));
  // Numbers as people write them: a leading plus sign, exponents, extra spaces.
  const RobotSpheres hand = parse_srdf_spheres(
      "<robot><link_sphere_approximation link=\"c\"><sphere center=\" +1  -2e0 3\" "
      "radius=\"+5E-1\"/></link_sphere_approximation></robot>",
      "f");
  CHECK(identical(hand, {{"c", {{{1, -2, 3}, 0.5}}}}));
  CHECK_THROWS_WITH(parse_srdf_spheres("<robot><link_sphere_approximation link=\"c\"><sphere "
                                       "center=\"+-1 0 0\" radius=\"1\"/>"
                                       "</link_sphere_approximation></robot>",
                                       "f"),
                    Contains("link \"c\" sphere 0"));
}

TEST_CASE("sph: every level of a spheretree file, unused nodes dropped", "[formats]") {
  // A tree of 3 levels and degree 2 with one unused node on the last level, and the
  // optional auxiliary columns on one line.
  const std::string text =
      "3 2\n0 0 0 2 1\n\n-1 0 0 1 1\n1 0 0 1 1 1 0 0 1.1 0.5\n"
      "-1.5 0 0 0.5 1\n-0.5 0 0 0.5 1\n0.5 0 0 0.5 1\n0 0 0 -1 1\n";
  const auto levels = parse_sph_levels(text, "f");
  REQUIRE(levels.size() == 3);
  CHECK(levels[0].size() == 1);
  CHECK(levels[1].size() == 2);
  CHECK(levels[2].size() == 3);
  CHECK(levels[2][2].center.x() == 0.5);
}

TEST_CASE("malformed sphere files name the file, the link and the problem", "[formats]") {
  auto curobo = [](const std::string& t) { parse_curobo_yaml(t, "f"); };
  auto xrdf = [](const std::string& t) { parse_xrdf(t, "f"); };
  auto urdf = [](const std::string& t) { parse_urdf_spheres(t, "f"); };
  auto srdf = [](const std::string& t) { parse_srdf_spheres(t, "f"); };
  auto foam = [](const std::string& t) { parse_foam_mesh_json(t, "f"); };
  auto foam_db = [](const std::string& t) { parse_foam_robot_json(t, "f"); };
  auto sph = [](const std::string& t) { parse_sph_levels(t, "f"); };
  CHECK_THAT(problem(curobo, "a: [1"), Contains("not valid YAML"));
  CHECK_THAT(problem(curobo, "robot_cfg: {kinematics: {collision_spheres: spheres/x.yml}}"),
             Contains("separate file"));
  CHECK_THAT(problem(curobo, "collision_spheres: {l1: [{center: [0, 0, 0], radius: -1}]}"),
             Contains("link \"l1\"") && Contains("radius -1"));
  CHECK_THAT(problem(curobo, "collision_spheres: {l1: [{center: [0, x, 0], radius: 1}]}"),
             Contains("link \"l1\" sphere 0 center"));
  CHECK_THAT(problem(curobo, "kinematics: {base_link: a}"), Contains("no \"collision_spheres\""));
  CHECK_THAT(problem(xrdf, "format: urdf"), Contains("format: xrdf"));
  CHECK_THAT(problem(xrdf, "format: xrdf\ngeometry: {g: {spheres: {}}}\ncollision: {geometry: h}"),
             Contains("\"h\""));
  CHECK_THAT(problem(urdf,
                     "<robot><link name=\"a\"><collision><geometry><sphere radius=\"x\"/>"
                     "</geometry></collision></link></robot>"),
             Contains("link \"a\"") && Contains("radius"));
  CHECK_THAT(problem(urdf, "<robot><link>"), Contains("XML"));
  CHECK_THAT(problem(urdf, "<sdf/>"), Contains("<robot>"));
  CHECK_THAT(problem(srdf,
                     "<robot><link_sphere_approximation link=\"b\"><sphere radius=\"1\"/>"
                     "</link_sphere_approximation></robot>"),
             Contains("link \"b\"") && Contains("center"));
  CHECK_THAT(problem(foam, "{\"spheres\": []}"), Contains("list of levels"));
  CHECK_THAT(problem(foam, "[{\"spheres\": [{\"origin\": [0, 0], \"radius\": 1}]}]"),
             Contains("level 0 sphere 0"));
  CHECK_THAT(problem(foam_db, "{\"l::m.stl\": {\"x\": {}}}"), Contains("\"l::m.stl\""));
  CHECK_THAT(problem(sph, "2\n"), Contains("levels degree"));
  CHECK_THAT(problem(sph, "2 4\n0 0 0 1 1\n0 0 0 1\n"), Contains("level 1 needs 4"));
  CHECK_THAT(problem(sph, "1 1\n0 0 nan 1\n"), Contains("level 0"));
}

TEST_CASE("writers reject invalid spheres and duplicate links", "[formats]") {
  CHECK_THROWS_AS(curobo_yaml_text({{"a", {{{0, 0, 0}, 0.0}}}}), InputError);
  CHECK_THROWS_AS(srdf_spheres_text({{"a", {}}, {"a", {}}}, "r"), InputError);
  CHECK_THROWS_AS(sph_text({}), InputError);
  // Centres 1e200 apart: a squared norm would overflow, the root sphere must still be finite.
  const std::vector<Sphere> far = {{{0, 1e200, 0}, 1.0}, {{0, -1e200, 0}, 1.0}};
  CHECK(parse_sph_levels(sph_text(far), "far.sph").size() == 2);
  CHECK(parse_sph_levels(sph_text({{{1.7e308, 0, 0}, 1.0}, {{1.7e308, 0, 0}, 2.0}}), "f").size() ==
        2);
  CHECK_THROWS_WITH(
      sph_text({{{0, 1.797693134862e308, 0}, 1.0}, {{0, -1.797693134862e308, 0}, 1.0}}),
      Contains("no root sphere bounds them"));
  CHECK_THROWS_WITH(spherize_urdf(medspheres::test::awkward_urdf(), {{"ghost", {}}}, "u.urdf"),
                    Contains("\"ghost\""));
}

#ifdef MEDSPHERES_SHARED_MESHES
TEST_CASE("cuRobo's own Unitree G1 configuration reads", "[formats][shared]") {
  const std::string path =
      std::string(MEDSPHERES_SHARED_MESHES) + "/../robots/unitree_g1/curobo_unitree_g1.yml";
  if (!std::filesystem::exists(path)) return;
  const RobotSpheres s = load_curobo_yaml(path);
  // Oracle: the file has one "radius:" key per sphere.
  const std::string text = medspheres::read_text_file(path);
  std::size_t radii = 0;
  for (std::size_t at = text.find("radius:"); at != std::string::npos;
       at = text.find("radius:", at + 1))
    ++radii;
  std::size_t total = 0;
  for (const auto& l : s) total += l.spheres.size();
  CHECK(total == radii);
  REQUIRE(find_link_spheres(s, "head_link"));
  CHECK(find_link_spheres(s, "head_link")->spheres[0].radius == 0.02945771813392639);
  // And it survives our writer and reader unchanged.
  CHECK(identical(parse_curobo_yaml(curobo_yaml_text(s), "again"), s));
}
#endif

TEST_CASE("a robot model's document writes every per-link format from its covering sets",
          "[formats]") {
  medspheres::RobotModel m = medspheres::test::three_link_arm();
  CHECK_THROWS_WITH(robot_document(m, SphereChoice::kOuter, "", "arm"),
                    Contains("arm") && Contains("no link has outer"));
  m.links[2].spheres.outer.spheres = {{{0.1, 0.2, 0.3}, 0.05}};
  m.links[2].spheres.inner.spheres = {{{0.1, 0.2, 0.3}, 0.01}};
  const SphereDocument doc = robot_document(m, SphereChoice::kOuter, "", "arm");
  const RobotSpheres expected{{"l2", {{{0.1, 0.2, 0.3}, 0.05}}}};
  {
    // Adjacent links for the planners skip the links without spheres between them (l1
    // between base and l2, l3 between l2 and tool); the leaf "tool" is the tool frame;
    // j2's default position is moved into its limits.
    medspheres::RobotModel n = m;
    n.links[0].spheres.outer.spheres = {{{0, 0, 0}, 0.1}};
    n.links[4].spheres.outer.spheres = {{{0, 0, 0}, 0.02}};
    n.joints[1].limits->lower = 0.125;
    const SphereDocument d = robot_document(n, SphereChoice::kOuter, "", "arm");
    const YAML::Node x = YAML::Load(sphere_document_text(d, SphereFormat::kXrdf));
    const YAML::Node ignore = x["self_collision"]["ignore"];
    REQUIRE(ignore.size() == 2);
    CHECK(ignore["base"].as<std::vector<std::string>>() == std::vector<std::string>{"l2"});
    CHECK(ignore["l2"].as<std::vector<std::string>>() == std::vector<std::string>{"tool"});
    CHECK(x["tool_frames"].as<std::vector<std::string>>() == std::vector<std::string>{"tool"});
    CHECK(x["default_joint_positions"]["j1"].as<double>() == 0.0);
    CHECK(x["default_joint_positions"]["j2"].as<double>() == 0.125);
    const YAML::Node c = YAML::Load(sphere_document_text(d, SphereFormat::kCurobo));
    CHECK(c["robot_cfg"]["kinematics"]["self_collision_ignore"]["l2"][0].as<std::string>() ==
          "tool");
  }
  // One link with spheres still makes foam's per-link database, not a one-mesh list.
  CHECK(identical(parse_foam_robot_json(sphere_document_text(doc, SphereFormat::kFoam), "f"),
                  expected));
  const YAML::Node curobo = YAML::Load(sphere_document_text(doc, SphereFormat::kCurobo));
  CHECK(curobo["robot_cfg"]["kinematics"]["base_link"].as<std::string>() == "base");
  const YAML::Node xrdf = YAML::Load(sphere_document_text(doc, SphereFormat::kXrdf));
  CHECK(xrdf["cspace"]["joint_names"].as<std::vector<std::string>>() ==
        std::vector<std::string>{"j1", "j2"});
  CHECK(medspheres::parse_robot(sphere_document_text(doc, SphereFormat::kRobot), "r")
            .links[2]
            .spheres.inner.size() == 1);
}

TEST_CASE("the cuRobo reader takes the current, the older and the sphere-file layouts",
          "[formats]") {
  // The same two links in cuRobo's three layouts: spheres under robot_cfg: kinematics:
  // (older configurations, and what medspheres writes), under a top-level kinematics:
  // (current configurations, block style as cuRobo's own files), and a separate sphere
  // file whose top level is collision_spheres:.
  const RobotSpheres want{{"a", {{{0.5, -1, 2}, 0.25}}},
                          {"b", {{{1e-3, 0, 0}, 0.125}, {{0, 0, 3}, 1.5}}}};
  const std::string older = R"(robot_cfg:
  kinematics:
    base_link: a
    collision_spheres:
      a: [{center: [0.5, -1, 2], radius: 0.25}]
      b:
        - {center: [1e-3, 0, 0], radius: 0.125}
        - {center: [0, 0, 3], radius: 1.5}
)";
  const std::string current = R"(kinematics:
  collision_link_names:
  - a
  - b
  collision_spheres:
    a:
    - center:
      - 0.5
      - -1
      - 2
      radius: 0.25
    b:
    - center: [0.001, 0, 0]
      radius: 0.125
    - center: [0, 0, 3.0]
      radius: 1.5
)";
  const std::string sphere_file = R"(collision_spheres:
  a: [{center: [0.5, -1, 2], radius: 0.25}]
  b: [{center: [0.001, 0, 0], radius: 0.125}, {center: [0, 0, 3], radius: 1.5}]
)";
  for (const std::string& text : {older, current, sphere_file, curobo_yaml_text(want)}) {
    INFO(text);
    CHECK(identical(parse_curobo_yaml(text, "f"), want));
  }
}
