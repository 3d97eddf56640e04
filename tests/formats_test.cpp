#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>

#include <yaml-cpp/yaml.h>
#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/formats/curobo_urdf_check.h"
#include "medspheres/formats/curobo_yaml.h"
#include "medspheres/formats/foam_json.h"
#include "medspheres/formats/sph_file.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/formats/spherized_urdf.h"
#include "medspheres/formats/srdf_disabled_collisions.h"
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

CuroboOptions with_base(const std::string& base) {
  CuroboOptions o;
  o.base_link = base;
  return o;
}

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
    CHECK(identical(parse_curobo_yaml(curobo_yaml_text(s, with_base("base")), "f"), s));
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
  const YAML::Node curobo = YAML::Load(curobo_yaml_text(s, with_base("base")));
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
  o.default_positions = {{"j1", 0.5}, {"j2", -1.25}};
  o.tool_frames = {"tool"};
  o.self_collision_ignore = {{"base", {"tool", kAwkwardLink}}};
  const YAML::Node y = YAML::Load(xrdf_text(s, o));
  CHECK(y["default_joint_positions"]["j2"].as<double>() == -1.25);
  CHECK(y["tool_frames"].as<std::vector<std::string>>() == std::vector<std::string>{"tool"});
  CHECK(y["self_collision"]["ignore"]["base"].as<std::vector<std::string>>() ==
        std::vector<std::string>{"tool", kAwkwardLink});
  CHECK(identical(parse_xrdf(xrdf_text(s, o), "f"), s));
  CuroboOptions co = with_base("base");
  co.self_collision_ignore = o.self_collision_ignore;
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

TEST_CASE("a link name with a control character is refused by every per-link format", "[formats]") {
  // XML turns a carriage return in an attribute into a line break: such a name could not
  // be written and read back as itself.
  CHECK_THROWS_WITH(parse_srdf_spheres("<robot><link_sphere_approximation link=\"a\rb\">"
                                       "<sphere center=\"0 0 0\" radius=\"1\"/>"
                                       "</link_sphere_approximation></robot>",
                                       "f.srdf"),
                    Contains("f.srdf") && Contains("control character"));
  const RobotSpheres tab{{"a\tb", {{{0, 0, 0}, 1.0}}}};
  CHECK_THROWS_WITH(srdf_spheres_text(tab, "r"), Contains("control character"));
  CHECK_THROWS_WITH(validate_robot_spheres(tab, "here"), Contains("\"a\tb\""));
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
  CHECK_THAT(problem(curobo, "collision_spheres: {l1: [{center: [0, 0, 0], radius: 0}]}"),
             Contains("link \"l1\"") && Contains("radius 0"));
  CHECK_THAT(problem(curobo, "collision_spheres: {l1: [{center: [0, 0, 0], radius: -.inf}]}"),
             Contains("link \"l1\"") && Contains("radius -inf"));
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
    // between base and l2, l3 between l2 and tool); the tool frame is l1, which carries
    // what only finger joints move (j2 prismatic, j3 a mimic); j2's default position is
    // moved into its limits.
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
    CHECK(x["tool_frames"].as<std::vector<std::string>>() == std::vector<std::string>{"l1"});
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
  // The planned joints: j2 is the gripper's (l1's finger joint), held at its default, which
  // default_joint_positions gives with j1's.
  const YAML::Node xrdf = YAML::Load(sphere_document_text(doc, SphereFormat::kXrdf));
  CHECK(xrdf["cspace"]["joint_names"].as<std::vector<std::string>>() ==
        std::vector<std::string>{"j1"});
  CHECK(xrdf["default_joint_positions"].size() == 2);
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

// ---------------------------------------------------------------------------------------------
// The loaders' contracts (curobo_yaml.h and xrdf.h list them with cuRobo's files and lines):
// one check per item, on the files of a robot model with a planner setup.

namespace {

using Names = std::vector<std::string>;

// The keys cuRobo's kinematics dataclasses take (v2 a35a708
// robot/loader/kinematics_loader_cfg.py:31-126; v1 d64c4b0
// cuda_robot_model/cuda_robot_generator.py:64-169): any other key is a TypeError.
const std::set<std::string> kV2Keys = {"base_link",
                                       "device_cfg",
                                       "tool_frames",
                                       "collision_link_names",
                                       "collision_spheres",
                                       "collision_sphere_buffer",
                                       "self_collision_buffer",
                                       "self_collision_ignore",
                                       "debug",
                                       "asset_root_path",
                                       "mesh_link_names",
                                       "grasp_contact_link_names",
                                       "load_tool_frames_with_mesh",
                                       "urdf_path",
                                       "lock_joints",
                                       "extra_links",
                                       "add_object_link",
                                       "use_external_assets",
                                       "external_asset_path",
                                       "external_robot_configs_path",
                                       "extra_collision_spheres",
                                       "load_collision_spheres",
                                       "num_envs",
                                       "cspace",
                                       "load_meshes",
                                       "use_global_cumul",
                                       "format_version"};
const std::set<std::string> kV1Keys = {"base_link",
                                       "ee_link",
                                       "tensor_args",
                                       "link_names",
                                       "collision_link_names",
                                       "collision_spheres",
                                       "collision_sphere_buffer",
                                       "compute_jacobian",
                                       "self_collision_buffer",
                                       "self_collision_ignore",
                                       "debug",
                                       "use_global_cumul",
                                       "asset_root_path",
                                       "mesh_link_names",
                                       "load_link_names_with_mesh",
                                       "urdf_path",
                                       "usd_path",
                                       "usd_robot_root",
                                       "isaac_usd_path",
                                       "use_usd_kinematics",
                                       "usd_flip_joints",
                                       "usd_flip_joint_limits",
                                       "lock_joints",
                                       "extra_links",
                                       "add_object_link",
                                       "use_external_assets",
                                       "external_asset_path",
                                       "external_robot_configs_path",
                                       "extra_collision_spheres",
                                       "cspace",
                                       "load_meshes"};

// PyYAML's float pattern (yaml/resolver.py, YAML 1.1), which cuRobo's loaders read with.
const std::regex kPyYamlFloat(
    R"(^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+][0-9]+)?|\.[0-9][0-9_]*(?:[eE][-+][0-9]+)?|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$)");

// Every plain scalar of \p n that reads as a number must be a PyYAML float.
void check_floats(const YAML::Node& n, const std::string& where, std::size_t& numbers) {
  if (n.IsMap()) {
    for (const auto& kv : n)
      check_floats(kv.second, where + "." + kv.first.as<std::string>(), numbers);
  } else if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i) check_floats(n[i], where, numbers);
  } else if (n.IsScalar()) {
    double v = 0;
    if (!YAML::convert<double>::decode(n, v)) return;
    INFO(where << ": " << n.Scalar());
    CHECK(std::regex_match(n.Scalar(), kPyYamlFloat));
    ++numbers;
  }
}

Names keys(const YAML::Node& map) {
  Names out;
  for (const auto& kv : map) out.push_back(kv.first.as<std::string>());
  return out;
}

// The three-link arm with spheres on base, l2 and tool, two tool frames, the gripper's j2
// locked, and a matrix that skips two pairs (one given by an SRDF).
medspheres::RobotModel planned_arm() {
  medspheres::RobotModel m = medspheres::test::three_link_arm();
  const RobotSpheres s = random_robot_spheres(9);
  m.links[0].spheres.outer.spheres = s[0].spheres;
  m.links[2].spheres.outer.spheres = s[1].spheres;
  m.links[4].spheres.outer.spheres = s[2].spheres;
  medspheres::PlannerSetup p;
  p.tool_frames = {"tool", "l2"};
  p.tool_frames_from = "option";
  p.locked_joints = {"j2"};
  p.default_positions = {{"j1", 1e-5}, {"j2", 0.25}};
  p.default_from = "sample";
  medspheres::SelfCollisionMatrix mx;
  mx.samples = 10;
  mx.pairs = {{"base", "l2", medspheres::PairClass::kAdjacent, true, ""},
              {"base", "tool", medspheres::PairClass::kGiven, true, "User"},
              {"l2", "tool", medspheres::PairClass::kChecked, false, ""}};
  mx.buffer = {{"base", -0.0125}, {"l2", 0.0}, {"tool", 0.0}};
  p.self_collision = mx;
  m.planner = p;
  return m;
}

YAML::Node curobo_file(const medspheres::RobotModel& m, CuroboLayout layout) {
  const SphereDocument doc = robot_document(m, SphereChoice::kOuter, "", "arm");
  WriteOptions o;
  o.curobo = layout;
  o.urdf_path = "/robots/arm.urdf";
  return YAML::Load(sphere_document_text(doc, SphereFormat::kCurobo, o));
}

}  // namespace

TEST_CASE("cuRobo loader contract: nesting, and only keys the dataclasses take", "[formats]") {
  const medspheres::RobotModel m = planned_arm();
  for (const auto& [layout, allowed] :
       {std::pair{CuroboLayout::kV2, &kV2Keys}, std::pair{CuroboLayout::kV1, &kV1Keys}}) {
    const YAML::Node f = curobo_file(m, layout);
    REQUIRE(f["robot_cfg"]["kinematics"].IsMap());
    for (const std::string& k : keys(f["robot_cfg"]["kinematics"])) {
      INFO("key " << k);
      CHECK(allowed->count(k) == 1);
    }
    const YAML::Node k = f["robot_cfg"]["kinematics"];
    CHECK(k["base_link"].as<std::string>() == "base");
    CHECK(k["urdf_path"].as<std::string>() == "/robots/arm.urdf");
    // collision_spheres: a mapping; collision_link_names: its keys, in order.
    CHECK(k["collision_spheres"].IsMap());
    CHECK(k["collision_link_names"].as<Names>() == keys(k["collision_spheres"]));
    CHECK(k["collision_link_names"].as<Names>() == Names{"base", "l2", "tool"});
    std::size_t numbers = 0;
    check_floats(f, "file", numbers);
    CHECK(numbers > 14 * 4);  // every sphere's four numbers at least
  }
}

TEST_CASE("cuRobo loader contract: v2 tool_frames, v1 ee_link and link_names", "[formats]") {
  const medspheres::RobotModel m = planned_arm();
  const YAML::Node v2 = curobo_file(m, CuroboLayout::kV2)["robot_cfg"]["kinematics"];
  CHECK(v2["tool_frames"].as<Names>() == Names{"tool", "l2"});
  CHECK(!v2["ee_link"]);
  CHECK(!v2["link_names"]);
  const YAML::Node v1 = curobo_file(m, CuroboLayout::kV1)["robot_cfg"]["kinematics"];
  CHECK(v1["ee_link"].as<std::string>() == "tool");
  CHECK(v1["link_names"].as<Names>() == Names{"tool", "l2"});
  CHECK(!v1["tool_frames"]);
  // One tool frame: v1 has no link_names.
  medspheres::RobotModel one = m;
  one.planner->tool_frames = {"tool"};
  CHECK(!curobo_file(one, CuroboLayout::kV1)["robot_cfg"]["kinematics"]["link_names"]);
}

TEST_CASE("cuRobo loader contract: buffers, ignore, lock_joints", "[formats]") {
  for (CuroboLayout layout : {CuroboLayout::kV2, CuroboLayout::kV1}) {
    const YAML::Node k = curobo_file(planned_arm(), layout)["robot_cfg"]["kinematics"];
    // collision_sphere_buffer: a float (isinstance(x, float)), not an integer.
    REQUIRE(k["collision_sphere_buffer"].IsScalar());
    CHECK(std::regex_match(k["collision_sphere_buffer"].Scalar(), kPyYamlFloat));
    CHECK(k["collision_sphere_buffer"].as<double>() == 0.0);
    // self_collision_buffer: a mapping over every collision link (.copy() on it).
    REQUIRE(k["self_collision_buffer"].IsMap());
    CHECK(keys(k["self_collision_buffer"]) == Names{"base", "l2", "tool"});
    CHECK(k["self_collision_buffer"]["base"].as<double>() == -0.0125);
    // self_collision_ignore: a mapping (.keys() on it), keyed by the earlier link.
    REQUIRE(k["self_collision_ignore"].IsMap());
    CHECK(keys(k["self_collision_ignore"]) == Names{"base"});
    CHECK(k["self_collision_ignore"]["base"].as<Names>() == Names{"l2", "tool"});
    // lock_joints: actuated joints (not mimic ones) at their default positions.
    REQUIRE(k["lock_joints"].IsMap());
    CHECK(keys(k["lock_joints"]) == Names{"j2"});
    CHECK(k["lock_joints"]["j2"].as<double>() == 0.25);
  }
  // With nothing skipped the ignore mapping is still written, empty.
  medspheres::RobotModel none = planned_arm();
  for (auto& p : none.planner->self_collision->pairs) p.ignored = false;
  const YAML::Node k = curobo_file(none, CuroboLayout::kV2)["robot_cfg"]["kinematics"];
  REQUIRE(k["self_collision_ignore"].IsMap());
  CHECK(k["self_collision_ignore"].size() == 0);
}

// The pairs of \p spheres (link -> [{center, radius}]) that \p ignore leaves checked, and the
// largest threshold r1 + r2 + buffer1 + buffer2 over their sphere pairs (cuRobo's test: two
// spheres collide when their centres are nearer than it).
static std::pair<std::size_t, double> checked_pairs(const YAML::Node& spheres,
                                                    const YAML::Node& ignore,
                                                    const YAML::Node& buffer) {
  const Names links = keys(spheres);
  std::size_t checked = 0;
  double threshold = -1e300;
  for (std::size_t i = 0; i < links.size(); ++i)
    for (std::size_t j = i + 1; j < links.size(); ++j) {
      bool skipped = false;
      for (const auto& [a, b] : {std::pair{links[i], links[j]}, std::pair{links[j], links[i]}})
        if (ignore[a])
          for (const std::string& n : ignore[a].as<Names>()) skipped |= n == b;
      if (skipped) continue;
      ++checked;
      for (const YAML::Node& s1 : spheres[links[i]])
        for (const YAML::Node& s2 : spheres[links[j]])
          threshold = std::max(threshold, s1["radius"].as<double>() + s2["radius"].as<double>() +
                                              buffer[links[i]].as<double>() +
                                              buffer[links[j]].as<double>());
    }
  return {checked, threshold};
}

TEST_CASE("cuRobo loader contract: with every pair skipped, one pair checked that cannot touch",
          "[formats]") {
  // cuRobo's loaders divide by the number of checked sphere pairs: a robot whose every pair
  // is skipped must still give them one, and it must never collide.
  medspheres::RobotModel all = planned_arm();
  for (auto& p : all.planner->self_collision->pairs) p.ignored = true;
  for (CuroboLayout layout : {CuroboLayout::kV2, CuroboLayout::kV1}) {
    const YAML::Node k = curobo_file(all, layout)["robot_cfg"]["kinematics"];
    const auto [checked, threshold] = checked_pairs(
        k["collision_spheres"], k["self_collision_ignore"], k["self_collision_buffer"]);
    CHECK(checked == 1);
    CHECK(threshold <= -0.01 + 1e-12);
  }
  const SphereDocument doc = robot_document(all, SphereChoice::kOuter, "", "arm");
  const YAML::Node x = YAML::Load(sphere_document_text(doc, SphereFormat::kXrdf));
  const std::string group = x["collision"]["geometry"].as<std::string>();
  const auto [checked, threshold] =
      checked_pairs(x["geometry"][group]["spheres"], x["self_collision"]["ignore"],
                    x["self_collision"]["buffer_distance"]);
  CHECK(checked == 1);
  CHECK(threshold <= -0.01 + 1e-12);
  // The SRDF still disables every pair.
  CHECK(
      parse_srdf_disabled_collisions(sphere_document_text(doc, SphereFormat::kSrdf), "f").size() ==
      all.planner->self_collision->pairs.size());
  // With one pair checked already, nothing changes.
  const YAML::Node k = curobo_file(planned_arm(), CuroboLayout::kV2)["robot_cfg"]["kinematics"];
  CHECK(k["self_collision_buffer"]["base"].as<double>() == -0.0125);
  CHECK(
      checked_pairs(k["collision_spheres"], k["self_collision_ignore"], k["self_collision_buffer"])
          .first == 1);
}

// The arm with spheres on l2 alone.
static medspheres::RobotModel one_link_with_spheres() {
  medspheres::RobotModel m = planned_arm();
  for (medspheres::Link& l : m.links)
    if (l.name != "l2") l.spheres.outer.spheres.clear();
  return m;
}

// Per sphere of \p spheres' link \p link, each radius.
static std::vector<double> radii(const YAML::Node& spheres, const std::string& link) {
  std::vector<double> out;
  for (const YAML::Node& s : spheres[link]) out.push_back(s["radius"].as<double>());
  return out;
}

TEST_CASE("cuRobo loader contract: spheres on one link, a placeholder frame gives v2 its pairs",
          "[formats]") {
  // cuRobo v2 divides by the number of checked sphere pairs, and one link has none: its
  // files add a frame at the base with one disabled sphere, whose pairs can never touch.
  const medspheres::RobotModel m = one_link_with_spheres();
  const YAML::Node k = curobo_file(m, CuroboLayout::kV2)["robot_cfg"]["kinematics"];
  CHECK(k["collision_link_names"].as<Names>() == Names{"l2", "medspheres_placeholder"});
  const YAML::Node link = k["extra_links"]["medspheres_placeholder"];
  REQUIRE(link.IsMap());
  CHECK(link["parent_link_name"].as<std::string>() == "base");
  CHECK(link["link_name"].as<std::string>() == "medspheres_placeholder");
  CHECK(link["joint_name"].as<std::string>() == "medspheres_placeholder_joint");
  CHECK(link["joint_type"].as<std::string>() == "FIXED");
  CHECK(link["fixed_transform"].as<std::vector<double>>() ==
        std::vector<double>{0, 0, 0, 1, 0, 0, 0});
  const std::vector<double> own = radii(k["collision_spheres"], "l2");
  const std::vector<double> placeholder = radii(k["collision_spheres"], "medspheres_placeholder");
  REQUIRE(placeholder.size() == 1);
  // Every pair's threshold r1 + r2 + buffers (l2's buffer 0, the frame's unset: 0) < 0.
  CHECK(*std::max_element(own.begin(), own.end()) + placeholder[0] < 0.0);
  CHECK(k["self_collision_buffer"]["l2"].as<double>() == 0.0);
  // Read back, the disabled sphere and its frame are left out.
  const SphereDocument doc = robot_document(m, SphereChoice::kOuter, "", "arm");
  WriteOptions o;
  o.curobo = CuroboLayout::kV2;
  CHECK(identical(parse_curobo_yaml(sphere_document_text(doc, SphereFormat::kCurobo, o), "f"),
                  doc.links));
  // v1 loads a robot without checked pairs as it is.
  const YAML::Node v1 = curobo_file(m, CuroboLayout::kV1)["robot_cfg"]["kinematics"];
  CHECK(!v1["extra_links"]);
  CHECK(v1["collision_link_names"].as<Names>() == Names{"l2"});
  // The XRDF: the frame as the modifier add_frame, its sphere in the geometry group.
  const std::string xrdf = sphere_document_text(doc, SphereFormat::kXrdf);
  const YAML::Node x = YAML::Load(xrdf);
  REQUIRE(x["modifiers"].size() == 2);
  CHECK(x["modifiers"][0]["set_base_frame"].as<std::string>() == "base");
  const YAML::Node frame = x["modifiers"][1]["add_frame"];
  REQUIRE(frame.IsMap());
  CHECK(frame["frame_name"].as<std::string>() == "medspheres_placeholder");
  CHECK(frame["parent_frame_name"].as<std::string>() == "base");
  CHECK(frame["joint_name"].as<std::string>() == "medspheres_placeholder_joint");
  CHECK(frame["joint_type"].as<std::string>() == "FIXED");
  CHECK(frame["fixed_transform"]["position"].as<std::vector<double>>() ==
        std::vector<double>{0, 0, 0});
  CHECK(frame["fixed_transform"]["orientation"]["w"].as<double>() == 1.0);
  CHECK(frame["fixed_transform"]["orientation"]["xyz"].as<std::vector<double>>() ==
        std::vector<double>{0, 0, 0});
  const YAML::Node g = x["geometry"][x["collision"]["geometry"].as<std::string>()]["spheres"];
  CHECK(keys(g) == Names{"l2", "medspheres_placeholder"});
  CHECK(radii(g, "medspheres_placeholder") == placeholder);
  CHECK(identical(parse_xrdf(xrdf, "f"), doc.links));
  // A robot with spheres on two links or more has no such frame.
  CHECK(!curobo_file(planned_arm(), CuroboLayout::kV2)["robot_cfg"]["kinematics"]["extra_links"]);
  // The frame's name is apart from every link's.
  medspheres::RobotModel named = m;
  named.links.push_back(medspheres::test::make_link("medspheres_placeholder"));
  named.joints.push_back(medspheres::test::make_joint("extra", medspheres::JointType::kFixed,
                                                      "tool", "medspheres_placeholder", {0, 0, 1}));
  const YAML::Node n = curobo_file(named, CuroboLayout::kV2)["robot_cfg"]["kinematics"];
  CHECK(n["extra_links"]["medspheres_placeholder_"].IsMap());
}

TEST_CASE("cuRobo's disabled spheres (negative radius) are left out when read", "[formats]") {
  // cuRobo's own ur10e.yml puts {center: [0, 0, 0.12], radius: -0.01} on tool0.
  const RobotSpheres read = parse_curobo_yaml(
      "collision_spheres:\n"
      "  wrist: [{center: [0, 0, 0], radius: 0.05}, {center: [0, 0, 1], radius: -10.0}]\n"
      "  tool0: [{center: [0, 0, 0.12], radius: -0.01}]\n",
      "f");
  REQUIRE(read.size() == 1);
  CHECK(read[0].link == "wrist");
  REQUIRE(read[0].spheres.size() == 1);
  CHECK(read[0].spheres[0].radius == 0.05);
}

TEST_CASE("no XRDF for a robot without an actuated joint", "[formats]") {
  // cuRobo's XRDF loaders take the largest acceleration limit of the cspace's joints, so a
  // robot with none (a gripper on its own) gets no XRDF, and a warning says why.
  medspheres::RobotModel m = planned_arm();
  CHECK(writes_xrdf(m));
  for (medspheres::Joint& j : m.joints) j.type = medspheres::JointType::kFixed;
  CHECK_FALSE(writes_xrdf(m));
  const std::vector<std::string> problems = curobo_urdf_problems(m);
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Contains("no actuated joint") && Contains("no XRDF"));
}

TEST_CASE("cuRobo loader contract: cspace in v2's and v1's names", "[formats]") {
  for (CuroboLayout layout : {CuroboLayout::kV2, CuroboLayout::kV1}) {
    const YAML::Node c = curobo_file(planned_arm(), layout)["robot_cfg"]["kinematics"]["cspace"];
    REQUIRE(c.IsMap());
    // Every actuated joint (the locked one too: cuRobo v2 requires a joint of the cspace
    // that is not in the planned tree to be locked).
    CHECK(c["joint_names"].as<Names>() == Names{"j1", "j2"});
    const char* key = layout == CuroboLayout::kV2 ? "default_joint_position" : "retract_config";
    const char* other = layout == CuroboLayout::kV2 ? "retract_config" : "default_joint_position";
    CHECK(c[key].as<std::vector<double>>() == std::vector<double>{1e-5, 0.25});
    CHECK(!c[other]);
    for (const char* list :
         {"null_space_weight", "cspace_distance_weight", "max_acceleration", "max_jerk"})
      CHECK(c[list].size() == 2);
  }
}

TEST_CASE("cuRobo loader contract: a spheres-only file that a configuration names", "[formats]") {
  const medspheres::RobotModel m = planned_arm();
  const YAML::Node f = curobo_file(m, CuroboLayout::kSpheres);
  // The file a configuration's `collision_spheres: "<path>"` names: collision_spheres at the
  // top level and nothing else (v2 kinematics_loader_cfg.py:176, v1 :216).
  CHECK(keys(f) == Names{"collision_spheres"});
  const SphereDocument doc = robot_document(m, SphereChoice::kOuter, "", "arm");
  WriteOptions o;
  o.curobo = CuroboLayout::kSpheres;
  CHECK(identical(parse_curobo_yaml(sphere_document_text(doc, SphereFormat::kCurobo, o), "f"),
                  doc.links));
}

TEST_CASE("XRDF loader contract: every required section", "[formats]") {
  const medspheres::RobotModel m = planned_arm();
  const SphereDocument doc = robot_document(m, SphereChoice::kOuter, "", "arm");
  const YAML::Node x = YAML::Load(sphere_document_text(doc, SphereFormat::kXrdf));
  CHECK(x["format"].as<std::string>() == "xrdf");
  CHECK(std::regex_match(x["format_version"].Scalar(), kPyYamlFloat));
  const std::string group = x["collision"]["geometry"].as<std::string>();
  CHECK(x["geometry"][group]["spheres"].IsMap());
  CHECK(keys(x["geometry"][group]["spheres"]) == Names{"base", "l2", "tool"});
  CHECK(x["self_collision"]["geometry"].as<std::string>() == group);
  REQUIRE(x["self_collision"]["ignore"].IsMap());
  CHECK(x["self_collision"]["ignore"]["base"].as<Names>() == Names{"l2", "tool"});
  REQUIRE(x["self_collision"]["buffer_distance"].IsMap());
  CHECK(x["self_collision"]["buffer_distance"]["base"].as<double>() == -0.0125);
  CHECK(x["tool_frames"].as<Names>() == Names{"tool", "l2"});
  // The base link named, so that the chain starts there whatever the URDF's root
  // (UrdfRobot::free_base).
  REQUIRE(x["modifiers"].IsSequence());
  REQUIRE(x["modifiers"].size() == 1);
  CHECK(x["modifiers"][0].size() == 1);
  CHECK(x["modifiers"][0]["set_base_frame"].as<std::string>() == "base");
  // The planned joints; the locked j2 is left out of the cspace, so the loader locks it at
  // its default_joint_positions value.
  CHECK(x["cspace"]["joint_names"].as<Names>() == Names{"j1"});
  CHECK(x["cspace"]["acceleration_limits"].size() == 1);
  CHECK(x["cspace"]["jerk_limits"].size() == 1);
  REQUIRE(x["default_joint_positions"].IsMap());
  CHECK(keys(x["default_joint_positions"]) == Names{"j1", "j2"});
  CHECK(x["default_joint_positions"]["j2"].as<double>() == 0.25);
  std::size_t numbers = 0;
  check_floats(x, "xrdf", numbers);
  CHECK(numbers > 14 * 4);
}

TEST_CASE("SRDF: every skipped pair as a disable_collisions with its reason", "[formats]") {
  const medspheres::RobotModel m = planned_arm();
  const SphereDocument doc = robot_document(m, SphereChoice::kOuter, "", "arm");
  const std::string text = sphere_document_text(doc, SphereFormat::kSrdf);
  const auto pairs = parse_srdf_disabled_collisions(text, "f");
  REQUIRE(pairs.size() == 2);
  CHECK(pairs[0].link1 == "base");
  CHECK(pairs[0].link2 == "l2");
  CHECK(pairs[0].reason == "Adjacent");
  CHECK(pairs[1].link2 == "tool");
  CHECK(pairs[1].reason == "User");  // a given pair keeps the SRDF's own reason
  CHECK(identical(parse_srdf_spheres(text, "f"), doc.links));
}

TEST_CASE("cuRobo v1's URDF parser: a mimic joint driven beyond its own limits is named",
          "[formats]") {
  auto revolute = [](const std::string& name, double limit, double velocity) {
    medspheres::Joint j;
    j.name = name;
    j.type = medspheres::JointType::kRevolute;
    j.limits = medspheres::JointLimits{-limit, limit, velocity, 1.0};
    return j;
  };
  auto mimic = [&](const std::string& name, double limit, double velocity, double multiplier,
                   double offset) {
    medspheres::Joint j = revolute(name, limit, velocity);
    j.mimic = medspheres::JointMimic{"source", multiplier, offset};
    return j;
  };
  medspheres::RobotModel m;
  m.joints = {revolute("source", 1.0, 2.0),
              mimic("within", 2.0, 3.0, 1.0, 0.5),      // [-0.5, 1.5] within [-2, 2]; 2 <= 3
              mimic("above", 1.0, 3.0, 1.0, 0.5),       // upper 1.5 > 1
              mimic("faster", 3.0, 3.0, 2.0, 0.0),      // velocity 4 > 3
              mimic("mirrored", 1.0, 2.0, -1.0, 0.0)};  // v1 maps lower to -1 * -1: 1, not < -1
  const std::vector<std::string> problems = medspheres::formats::curobo_urdf_problems(m);
  REQUIRE(problems.size() == 2);
  CHECK_THAT(problems[0], Catch::Matchers::Contains("mimic joint 'above' follows 'source'"));
  CHECK_THAT(problems[0], Catch::Matchers::Contains("(upper 1.5 > 1)"));
  CHECK_THAT(problems[0], Catch::Matchers::Contains("cuRobo v1's URDF parser refuses"));
  CHECK_THAT(problems[1], Catch::Matchers::Contains("mimic joint 'faster'"));
  CHECK_THAT(problems[1], Catch::Matchers::Contains("(velocity 4 > 3)"));
}
