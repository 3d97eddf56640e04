// The generated coarse arm (coarse_arm.h).

#include "support/coarse_arm.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

#include "medspheres/mesh/mesh_generators.h"
#include "support/mesh_writers.h"

namespace medspheres::test {
namespace {

TriangleMesh moved(TriangleMesh m, const Eigen::Isometry3d& X) {
  for (Eigen::Vector3d& v : m.vertices) v = X * v;
  return m;
}

// A capsule of radius r around the segment from a to b (link frame).
TriangleMesh capsule(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r, int slices,
                     int stacks) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), b - a).matrix();
  X.translation() = (a + b) / 2;
  return moved(make_capsule(r, (b - a).norm() / 2, slices, stacks), X);
}

// A cylinder of radius r and length 2 h along z about the point c (link frame).
TriangleMesh cylinder(const Eigen::Vector3d& c, double r, double h, int slices) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = c;
  return moved(make_cylinder(r, h, slices), X);
}

// The chain: name, parent, type, origin xyz and rpy, axis, limits, mimic.
const char* const kJoints = R"(
  <joint name="joint1" type="revolute">
    <parent link="link0"/><child link="link1"/>
    <origin xyz="0 0 0.333" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2.8973" upper="2.8973" effort="87" velocity="2.175"/>
  </joint>
  <joint name="joint2" type="revolute">
    <parent link="link1"/><child link="link2"/>
    <origin xyz="0 0 0" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-1.7628" upper="1.7628" effort="87" velocity="2.175"/>
  </joint>
  <joint name="joint3" type="revolute">
    <parent link="link2"/><child link="link3"/>
    <origin xyz="0 -0.316 0" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2.8973" upper="2.8973" effort="87" velocity="2.175"/>
  </joint>
  <joint name="joint4" type="revolute">
    <parent link="link3"/><child link="link4"/>
    <origin xyz="0.0825 0 0" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3.0718" upper="-0.0698" effort="87" velocity="2.175"/>
  </joint>
  <joint name="joint5" type="revolute">
    <parent link="link4"/><child link="link5"/>
    <origin xyz="-0.0825 0.384 0" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2.8973" upper="2.8973" effort="12" velocity="2.61"/>
  </joint>
  <joint name="joint6" type="revolute">
    <parent link="link5"/><child link="link6"/>
    <origin xyz="0 0 0" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-0.0175" upper="3.7525" effort="12" velocity="2.61"/>
  </joint>
  <joint name="joint7" type="revolute">
    <parent link="link6"/><child link="link7"/>
    <origin xyz="0.088 0 0" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2.8973" upper="2.8973" effort="12" velocity="2.61"/>
  </joint>
  <joint name="joint8" type="fixed">
    <parent link="link7"/><child link="link8"/>
    <origin xyz="0 0 0.107" rpy="0 0 0"/>
  </joint>
  <joint name="hand_joint" type="fixed">
    <parent link="link8"/><child link="hand"/>
    <origin xyz="0 0 0" rpy="0 0 -0.7853981633974483"/>
  </joint>
  <joint name="finger_joint1" type="prismatic">
    <parent link="hand"/><child link="leftfinger"/>
    <origin xyz="0 0 0.0584" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.04" effort="20" velocity="0.2"/>
  </joint>
  <joint name="finger_joint2" type="prismatic">
    <parent link="hand"/><child link="rightfinger"/>
    <origin xyz="0 0 0.0584" rpy="0 0 0"/><axis xyz="0 -1 0"/>
    <limit lower="0" upper="0.04" effort="20" velocity="0.2"/>
    <mimic joint="finger_joint1"/>
  </joint>
)";

}  // namespace

std::vector<CoarseArmLink> coarse_arm_links() {
  using V = Eigen::Vector3d;
  return {
      {"link0", cylinder(V(-0.04, 0, 0.07), 0.09, 0.07, 24)},
      {"link1", capsule(V(0, 0, -0.19), V(0, 0, -0.02), 0.06, 16, 4)},
      {"link2", capsule(V(0, 0, 0), V(0, -0.2, 0), 0.06, 12, 3)},
      {"link3", capsule(V(0, 0, -0.12), V(0.07, 0, 0), 0.055, 12, 3)},
      {"link4", capsule(V(0, 0, 0), V(-0.06, 0.12, 0), 0.055, 12, 3)},
      {"link5", capsule(V(0, 0.06, -0.24), V(0, 0, -0.03), 0.05, 16, 4)},
      {"link6", capsule(V(0, 0, -0.01), V(0.088, 0, 0), 0.05, 10, 2)},
      {"link7", capsule(V(0, 0, -0.01), V(0, 0, 0.075), 0.045, 12, 2)},
      {"hand", capsule(V(0, -0.075, 0.03), V(0, 0.075, 0.03), 0.035, 12, 4)},
      {"leftfinger", cylinder(V(0, 0.015, 0.025), 0.011, 0.022, 8)},
      {"rightfinger", cylinder(V(0, -0.015, 0.025), 0.011, 0.022, 8)},
  };
}

std::string coarse_arm_urdf() {
  std::ostringstream s;
  s << "<?xml version=\"1.0\"?>\n<robot name=\"coarse_arm\">\n";
  for (const CoarseArmLink& l : coarse_arm_links()) {
    s << "  <link name=\"" << l.name << "\">\n    <collision><geometry><mesh filename=\"meshes/"
      << l.name << ".obj\"/></geometry></collision>\n  </link>\n";
    if (l.name == "link7") s << "  <link name=\"link8\"/>\n";
  }
  s << kJoints << "</robot>\n";
  return s.str();
}

std::string write_coarse_arm(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir / "meshes");
  // Each file is written beside its place and renamed into it, so that a process reading
  // the folder while another writes it (two benchmarks sharing a cache) sees a whole file.
  auto write = [](const std::filesystem::path& p, const std::string& text) {
    const std::filesystem::path tmp = p.string() + ".tmp" + std::to_string(::getpid());
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      out << text;
      if (!out) throw std::runtime_error("write_coarse_arm: cannot write " + tmp.string());
    }
    std::filesystem::rename(tmp, p);
  };
  for (const CoarseArmLink& l : coarse_arm_links())
    write(dir / "meshes" / (l.name + ".obj"), to_obj(l.mesh));
  const std::filesystem::path urdf = dir / "coarse_arm.urdf";
  write(urdf, coarse_arm_urdf());
  return urdf.string();
}

}  // namespace medspheres::test
