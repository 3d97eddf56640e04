// Reading robots: urdfdom's model in the file's order, link geometry in link frames
// (checked against the transform written out by hand), package resolution, bad input.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"
#include "support/urdf_fixtures.h"

using namespace medspheres;
using Catch::Matchers::Contains;
using medspheres::test::TempDir;

namespace {

// A URDF with the given body inside <robot name="r">.
std::string urdf(const std::string& body) {
  return "<?xml version=\"1.0\"?>\n<robot name=\"r\">\n" + body + "\n</robot>\n";
}

// The message of the InputError that reading \p text throws ("" when none).
std::string read_error(const TempDir& dir, const std::string& text,
                       const UrdfReadOptions& options = {}) {
  const std::string path = dir.write("bad.urdf", text);
  try {
    const UrdfRobot robot = read_urdf(path, options);
    load_link_solids(robot);
  } catch (const InputError& e) {
    CHECK(e.source() == path);
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("read_urdf: links and joints in the file's order, with every field", "[robot]") {
  TempDir dir;
  const std::string path = test::write_arm(dir);
  UrdfReadOptions options;
  options.packages.explicit_dirs["arm_pkg"] = (dir.path() / "pkg/arm_pkg").string();
  const UrdfRobot robot = read_urdf(path, options);
  REQUIRE(robot.model.links.size() == 4);
  CHECK(robot.model.name == "arm");
  CHECK(robot.model.root_link == "base");
  const char* names[] = {"base", "forearm", "hand", "tool"};
  for (int i = 0; i < 4; ++i) CHECK(robot.model.links[i].name == names[i]);
  REQUIRE(robot.model.joints.size() == 3);
  const Joint& j1 = robot.model.joints[0];
  CHECK(j1.name == "j1");
  CHECK(j1.type == JointType::kRevolute);
  CHECK(j1.parent == "base");
  CHECK(j1.child == "forearm");
  CHECK((j1.axis - Eigen::Vector3d::UnitZ()).norm() < 1e-15);  // normalised from 0 0 2
  CHECK((j1.origin.translation() - Eigen::Vector3d(0, 0, 0.1)).norm() < 1e-15);
  CHECK((j1.origin.linear() - test::rpy_matrix(0, 0, 0.5)).norm() < 1e-14);
  REQUIRE(j1.limits);
  CHECK(j1.limits->lower == -1.5);
  CHECK(j1.limits->upper == 1.5);
  CHECK(j1.limits->velocity == 2);
  CHECK(j1.limits->effort == 10);
  const Joint& j2 = robot.model.joints[1];
  CHECK(j2.type == JointType::kPrismatic);
  REQUIRE(j2.mimic);
  CHECK(j2.mimic->joint == "j1");
  CHECK(j2.mimic->multiplier == 0.5);
  CHECK(j2.mimic->offset == 0.01);
  CHECK(robot.model.joints[2].type == JointType::kFixed);
}

TEST_CASE("link solids: v of a mesh file lands at T_origin (S v) in the link frame", "[robot]") {
  TempDir dir;
  PackageDirs packages;
  packages.explicit_dirs["arm_pkg"] = (dir.path() / "pkg/arm_pkg").string();
  const UrdfRobot robot = read_urdf(test::write_arm(dir), {packages, false});
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  REQUIRE(solids.size() == 4);

  // forearm: the file's vertices, scaled and moved by hand.
  const LinkSolid& forearm = solids[1];
  REQUIRE(forearm.parts.size() == 1);
  const TriangleMesh placed = forearm.placed_mesh();
  // The file's vertices as the loader reads them (assimp parses them to floats).
  const TriangleMesh file = load_mesh((dir.path() / "meshes/forearm.obj").string()).mesh;
  REQUIRE(placed.num_vertices() == file.num_vertices());
  const Eigen::Matrix3d r = test::rpy_matrix(0.3, -0.4, 0.9);
  const Eigen::Vector3d t(0.1, -0.05, 0.2);
  const Eigen::Vector3d s(2, 0.5, 1.5);
  for (std::size_t i = 0; i < file.num_vertices(); ++i) {
    const Eigen::Vector3d expect = r * file.vertices[i].cwiseProduct(s) + t;
    CHECK((placed.vertices[i] - expect).norm() < 1e-15);
  }
  CHECK(analyze_mesh(placed).is_closed_outward());
  CHECK(forearm.parts[0].source == (dir.path() / "meshes/forearm.obj").string());
  CHECK(forearm.parts[0].sha256.size() == 64);

  // base: a box and a cylinder, two parts; hand: a mesh through package:// and a sphere.
  CHECK(solids[0].parts.size() == 2);
  CHECK(solids[0].triangles() == 12u + 4u * kCylinderSlices);
  CHECK(solids[0].spheres.empty());
  REQUIRE(solids[2].parts.size() == 1);
  REQUIRE(solids[2].spheres.size() == 1);
  CHECK((solids[2].spheres[0].center - Eigen::Vector3d(0, 0, 0.06)).norm() == 0.0);
  CHECK(solids[2].spheres[0].radius == 0.015);
  CHECK(solids[3].empty());
}

TEST_CASE("package:// through ROS_PACKAGE_PATH, and a package nobody knows", "[robot]") {
  TempDir dir;
  const std::string path = test::write_arm(dir);
  const char* saved = std::getenv("ROS_PACKAGE_PATH");
  const std::string old = saved ? saved : "";
  ::setenv("ROS_PACKAGE_PATH", ("/nonexistent:" + (dir.path() / "pkg").string()).c_str(), 1);
  const UrdfRobot robot = read_urdf(path);
  CHECK(robot.links[2].parts[0].path == (dir.path() / "pkg/arm_pkg/meshes/hand.obj").string());
  // A package folder found deeper down by its package.xml.
  ::setenv("ROS_PACKAGE_PATH", dir.path().string().c_str(), 1);
  CHECK(read_urdf(path).links[2].parts[0].path == robot.links[2].parts[0].path);
  ::setenv("ROS_PACKAGE_PATH", "/nonexistent", 1);
  try {
    read_urdf(path);
    FAIL("an unknown package must be an error");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(),
               Contains(path) && Contains("link 'hand'") && Contains("unknown package 'arm_pkg'"));
  }
  if (saved)
    ::setenv("ROS_PACKAGE_PATH", old.c_str(), 1);
  else
    ::unsetenv("ROS_PACKAGE_PATH");
}

TEST_CASE("mesh names: file://, absolute paths, other schemes", "[robot]") {
  PackageDirs none;
  none.use_ros_package_path = false;
  CHECK(resolve_mesh_path("file:///a/b.stl", "/u", none) == "/a/b.stl");
  CHECK(resolve_mesh_path("file://m/b.stl", "/u", none) == "/u/m/b.stl");
  CHECK(resolve_mesh_path("/a/./b.stl", "/u", none) == "/a/b.stl");
  CHECK(resolve_mesh_path("../m/b.stl", "/u/v", none) == "/u/m/b.stl");
  none.explicit_dirs["p"] = "/pk";
  CHECK(resolve_mesh_path("package://p/m/b.stl", "/u", none) == "/pk/m/b.stl");
  CHECK_THROWS_AS(resolve_mesh_path("http://x/b.stl", "/u", none), InputError);
  CHECK_THROWS_AS(resolve_mesh_path("package:///b.stl", "/u", none), InputError);
  CHECK_THROWS_AS(resolve_mesh_path("package://q/b.stl", "/u", none), InputError);
  PackageDirs dirs;
  add_package_dir(dirs, "a=/x=y");
  CHECK(dirs.explicit_dirs.at("a") == "/x=y");
  CHECK_THROWS_AS(add_package_dir(dirs, "=x"), InputError);
  CHECK_THROWS_AS(add_package_dir(dirs, "a="), InputError);
}

TEST_CASE("mesh names from a description's root: the nearest ancestor folder that has the file",
          "[robot]") {
  // cuRobo's own descriptions name meshes from the description's root (its
  // asset_root_path), with the URDF in a urdf/ folder below it.
  TempDir dir;
  std::filesystem::create_directories(dir.path() / "desc" / "urdf");
  std::filesystem::create_directories(dir.path() / "desc" / "meshes");
  const std::string mesh =
      dir.write("desc/meshes/c.obj", test::to_obj(make_box({0.1, 0.2, 0.3}, 1)));
  const std::string desc_urdf = (dir.path() / "desc" / "urdf").string();
  PackageDirs none;
  none.use_ros_package_path = false;
  CHECK(resolve_mesh_path("meshes/c.obj", desc_urdf, none) == mesh);
  CHECK(resolve_mesh_path("file://meshes/c.obj", desc_urdf, none) == mesh);
  // No file anywhere up the tree: the path from the URDF's folder, for the loader's error.
  CHECK(resolve_mesh_path("meshes/d.obj", desc_urdf, none) == desc_urdf + "/meshes/d.obj");
  const UrdfRobot robot = read_urdf(dir.write("desc/urdf/r.urdf", urdf(R"(<link name="l">
        <collision><geometry><mesh filename="meshes/c.obj"/></geometry></collision></link>)")));
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  CHECK(analyze_mesh(solids[0].placed_mesh()).signed_volume ==
        Approx(0.2 * 0.4 * 0.6).epsilon(1e-6));
  // A file beside the URDF comes first.
  std::filesystem::create_directories(dir.path() / "desc" / "urdf" / "meshes");
  const std::string beside =
      dir.write("desc/urdf/meshes/c.obj", test::to_obj(make_box({0.1, 0.1, 0.1}, 1)));
  CHECK(resolve_mesh_path("meshes/c.obj", desc_urdf, none) == beside);
}

TEST_CASE("a mirroring scale keeps the solid wound outward", "[robot]") {
  TempDir dir;
  dir.write("c.obj", test::to_obj(make_box({0.1, 0.2, 0.3}, 1)));
  const UrdfRobot robot = read_urdf(dir.write("m.urdf", urdf(R"(<link name="l"><collision><geometry>
        <mesh filename="c.obj" scale="-1 1 2"/></geometry></collision></link>)")));
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  const MeshReport report = analyze_mesh(solids[0].placed_mesh());
  CHECK(report.is_closed_outward());
  CHECK(report.signed_volume == Approx(0.2 * 0.4 * 0.6 * 2).epsilon(1e-6));
}

TEST_CASE("from_visual: visual geometry where a link has no collision geometry", "[robot]") {
  TempDir dir;
  const std::string text = urdf(R"(<link name="v">
      <visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>
    <link name="c">
      <visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual>
      <collision><geometry><sphere radius="0.1"/></geometry></collision></link>
    <joint name="j" type="fixed"><parent link="v"/><child link="c"/></joint>)");
  const std::string path = dir.write("v.urdf", text);
  const UrdfRobot plain = read_urdf(path);
  CHECK(plain.links[0].parts.empty());
  UrdfReadOptions options;
  options.from_visual = true;
  const UrdfRobot visual = read_urdf(path, options);
  REQUIRE(visual.links[0].parts.size() == 1);
  CHECK(visual.links[0].from_visual);
  CHECK(visual.links[0].parts[0].shape == PartShape::kBox);
  REQUIRE(visual.links[1].parts.size() == 1);  // its collision sphere, not the visual box
  CHECK(visual.links[1].parts[0].shape == PartShape::kSphere);
  CHECK_FALSE(visual.links[1].from_visual);
}

TEST_CASE("a link name with XML special characters is read, not an error", "[robot]") {
  TempDir dir;
  const UrdfRobot robot = read_urdf(
      dir.write("s.urdf", urdf(R"(<link name="a&amp;b&lt;c&gt;&quot;d&apos;"><collision><geometry>
        <box size="0.1 0.1 0.1"/></geometry></collision></link>)")));
  REQUIRE(robot.model.links.size() == 1);
  CHECK(robot.model.links[0].name == "a&b<c>\"d'");
}

TEST_CASE("bad robots: each names the URDF, the link and the problem", "[robot]") {
  TempDir dir;
  const std::string box =
      R"(<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>)";
  CHECK_THAT(read_error(dir, "<robot name=\"r\"><link name=\"a\">"), Contains("not well-formed"));
  CHECK_THAT(read_error(dir, urdf(R"(<link name="a"/><link name="b"/><link name="c"/>
      <joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>
      <joint name="j2" type="fixed"><parent link="b"/><child link="c"/></joint>
      <joint name="j3" type="fixed"><parent link="c"/><child link="b"/></joint>)")),
             Contains("link 'b' is the child of two joints ('j1' and 'j3')"));
  CHECK_THAT(read_error(dir, urdf(R"(<link name="b"/><link name="c"/>
      <joint name="j2" type="fixed"><parent link="b"/><child link="c"/></joint>
      <joint name="j3" type="fixed"><parent link="c"/><child link="b"/></joint>)")),
             Contains("joint cycle") && Contains("'b'") && Contains("'c'"));
  CHECK_THAT(read_error(dir, urdf(R"(<link name="a"><collision><geometry>
      <cone radius="0.1" length="0.2"/></geometry></collision></link>)")),
             Contains("cone") && Contains("[a]"));
  CHECK_THAT(read_error(dir, urdf(R"(<link name="a">)" + box + R"(<collision><geometry>
      <capsule radius="0.1"/></geometry></collision></link>)")),
             Contains("link 'a'") && Contains("capsule") && Contains("length"));
  CHECK_THAT(read_error(dir, urdf(R"(<link name="a"><collision><geometry>
      <capsule radius="0" length="0.2"/></geometry></collision></link>)")),
             Contains("link 'a'") && Contains("radius > 0"));
  CHECK_THAT(read_error(dir, urdf(R"(<link name="a"><collision><geometry>
      <mesh filename="missing.stl"/></geometry></collision></link>)")),
             Contains("link 'a'") && Contains("missing.stl"));
  CHECK_THAT(read_error(dir, urdf(R"(<link name="a"><collision><geometry>
      <box size="0 0.1 0.1"/></geometry></collision></link>)")),
             Contains("link 'a'") && Contains("empty primitive"));
  // Zero in every size: a placeholder (Kinova's root link), read as no geometry.
  {
    const std::string body = R"(<link name="a">
      <collision><geometry><box size="0 0 0"/></geometry></collision>
      <collision><geometry><sphere radius="0"/></geometry></collision></link>
      <joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>
      <link name="b">)" + box +
                             "</link>";
    const std::string path = dir.write("placeholder.urdf", urdf(body));
    const UrdfRobot robot = read_urdf(path);
    REQUIRE(robot.links.size() == 2);
    CHECK(robot.links[0].parts.empty());
    CHECK(robot.links[1].parts.size() == 1);
  }
  // A fixed joint's <mimic> means nothing (it never moves): dropped, like its <axis>.
  {
    const std::string body = R"(<link name="a">)" + box + R"(</link><link name="b"/><link name="c"/>
      <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="j2" type="fixed"><parent link="a"/><child link="c"/><axis xyz="0 1 0"/>
        <mimic joint="j1"/></joint>)";
    const UrdfRobot robot = read_urdf(dir.write("fixed_mimic.urdf", urdf(body)));
    REQUIRE(robot.model.joints.size() == 2);
    CHECK(robot.model.joints[1].type == JointType::kFixed);
    CHECK_FALSE(robot.model.joints[1].mimic);
  }
  CHECK_THAT(read_error(dir, urdf(R"(<link name="b"/><link name="c"/>
      <joint name="j1" type="prismatic"><parent link="b"/><child link="c"/><axis xyz="1 0 0"/>
        <limit lower="0" upper="1" effort="1" velocity="1"/><mimic joint="nowhere"/></joint>)")),
             Contains("joint \"j1\"") && Contains("nowhere") && Contains("does not exist"));
  CHECK_THAT(read_error(dir, urdf(R"(<link name="a"><collision><geometry>
      <mesh filename="x.stl" scale="1 0 1"/></geometry></collision></link>)")),
             Contains("link 'a'") && Contains("scale"));
  CHECK_THAT(read_error(dir, urdf("<link name=\"\">" + box + "</link>")), Contains("empty name"));
  dir.write("empty.obj", "# no faces\nv 0 0 0\n");
  CHECK_THAT(read_error(dir, urdf(R"(<link name="e"><collision><geometry>
      <mesh filename="empty.obj"/></geometry></collision></link>)")),
             Contains("link 'e'"));
}

TEST_CASE("a <capsule>, which urdfdom 3 does not know, is read and meshed inside it", "[robot]") {
  TempDir dir;
  // Second of three collision elements, with a rotated origin; a visual capsule too.
  const std::string path = dir.write("c.urdf", urdf(R"(<link name="c">
    <visual><geometry><capsule radius="0.5" length="9"/></geometry></visual>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
    <collision><origin xyz="1 2 3" rpy="0 1.5707963267948966 0"/>
      <geometry><capsule radius="0.05" length="0.3"/></geometry></collision>
    <collision><geometry><sphere radius="0.02"/></geometry></collision></link>
    <link name="v"><visual><origin xyz="0 0 0.5"/>
      <geometry><capsule radius="0.1" length="0.4"/></geometry></visual></link>
    <joint name="j" type="fixed"><parent link="c"/><child link="v"/></joint>)"));
  UrdfReadOptions options;
  options.from_visual = true;
  const UrdfRobot robot = read_urdf(path, options);
  REQUIRE(robot.links.size() == 2);
  const std::vector<LinkPart>& parts = robot.links[0].parts;
  REQUIRE(parts.size() == 3);
  CHECK(parts[0].shape == PartShape::kBox);
  CHECK(parts[1].shape == PartShape::kCapsule);
  CHECK(parts[1].size == Eigen::Vector3d(0.05, 0.05, 0.3));
  CHECK(parts[2].shape == PartShape::kSphere);
  CHECK(parts[2].size.x() == 0.02);
  REQUIRE(robot.links[1].parts.size() == 1);
  CHECK(robot.links[1].from_visual);
  CHECK(robot.links[1].parts[0].shape == PartShape::kCapsule);
  CHECK(robot.links[1].parts[0].size == Eigen::Vector3d(0.1, 0.1, 0.4));

  // The meshed capsule in the link frame: every vertex within r of the axis segment (its
  // ends at origin * (0, 0, +-l/2), the axis along the link's x after the rotation), and
  // the poles and the equator ring's vertices on the capsule's surface.
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  REQUIRE(solids[0].parts.size() == 2);
  CHECK(solids[0].spheres.size() == 1);
  const LinkSolidPart& capsule = solids[0].parts[1];
  CHECK(capsule.source == "capsule 0.05 0.3");
  const Eigen::Vector3d a = capsule.origin * Eigen::Vector3d(0, 0, -0.15);
  const Eigen::Vector3d b = capsule.origin * Eigen::Vector3d(0, 0, 0.15);
  CHECK((a - Eigen::Vector3d(0.85, 2, 3)).norm() < 1e-12);
  double farthest = 0, nearest = 1;
  for (const Eigen::Vector3d& v : capsule.mesh.vertices) {
    const Eigen::Vector3d w = capsule.origin * v;
    const double t = std::clamp((w - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    const double d = (w - (a + t * (b - a))).norm();
    farthest = std::max(farthest, d);
    nearest = std::min(nearest, d);
  }
  CHECK(farthest < 0.05 * (1 + 1e-12));
  CHECK(nearest > 0.05 * (1 - 1e-12));  // every vertex on the surface
  CHECK(analyze_mesh(capsule.mesh).is_closed_outward());
}

TEST_CASE(
    "quirks of published URDFs are read: XML version 0.0, joint names equal to link "
    "names, limits without bounds",
    "[robot]") {
  // As bullet3's Minitaur has them.
  TempDir dir;
  const std::string path = dir.write("q.urdf", R"(<?xml version="0.0" ?>
<robot name="quadruped">
  <link name="base"><collision><geometry><box size=".34 0.14 .07"/></geometry></collision></link>
  <link name="motor"><collision><geometry><cylinder length="0.026" radius="0.0434"/></geometry>
  </collision></link>
  <link name="leg"><collision><origin rpy="0.0 0 0" xyz="0 0 .1"/>
    <geometry><box size=".01 0.01 .2"/></geometry></collision></link>
  <joint name="motor" type="continuous"><axis xyz="0 0 1"/><parent link="base"/>
    <child link="motor"/><origin rpy="1.57075 0 3.141592" xyz="0.21 0.04 0"/>
    <limit effort="100" velocity="100"/><joint_properties damping="0.0" friction="0.0"/></joint>
  <joint name="leg" type="revolute"><axis xyz="0 1 0"/><parent link="motor"/><child link="leg"/>
    <origin rpy="0 0 0" xyz="0.0 0.01 .055"/><limit effort="100" velocity="100"/></joint>
</robot>)");
  const UrdfRobot robot = read_urdf(path);
  REQUIRE(robot.model.links.size() == 3);
  REQUIRE(robot.model.joints.size() == 2);
  CHECK(robot.model.joints[0].name == "motor");
  CHECK(robot.model.joints[0].child == "motor");
  CHECK(robot.model.joints[0].type == JointType::kContinuous);
  const Joint& knee = robot.model.joints[1];
  CHECK(knee.type == JointType::kRevolute);
  REQUIRE(knee.limits);  // urdfdom's defaults for the missing bounds
  CHECK(knee.limits->lower == 0.0);
  CHECK(knee.limits->upper == 0.0);
  CHECK(knee.limits->velocity == 100.0);
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  for (const LinkSolid& s : solids) CHECK(s.parts.size() == 1);
}

TEST_CASE("a floating or planar joint from a bare root link is left out with it, else refused",
          "[robot]") {
  TempDir dir;
  const std::string box =
      R"(<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>)";
  const std::string arm = R"(<link name="base">)" + box + R"(</link><link name="hand">)" + box +
                          R"(</link>
      <joint name="j" type="revolute"><parent link="base"/><child link="hand"/>
        <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>)";
  for (const std::string type : {"floating", "planar"}) {
    INFO(type);
    const std::string free = R"(<joint name="free" type=")" + type +
                             R"("><parent link="world"/><child link="base"/>)" +
                             (type == "planar" ? R"(<axis xyz="0 0 1"/>)" : "") + "</joint>";
    const UrdfRobot robot =
        read_urdf(dir.write(type + ".urdf", urdf(R"(<link name="world"/>)" + free + arm)));
    CHECK(robot.model.root_link == "base");
    REQUIRE(robot.links.size() == 2);
    REQUIRE(robot.model.links.size() == 2);
    CHECK(robot.links[0].name == "base");
    CHECK(robot.model.links[0].name == "base");
    CHECK(robot.links[1].name == "hand");
    REQUIRE(robot.model.joints.size() == 1);
    CHECK(robot.model.joints[0].name == "j");
    CHECK(robot.free_base.joint == "free");
    CHECK(robot.free_base.type == type);
    CHECK(robot.free_base.link == "world");

    // From a link that is not the root, from a root with geometry, or from a root with
    // another joint: the robot would not be one rigid tree below a fixed base.
    CHECK_THAT(read_error(dir, urdf(arm + R"(<link name="tip"/>
        <joint name="loose" type=")" +
                                    type + R"("><parent link="hand"/><child link="tip"/>
        <axis xyz="0 0 1"/></joint>)")),
               Contains("joint 'loose'") && Contains("its parent 'hand' is not the root 'base'"));
    CHECK_THAT(read_error(dir, urdf(R"(<link name="world">)" + box + "</link>" + free + arm)),
               Contains("joint 'free'") && Contains("the root 'world' carries geometry"));
    CHECK_THAT(
        read_error(dir, urdf(R"(<link name="world"/><link name="table">)" + box + R"(</link>
        <joint name="table_fixed" type="fixed"><parent link="world"/><child link="table"/></joint>)" +
                             free + arm)),
        Contains("joint 'free'") && Contains("the root 'world' has the joint 'table_fixed'"));
  }
  CHECK(read_urdf(dir.write("fixed.urdf", urdf(arm))).free_base.joint.empty());
}
