// medspheres robot and eval of a robot, run as a user runs them: the output folder, the
// robot file's spheres inside their links, bad robots (exit 2, no output), jobs.
#include <algorithm>
#include <filesystem>
#include <set>
#include <string>

#include <yaml-cpp/yaml.h>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/formats/sphere_document.h"
#include "medspheres/io.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/robot_file.h"
#include "support/generated_arms.h"
#include "support/run_command.h"
#include "support/sanitizer_build.h"
#include "support/urdf_fixtures.h"

using Catch::Matchers::Contains;
using medspheres::test::CommandResult;
using medspheres::test::run_command;
using medspheres::test::shell_quote;
using medspheres::test::TempDir;
namespace fs = std::filesystem;

namespace {

CommandResult cli(const std::string& args, int seconds = 300) {
  return run_command("timeout " + std::to_string(seconds) + " " + shell_quote(MEDSPHERES_CLI) +
                     " " + args);
}

// The sphere pairs a loader of the cuRobo YAML \p path checks for self-collision, counted
// sphere by sphere as cuRobo builds them: every sphere of collision_spheres against every
// sphere of another listed link, unless self_collision_ignore names the pair either way.
std::size_t curobo_sphere_pairs(const std::string& path) {
  const YAML::Node k = YAML::LoadFile(path)["robot_cfg"]["kinematics"];
  std::vector<std::string> owner;  // the link of each sphere
  for (const auto& link : k["collision_link_names"]) {
    const std::string name = link.as<std::string>();
    for (std::size_t i = 0; i < k["collision_spheres"][name].size(); ++i) owner.push_back(name);
  }
  auto ignored = [&](const std::string& a, const std::string& b) {
    for (const auto& other : k["self_collision_ignore"][a])
      if (other.as<std::string>() == b) return true;
    return false;
  };
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < owner.size(); ++i)
    for (std::size_t j = i + 1; j < owner.size(); ++j)
      if (owner[i] != owner[j] && !ignored(owner[i], owner[j]) && !ignored(owner[j], owner[i]))
        ++pairs;
  return pairs;
}

std::string arm_args(const TempDir& dir, const std::string& urdf, const std::string& out) {
  return shell_quote(urdf) + " -o " + shell_quote(out) + " --package " +
         shell_quote("arm_pkg=" + (dir.path() / "pkg/arm_pkg").string()) + " --spheres-per-link 10";
}

// `eval --json` of the arm's URDF against the sphere file \p file (a path in \p dir), which
// must succeed; \p sampling: its --samples and --surface-samples.
nlohmann::json eval_arm(const TempDir& dir, const std::string& urdf, const std::string& file,
                        const std::string& sampling) {
  const CommandResult r =
      cli("eval " + shell_quote(urdf) + " " + shell_quote(dir.file(file)) + " --package " +
          shell_quote("arm_pkg=" + (dir.path() / "pkg/arm_pkg").string()) + sampling + " --json");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  return nlohmann::json::parse(r.out);
}

// The entries of \p dir (the temporary folders robot might leave behind included).
std::size_t entries(const fs::path& dir) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) (void)e, ++n;
  return n;
}

}  // namespace

TEST_CASE("robot writes a folder whose robot file has each link's spheres", "[cli][robot]") {
  TempDir dir;
  const std::string urdf = medspheres::test::write_arm(dir);
  const std::string out = dir.file("out");
  const CommandResult r = cli("robot " + arm_args(dir, urdf, out) + " --jobs 2");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.err, Contains("forearm") && Contains("triangles"));
  CHECK_THAT(r.out, Contains("total") && Contains("no collision geometry"));
  const medspheres::RobotModel model = medspheres::load_robot(out + "/arm.robot.json");
  REQUIRE(model.links.size() == 4);
  CHECK(model.joints.size() == 3);
  // The forearm's spheres inside its mesh as the URDF places it, computed here.
  medspheres::TriangleMesh forearm =
      medspheres::load_mesh((dir.path() / "meshes/forearm.obj").string()).mesh;
  const Eigen::Matrix3d rot = medspheres::test::rpy_matrix(0.3, -0.4, 0.9);
  for (Eigen::Vector3d& v : forearm.vertices)
    v = rot * v.cwiseProduct(Eigen::Vector3d(2, 0.5, 1.5)) + Eigen::Vector3d(0.1, -0.05, 0.2);
  const medspheres::MeshQuery query(forearm);
  const medspheres::Link* link = model.find_link("forearm");
  REQUIRE(link != nullptr);
  REQUIRE(!link->spheres.inner.empty());
  CHECK(link->spheres.inner.size() <= 10);
  for (const medspheres::Sphere& s : link->spheres.inner.spheres) {
    CHECK(query.winding_number(s.center) > 0.5);
    CHECK(query.closest_point(s.center).distance() >= s.radius);
  }

  // Every baked link has a covering set with its certificate, and every planner format
  // carries those covering sets.
  for (const medspheres::Link& l : model.links) {
    INFO(l.name);
    CHECK(l.spheres.outer.empty() == l.spheres.inner.empty());
    if (!l.spheres.outer.empty())
      CHECK(nlohmann::json::parse(l.spheres.outer_certificate_json)["certified"] == true);
  }
  for (const std::string name :
       {"arm.curobo.yml", "arm.xrdf", "arm.spherized.urdf", "arm.srdf", "arm.foam.json"}) {
    INFO(name);
    const medspheres::formats::SphereDocument doc =
        medspheres::formats::read_sphere_document(out + "/" + name);
    for (const medspheres::Link& l : model.links) {
      const auto* got = medspheres::formats::find_link_spheres(doc.links, l.name);
      if (l.spheres.outer.empty()) {
        CHECK(got == nullptr);
        continue;
      }
      REQUIRE(got != nullptr);
      REQUIRE(got->spheres.size() == l.spheres.outer.size());
      for (std::size_t k = 0; k < got->spheres.size(); ++k) {
        CHECK(got->spheres[k].center == l.spheres.outer.spheres[k].center);
        CHECK(got->spheres[k].radius == l.spheres.outer.spheres[k].radius);
      }
    }
  }
  CHECK(fs::exists(out + "/sph/forearm.sph"));
  CHECK(fs::exists(out + "/sph/hand.sph"));
  CHECK_FALSE(fs::exists(out + "/sph/tool.sph"));

  // Run again into the same folder: replaced as a whole, nothing left beside it.
  REQUIRE(cli("robot " + arm_args(dir, urdf, out) + " -q").exit_code == 0);
  CHECK(fs::exists(out + "/arm.robot.json"));
  CHECK(entries(dir.path()) == 4);  // arm.urdf, meshes, pkg, out
}

TEST_CASE("robot: --jobs 1 and --jobs 2 give the same spheres", "[cli][robot]") {
  TempDir dir;
  const std::string urdf = medspheres::test::write_arm(dir);
  REQUIRE(cli("robot " + arm_args(dir, urdf, dir.file("a")) + " -q --jobs 1").exit_code == 0);
  REQUIRE(cli("robot " + arm_args(dir, urdf, dir.file("b")) + " -q --jobs 2").exit_code == 0);
  const medspheres::RobotModel a = medspheres::load_robot(dir.file("a/arm.robot.json"));
  const medspheres::RobotModel b = medspheres::load_robot(dir.file("b/arm.robot.json"));
  REQUIRE(a.links.size() == b.links.size());
  for (std::size_t i = 0; i < a.links.size(); ++i) {
    const auto& sa = a.links[i].spheres.inner.spheres;
    const auto& sb = b.links[i].spheres.inner.spheres;
    REQUIRE(sa.size() == sb.size());
    for (std::size_t k = 0; k < sa.size(); ++k) {
      CHECK(sa[k].center == sb[k].center);
      CHECK(sa[k].radius == sb[k].radius);
    }
  }
  // The planner files have no timings: byte for byte the same.
  for (const std::string name : {"arm.curobo.yml", "arm.xrdf", "arm.spherized.urdf", "arm.srdf",
                                 "arm.foam.json", "sph/forearm.sph"}) {
    INFO(name);
    CHECK(medspheres::test::read_file(dir.file("a/" + name)) ==
          medspheres::test::read_file(dir.file("b/" + name)));
  }
}

TEST_CASE("robot: bad robots exit 2 naming the URDF and the link, with no output", "[cli][robot]") {
  TempDir dir;
  medspheres::test::write_arm(dir);
  struct Case {
    const char* what;
    std::string urdf;
    std::string expect;
  };
  const std::string head = "<robot name=\"r\">";
  const std::string box =
      R"(<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>)";
  const std::vector<Case> cases = {
      {"malformed", head + "<link name=\"a\">", "not well-formed"},
      {"missing mesh",
       head + R"(<link name="a"><collision><geometry><mesh filename="gone.stl"/></geometry>
         </collision></link></robot>)",
       "link 'a'"},
      {"unknown package",
       head + R"(<link name="a"><collision><geometry><mesh filename="package://nope/m.stl"/>
         </geometry></collision></link></robot>)",
       "unknown package 'nope'"},
      {"joint cycle", head + R"(<link name="b"/><link name="c"/>
         <joint name="j2" type="fixed"><parent link="b"/><child link="c"/></joint>
         <joint name="j3" type="fixed"><parent link="c"/><child link="b"/></joint></robot>)",
       "joint cycle"},
      {"empty link", head + R"(<link name="a"><collision><geometry><box size="0 1 1"/>
         </geometry></collision></link></robot>)",
       "link 'a'"},
      {"unsupported geometry", head + R"(<link name="a"><collision><geometry>
         <cone radius="0.1" length="0.2"/></geometry></collision></link></robot>)",
       "cone"},
      {"floating joint below the root", head + "<link name=\"a\">" + box + R"(</link>
         <link name="b">)" + box + R"(</link>
         <joint name="loose" type="floating"><parent link="a"/><child link="b"/></joint></robot>)",
       "joint 'loose'"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    const std::string urdf = dir.write("bad.urdf", c.urdf);
    const std::string out = dir.file("out");
    const std::size_t before = entries(dir.path());
    const CommandResult r = cli("robot " + shell_quote(urdf) + " -o " + shell_quote(out));
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(urdf) && Contains(c.expect));
    CHECK_FALSE(fs::exists(out));
    CHECK(entries(dir.path()) == before);
  }
}

TEST_CASE(
    "robot: a floating joint from a bare root link is left out, and the files' base is its "
    "child",
    "[cli][robot]") {
  TempDir dir;
  std::string text = medspheres::read_text_file(medspheres::test::write_arm(dir));
  const std::string free = R"(<link name="world"/>
  <joint name="free" type="floating"><parent link="world"/><child link="base"/></joint>
  )";
  text.insert(text.find("<link name=\"base\">"), free);
  const std::string urdf = dir.write("floating_arm.urdf", text);
  const std::string out = dir.file("out");
  const CommandResult r = cli("robot " + arm_args(dir, urdf, out) + " --jobs 2");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.err, Contains("the floating joint 'free' and the root link 'world'") &&
                        Contains("base link is 'base'"));
  const YAML::Node xrdf = YAML::LoadFile(out + "/arm.xrdf");
  CHECK(xrdf["modifiers"][0]["set_base_frame"].as<std::string>() == "base");
  const YAML::Node yml = YAML::LoadFile(out + "/arm.curobo.yml");
  CHECK(yml["robot_cfg"]["kinematics"]["base_link"].as<std::string>() == "base");
  const medspheres::RobotModel model = medspheres::load_robot(out + "/arm.robot.json");
  CHECK(model.root_link == "base");
  CHECK(model.find_link("world") == nullptr);
  for (const medspheres::Joint& j : model.joints) CHECK(j.name != "free");
}

TEST_CASE("robot: an output folder that holds an input is refused, and the inputs stay",
          "[cli][robot]") {
  // The folder is replaced as a whole: -o naming the URDF's folder, or a folder above its
  // meshes, would remove them.
  TempDir dir;
  const std::string urdf = medspheres::test::write_arm(dir);
  const std::string mesh = dir.file("meshes/forearm.obj");
  const std::string bytes = medspheres::read_text_file(mesh);
  for (const std::string& out : {dir.path().string(), dir.file("meshes"), dir.file("pkg")}) {
    INFO(out);
    const std::size_t before = entries(dir.path());
    const CommandResult r = cli("robot " + arm_args(dir, urdf, out));
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains("--output: " + out + " holds the input"));
    CHECK(entries(dir.path()) == before);
    CHECK(medspheres::read_text_file(mesh) == bytes);
  }
  CHECK(fs::exists(dir.file("pkg/arm_pkg/meshes/hand.obj")));
  // A batch whose robot's own folder (out/arm) holds its meshes: quiet, yet it says why.
  fs::create_directories(dir.path() / "batch/arm");
  fs::copy_file(mesh, dir.path() / "batch/arm/forearm.obj");
  std::string text = medspheres::read_text_file(urdf);
  text.replace(text.find("meshes/forearm.obj"), 18, "arm/forearm.obj");
  dir.write("batch/arm.urdf", text);
  const CommandResult batch =
      cli("robot " + shell_quote(dir.file("batch")) + " -o " + shell_quote(dir.file("batch")) +
          " -q --package " + shell_quote("arm_pkg=" + (dir.path() / "pkg/arm_pkg").string()));
  CHECK(batch.exit_code == 2);
  CHECK_THAT(batch.err, Contains("holds the input") && Contains("forearm.obj"));
  CHECK(medspheres::read_text_file(dir.file("batch/arm/forearm.obj")) == bytes);
}

TEST_CASE("robot: a gripper on its own (one link, no joint) gets files cuRobo loads",
          "[cli][robot]") {
  TempDir dir;
  const std::string urdf = dir.write("gripper.urdf", R"(<?xml version="1.0"?>
<robot name="gripper">
  <link name="hand">
    <collision><geometry><box size="0.2 0.05 0.06"/></geometry></collision>
  </link>
</robot>
)");
  const std::string out = dir.file("out");
  const CommandResult r =
      cli("robot " + shell_quote(urdf) + " -o " + shell_quote(out) + " --spheres-per-link 6");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  // No XRDF: cuRobo's XRDF loaders need a cspace joint.
  CHECK_THAT(r.err, Contains("no actuated joint") && Contains("writes no XRDF"));
  CHECK_FALSE(fs::exists(out + "/gripper.xrdf"));
  CHECK(fs::exists(out + "/gripper.robot.json"));
  // cuRobo v2 gets sphere pairs to divide by, none of which can touch.
  const YAML::Node k = YAML::LoadFile(out + "/gripper.curobo.yml")["robot_cfg"]["kinematics"];
  CHECK(k["extra_links"]["medspheres_placeholder"]["parent_link_name"].as<std::string>() == "hand");
  CHECK(curobo_sphere_pairs(out + "/gripper.curobo.yml") == k["collision_spheres"]["hand"].size());
  double largest = 0.0;
  for (const auto& sphere : k["collision_spheres"]["hand"])
    largest = std::max(largest, sphere["radius"].as<double>());
  CHECK(largest + k["collision_spheres"]["medspheres_placeholder"][0]["radius"].as<double>() < 0);
  const YAML::Node v1 = YAML::LoadFile(out + "/gripper.curobo_v1.yml")["robot_cfg"]["kinematics"];
  CHECK_FALSE(v1["extra_links"]);
}

TEST_CASE("robot: a link name with XML special characters works", "[cli][robot]") {
  TempDir dir;
  const std::string urdf = dir.write("s.urdf", R"(<robot name="s">
  <link name="a&amp;b&lt;c&gt;"><collision><geometry><box size="0.1 0.2 0.3"/></geometry>
  </collision></link></robot>)");
  const CommandResult r = cli("robot " + shell_quote(urdf) + " -o " + shell_quote(dir.file("out")) +
                              " --spheres-per-link 5");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const medspheres::RobotModel m = medspheres::load_robot(dir.file("out/s.robot.json"));
  REQUIRE(m.links.size() == 1);
  CHECK(m.links[0].name == "a&b<c>");
  CHECK(!m.links[0].spheres.inner.empty());
}

TEST_CASE("robot: bad options exit 2 before any work", "[cli][robot]") {
  TempDir dir;
  const std::string urdf = medspheres::test::write_arm(dir);
  const std::string out = shell_quote(dir.file("out"));
  const std::string pkg =
      " --package " + shell_quote("arm_pkg=" + (dir.path() / "pkg/arm_pkg").string());
  for (const std::string& bad : {std::string(" --spheres-per-link 0"),
                                 std::string(" --budget 5 --spheres-per-link 3"),
                                 std::string(" --link forearm"),
                                 std::string(" --link nowhere=3"),
                                 std::string(" --format nonsense"),
                                 std::string(" --jobs -1"),
                                 std::string(" --budget 2"),
                                 std::string(" --self-collision-samples 0"),
                                 std::string(" --self-collision-threshold 0"),
                                 std::string(" --self-collision-margin -1"),
                                 std::string(" --tool-frame ghost"),
                                 std::string(" --free-joint ghost"),
                                 std::string(" --srdf ") + shell_quote(dir.file("missing.srdf")),
                                 std::string(" --srdf ''"),
                                 std::string(" --contact-band -1"),  // checked without --contact
                                 std::string(" --contact --no-self-collision"),
                                 std::string(" --contact --no-outer"),
                                 std::string(" --contact --contact-band 0"),
                                 std::string(" --contact --contact-weight 0.5"),
                                 std::string(" --contact --contact-samples 0"),
                                 std::string(" --fill-covers --no-outer"),
                                 std::string(" --balance-rounds 4 --no-outer"),
                                 std::string(" --protrusion-restarts -1"),
                                 std::string(" --protrusion-allowance -1"),
                                 std::string(" --robust-resolution 5")}) {
    INFO(bad);
    const CommandResult r = cli("robot " + shell_quote(urdf) + " -o " + out + pkg + bad);
    CHECK(r.exit_code == 2);
    CHECK_FALSE(fs::exists(dir.file("out")));
  }
  // Unsigned options: "-1" is refused by name, not read as the type's largest value (which
  // once failed allocating the samples, exit 1, or ran with another seed).
  for (const std::string flag : {"--self-collision-samples", "--self-collision-seed",
                                 "--self-collision-estimate", "--contact-samples", "--seed"}) {
    INFO(flag);
    const std::string contact = flag == "--contact-samples" ? " --contact" : "";
    const CommandResult r =
        cli("robot " + shell_quote(urdf) + " -o " + out + pkg + contact + " " + flag + " -1");
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(flag + ": must be an integer >= 0, got -1"));
    CHECK_FALSE(fs::exists(dir.file("out")));
  }
  // A job count out of range is refused by its name, one robot or a batch of two.
  for (const std::string jobs : {"-1", "2000"})
    for (const std::string& robots :
         {shell_quote(urdf), shell_quote(urdf) + " " + shell_quote(urdf)}) {
      const CommandResult r = cli("robot " + robots + " -o " + out + pkg + " --jobs " + jobs);
      CHECK(r.exit_code == 2);
      CHECK_THAT(r.err, Contains("--jobs: must be in [0, 1024]"));
    }
  dir.write("file", "x");
  CHECK(
      cli("robot " + shell_quote(urdf) + " -o " + shell_quote(dir.file("file")) + pkg).exit_code ==
      2);
}

TEST_CASE("eval of a robot: one row per link", "[cli][robot]") {
  TempDir dir;
  const std::string urdf = medspheres::test::write_arm(dir);
  // The planner formats carry the inner sets here, which the robot file's eval measures.
  REQUIRE(cli("robot " + arm_args(dir, urdf, dir.file("out")) + " --set inner -q").exit_code == 0);
  const std::string sampling = " --samples 20000 --surface-samples 2000";
  const auto j = eval_arm(dir, urdf, "out/arm.robot.json", sampling);
  REQUIRE(j["links"].size() == 4);
  for (int i = 0; i < 3; ++i) {
    INFO(j["links"][i]["link"]);
    // Inner sets: nothing sticks out. The base's box and cylinder overlap, so its volume
    // counts the overlap twice and its nerr is approximate.
    CHECK(j["links"][i]["nerr_kind"] == (i == 0 ? "approximate" : "exact"));
    CHECK(j["links"][i]["max_protrusion"].get<double>() <= 0.0);
    CHECK(j["links"][i]["nerr"].get<double>() > 0.0);
  }
  CHECK(j["links"][2]["primitives"] == 1);
  CHECK(j["links"][3]["note"] == "no collision geometry");
  // The same from every planner file, which carry the same spheres.
  for (const std::string name :
       {"arm.curobo.yml", "arm.xrdf", "arm.srdf", "arm.spherized.urdf", "arm.foam.json"}) {
    INFO(name);
    const auto jy = eval_arm(dir, urdf, "out/" + name, sampling);
    for (int i = 0; i < 3; ++i) CHECK(jy["links"][i]["nerr"] == j["links"][i]["nerr"]);
  }
}

TEST_CASE("robot: budgets, --link, --format, --no-outer and the tree reach the output",
          "[cli][robot]") {
  TempDir dir;
  const std::string urdf = medspheres::test::write_arm(dir);
  const std::string out = dir.file("out");
  const std::string pkg =
      " --package " + shell_quote("arm_pkg=" + (dir.path() / "pkg/arm_pkg").string());
  const CommandResult r = cli("robot " + shell_quote(urdf) + " -o " + shell_quote(out) + pkg +
                              " --budget 12 --link forearm=5 --no-outer --format robot,xrdf -q");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  // Only the chosen formats, and beside the robot file its self-collision report.
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(out)) files.insert(e.path().filename().string());
  CHECK(files == std::set<std::string>{"arm.robot.json", "arm.self_collision.txt", "arm.xrdf"});
  const medspheres::RobotModel m = medspheres::load_robot(out + "/arm.robot.json");
  std::size_t total = 0;
  for (const medspheres::Link& l : m.links) {
    CHECK(l.spheres.outer.empty());  // --no-outer
    total += l.spheres.inner.size();
  }
  CHECK(total <= 12);
  CHECK(m.find_link("forearm")->spheres.inner.size() <= 5);
  CHECK(!m.find_link("base")->spheres.inner.empty());
  CHECK(!m.find_link("hand")->spheres.inner.empty());
  // The kinematic tree as the URDF has it: limits, mimic, axis, origin.
  const medspheres::Joint* j1 = m.find_joint("j1");
  const medspheres::Joint* j2 = m.find_joint("j2");
  REQUIRE((j1 && j2));
  CHECK(j1->type == medspheres::JointType::kRevolute);
  CHECK(j1->axis == Eigen::Vector3d::UnitZ());
  CHECK(j1->origin.translation() == Eigen::Vector3d(0, 0, 0.1));
  CHECK((j1->origin.linear() - Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix())
            .norm() < 1e-15);
  REQUIRE(j1->limits);
  CHECK(j1->limits->lower == -1.5);
  CHECK(j1->limits->effort == 10);
  REQUIRE(j2->mimic);
  CHECK(j2->mimic->joint == "j1");
  CHECK(j2->mimic->multiplier == 0.5);
  CHECK(j2->mimic->offset == 0.01);
  // Provenance: the URDF, each mesh's sha256, the options, per-link statistics.
  const auto meta = nlohmann::json::parse(m.metadata_json);
  CHECK(meta["urdf"] == urdf);
  CHECK(meta["options"]["budget"] == 12);
  CHECK(meta["options"]["link"] == nlohmann::json::array({"forearm=5"}));
  CHECK(meta["options"]["outer"] == false);
  CHECK(meta["links"]["forearm"]["parts"][0]["sha256"].get<std::string>().size() == 64);
  CHECK(meta["links"]["forearm"]["budget"] == 5);
}

TEST_CASE("robot: --from-visual bakes a link's visual geometry where it has no collision",
          "[cli][robot]") {
  TempDir dir;
  const std::string urdf = dir.write("v.urdf", R"(<robot name="v">
  <link name="c"><collision><geometry><box size="0.1 0.2 0.3"/></geometry></collision></link>
  <link name="v"><visual><geometry><capsule radius="0.05" length="0.2"/></geometry></visual></link>
  <joint name="j" type="continuous"><parent link="c"/><child link="v"/><axis xyz="0 1 0"/></joint>
</robot>)");
  for (const bool visual : {false, true}) {
    INFO(visual);
    const std::string out = dir.file(visual ? "with" : "without");
    const CommandResult r =
        cli("robot " + shell_quote(urdf) + " -o " + shell_quote(out) +
            " --spheres-per-link 4 --no-outer --format robot" + (visual ? " --from-visual" : ""));
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const medspheres::RobotModel m = medspheres::load_robot(out + "/v.robot.json");
    const medspheres::Link* v = m.find_link("v");
    REQUIRE(v != nullptr);
    CHECK(v->spheres.inner.empty() == !visual);
    CHECK_THAT(r.out, Contains(visual ? "visual geometry" : "no collision geometry"));
    // cuRobo's URDF parser needs a <limit> on a continuous joint: said by name.
    CHECK_THAT(r.err, Contains("continuous joint 'j' has no <limit>"));
    // The capsule's inner spheres lie inside it: within r of its axis segment.
    for (const medspheres::Sphere& s : v->spheres.inner.spheres) {
      const double z = std::clamp(s.center.z(), -0.1, 0.1);
      CHECK((s.center - Eigen::Vector3d(0, 0, z)).norm() + s.radius <= 0.05 * (1 + 1e-12));
    }
  }
  // With the limit, no warning.
  std::string text = medspheres::test::read_file(urdf);
  const std::string axis = R"(<axis xyz="0 1 0"/>)";
  text.replace(text.find(axis), axis.size(), axis + R"(<limit effort="1" velocity="1"/>)");
  const std::string limited = dir.write("limited.urdf", text);
  const CommandResult r =
      cli("robot " + shell_quote(limited) + " -o " + shell_quote(dir.file("limited")) +
          " --spheres-per-link 4 --no-outer --format robot");
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.err, !Contains("no <limit>"));
  CHECK_THAT(r.err, !Contains("joint 'j'"));
  // A velocity limit of 0 (as URDF generators write it): cuRobo v2 refuses the empty range
  // [-0, 0]. Said by name, with the value.
  const std::string limit = R"(<limit effort="1" velocity="1"/>)";
  text.replace(text.find(limit), limit.size(), R"(<limit effort="1" velocity="0"/>)");
  const CommandResult zero =
      cli("robot " + shell_quote(dir.write("zero.urdf", text)) + " -o " +
          shell_quote(dir.file("zero")) + " --spheres-per-link 4 --no-outer --format robot");
  REQUIRE(zero.exit_code == 0);
  CHECK_THAT(zero.err, Contains("joint 'j' has velocity 0 in its <limit>"));
  CHECK_THAT(zero.err, !Contains("no <limit>"));
  CHECK_THAT(zero.err, !Contains("no link has collision geometry"));
  // A robot with visual geometry alone: its files would carry no sphere, and the warning
  // names the option that bakes the visual geometry.
  const std::string bare = dir.write("bare.urdf", R"(<robot name="bare">
  <link name="v"><visual><geometry><box size="0.1 0.2 0.3"/></geometry></visual></link>
</robot>)");
  for (const bool visual : {false, true}) {
    const CommandResult b =
        cli("robot " + shell_quote(bare) + " -o " + shell_quote(dir.file(visual ? "bv" : "b")) +
            " --spheres-per-link 4 --no-outer --format robot" + (visual ? " --from-visual" : ""));
    REQUIRE(b.exit_code == 0);
    if (visual)
      CHECK_THAT(b.err, !Contains("no link has collision geometry"));
    else
      CHECK_THAT(b.err, Contains("no link has collision geometry, so the files carry no sphere; "
                                 "--from-visual"));
  }
  // The batch of both says it of the first only, by its path.
  const CommandResult batch =
      cli("robot " + shell_quote(urdf) + " " + shell_quote(limited) + " -o " +
          shell_quote(dir.file("batch")) + " --spheres-per-link 4 --no-outer --format robot");
  REQUIRE(batch.exit_code == 0);
  CHECK_THAT(batch.err, Contains(urdf + ": continuous joint 'j' has no <limit>"));
  CHECK_THAT(batch.err, !Contains(limited + ": continuous"));
  // And a batch of the bare robot and the limited one says the bare one has no geometry.
  const CommandResult bare_batch =
      cli("robot " + shell_quote(bare) + " " + shell_quote(limited) + " -o " +
          shell_quote(dir.file("bare_batch")) + " --spheres-per-link 4 --no-outer --format robot");
  REQUIRE(bare_batch.exit_code == 0);
  CHECK_THAT(bare_batch.err, Contains(bare + ": no link has collision geometry"));
  CHECK_THAT(bare_batch.err, !Contains(limited + ": no link"));
}

TEST_CASE("robot: --target-error and --dilate apply to every link", "[cli][robot]") {
  TempDir dir;
  const std::string urdf = medspheres::test::write_arm(dir);
  const std::string pkg =
      " --package " + shell_quote("arm_pkg=" + (dir.path() / "pkg/arm_pkg").string());
  auto run = [&](const std::string& name, const std::string& flags) {
    const std::string out = dir.file(name);
    const CommandResult r = cli("robot " + shell_quote(urdf) + " -o " + shell_quote(out) + pkg +
                                " --no-outer --format robot -q" + flags);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    return medspheres::load_robot(out + "/arm.robot.json");
  };
  // A target error without a budget: each meshed link baked to it (nerr is exact here: the
  // inner spheres are inside, so it is the true error).
  const medspheres::RobotModel t = run("target", " --target-error 0.3");
  const auto meta = nlohmann::json::parse(t.metadata_json);
  CHECK(meta["options"]["target_error"] == 0.3);
  for (const char* link : {"forearm", "hand"}) {
    INFO(link);
    CHECK(meta["links"][link]["nerr_kind"] == "exact");
    CHECK(meta["links"][link]["nerr"].get<double>() <= 0.3);
  }
  // Dilation grows the spheres of every baked link toward the surface.
  const medspheres::RobotModel plain = run("plain", " --spheres-per-link 6");
  const medspheres::RobotModel dilated = run("dilated", " --spheres-per-link 6 --dilate");
  CHECK(nlohmann::json::parse(dilated.metadata_json)["options"]["dilate"] == true);
  for (const char* link : {"forearm", "hand"}) {
    INFO(link);
    double r_plain = 0, r_dilated = 0;
    for (const auto& s : plain.find_link(link)->spheres.inner.spheres) r_plain += s.radius;
    for (const auto& s : dilated.find_link(link)->spheres.inner.spheres) r_dilated += s.radius;
    CHECK(r_dilated > r_plain);
  }
}

TEST_CASE("robot --cover-start: a planner's own spheres become certified covers, link by link",
          "[cli][robot]") {
  TempDir dir;
  const std::string urdf = medspheres::test::write_arm(dir);
  // The start: the inner sets in cuRobo's format, link frames; they miss the surface.
  REQUIRE(cli("robot " + arm_args(dir, urdf, dir.file("inner")) + " --no-outer --link forearm=5 -q")
              .exit_code == 0);
  const std::string start = dir.file("inner/arm.curobo.yml");
  const CommandResult r =
      cli("robot " + arm_args(dir, urdf, dir.file("out")) + " --cover-start " + shell_quote(start));
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("covering set of") && Contains("from 5 given"));
  // Every link with meshed parts is certified covered in the planner file, by eval.
  const auto j =
      eval_arm(dir, urdf, "out/arm.curobo.yml", " --samples 2000 --surface-samples 20000");
  for (int i = 0; i < 3; ++i) {
    INFO(j["links"][i]["link"]);
    CHECK(j["links"][i]["surface_certificate"]["certified"] == true);
    CHECK(j["links"][i]["uncovered_max"].get<double>() == 0.0);
  }
  const auto meta =
      nlohmann::json::parse(medspheres::load_robot(dir.file("out/arm.robot.json")).metadata_json);
  CHECK(meta["links"]["forearm"]["outer_start_spheres"] == 5);
  CHECK(meta["links"]["forearm"]["outer_spheres"].get<int>() <= 5);
  CHECK(meta["options"]["cover_start"] == start);
  // Bad uses exit 2 and write nothing: with --no-outer, and a one-set file.
  medspheres::SphereSet lone;
  lone.spheres = {{Eigen::Vector3d::Zero(), 0.01}};
  const std::string one = dir.write("one.json", medspheres::sphere_set_to_json(lone));
  for (const std::string& bad :
       std::vector<std::string>{" --cover-start " + shell_quote(start) + " --no-outer",
                                " --cover-start " + shell_quote(one)}) {
    const std::string out = dir.file("bad");
    const CommandResult b = cli("robot " + arm_args(dir, urdf, out) + bad);
    CHECK(b.exit_code == 2);
    CHECK_THAT(b.err, Contains("--cover-start"));
    CHECK_FALSE(fs::exists(out));
  }
  // The folder that holds the start file is no output: replacing it would remove the file.
  const std::string before = medspheres::read_text_file(start);
  const CommandResult held = cli("robot " + arm_args(dir, urdf, dir.file("inner")) +
                                 " --cover-start " + shell_quote(start));
  CHECK(held.exit_code == 2);
  CHECK_THAT(held.err, Contains("holds the input " + start));
  CHECK(medspheres::read_text_file(start) == before);
}

TEST_CASE("robot: tool frames, the matrix and the default configuration in every planner file",
          "[cli][robot]") {
  TempDir dir;
  const std::string urdf = dir.write("arm.urdf", medspheres::test::generated_arm_urdf(7, 4));
  const std::string out = dir.file("out");
  // 3 spheres a link in the sanitizer builds, where the covers' bakes took most of the time;
  // no check here depends on the budget.
  const std::string per_link = medspheres::test::kSanitizerBuild ? "3" : "6";
  const CommandResult r = cli(
      "robot " + shell_quote(urdf) + " -o " + shell_quote(out) + " --spheres-per-link " + per_link +
      " --no-measure --self-collision-samples 300 --self-collision-estimate 200 --tool-frame "
      "link4 --tool-frame hand");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  // The summary names the choices.
  CHECK_THAT(r.out, Contains("tool frames: link4, hand (as given)"));
  CHECK_THAT(r.out, Contains("default configuration: "));
  CHECK_THAT(r.out, Contains("self-collision matrix: 300 samples"));
  CHECK_THAT(r.out, Contains("self-collision estimate: of 200 other random configurations (seed "
                             "7920), "));
  CHECK_THAT(r.out, Contains(", and 0 have a checked pair's meshes touching while no checked "
                             "pair's spheres do"));
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(out)) files.insert(e.path().filename().string());
  for (const char* f : {"generated_arm_7.curobo.yml", "generated_arm_7.curobo_v1.yml",
                        "generated_arm_7.curobo_spheres.yml", "generated_arm_7.xrdf",
                        "generated_arm_7.srdf", "generated_arm_7.self_collision.txt"})
    CHECK(files.count(f) == 1);
  // The robot file keeps the setup, and convert writes it again: the cuRobo file converted
  // from the robot file is the one the robot command wrote.
  const medspheres::RobotModel m = medspheres::load_robot(out + "/generated_arm_7.robot.json");
  REQUIRE(m.planner);
  CHECK(m.planner->tool_frames == std::vector<std::string>{"link4", "hand"});
  REQUIRE(m.planner->self_collision);
  CHECK(m.planner->self_collision->samples == 300);
  const CommandResult c = cli("convert " + shell_quote(out + "/generated_arm_7.robot.json") + " " +
                              shell_quote(dir.file("again.xrdf")));
  REQUIRE(c.exit_code == 0);
  CHECK(medspheres::read_text_file(dir.file("again.xrdf")) ==
        medspheres::read_text_file(out + "/generated_arm_7.xrdf"));
  const std::string report =
      medspheres::read_text_file(out + "/generated_arm_7.self_collision.txt");
  CHECK_THAT(report, Contains("300 samples (seed 1)"));
  CHECK_THAT(report, Contains("adjacent"));
  // The sphere pairs that the summary and the report count are those a loader builds from
  // the written cuRobo file.
  const std::size_t pairs = curobo_sphere_pairs(out + "/generated_arm_7.curobo.yml");
  CHECK(pairs > 0);
  CHECK_THAT(r.out, Contains("; cuRobo checks " + std::to_string(pairs) + " sphere pairs\n"));
  CHECK_THAT(report, Contains("sphere pairs cuRobo checks: " + std::to_string(pairs) + " ("));

  // --free-joint: the gripper's two finger joints are locked by default; one given stays free.
  const std::string freed = dir.file("freed");
  const CommandResult f =
      cli("robot " + shell_quote(urdf) + " -o " + shell_quote(freed) +
          " --spheres-per-link 6 --no-measure --no-outer --no-self-collision --format robot,curobo "
          "--free-joint left_finger_joint");
  INFO(f.err);
  REQUIRE(f.exit_code == 0);
  CHECK_THAT(f.out, Contains("locked joints (the gripper's): right_finger_joint\n"
                             "free finger joints (--free-joint): left_finger_joint\n"));
  const YAML::Node yml = YAML::LoadFile(freed + "/generated_arm_7.curobo.yml");
  const YAML::Node locks = yml["robot_cfg"]["kinematics"]["lock_joints"];
  REQUIRE(locks.IsMap());
  CHECK(locks.size() == 1);
  CHECK(locks["right_finger_joint"]);
  CHECK_FALSE(locks["left_finger_joint"]);
  const medspheres::RobotModel freed_model =
      medspheres::load_robot(freed + "/generated_arm_7.robot.json");
  REQUIRE(freed_model.planner);
  CHECK(freed_model.planner->locked_joints == std::vector<std::string>{"right_finger_joint"});
}
