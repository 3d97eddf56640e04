#pragma once
// Small robots written by tests: a URDF and its mesh files in a temporary folder.

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "medspheres/mesh/mesh_generators.h"
#include "support/mesh_writers.h"
#include "support/temp_dir.h"

namespace medspheres::test {

/// URDF's rpy: fixed axes x, y, z, i.e. R = Rz(yaw) Ry(pitch) Rx(roll), written out.
inline Eigen::Matrix3d rpy_matrix(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll), sr = std::sin(roll);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  Eigen::Matrix3d r;
  r << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return r;
}

/// The mesh of the arm's forearm: a capsule along z, 0.1 long, radius 0.03, in the file's
/// units (the URDF scales it).
inline TriangleMesh forearm_mesh() {
  return make_capsule(0.03, 0.05, 24, 6);
}

/// Writes, into \p dir, meshes/forearm.obj, pkg/arm_pkg/meshes/hand.obj (package
/// arm_pkg) and arm.urdf: a two-link arm and more:
/// - base: a box 0.2 x 0.1 x 0.05 and a cylinder (two collision elements);
/// - forearm: forearm.obj scaled (2, 0.5, 1.5) at xyz (0.1, -0.05, 0.2), rpy (0.3, -0.4,
///   0.9), child of base by revolute joint j1 (axis 0 0 1, limits);
/// - hand: package://arm_pkg/meshes/hand.obj and a sphere primitive, child of forearm by
///   prismatic j2 (mimic of j1);
/// - tool: no geometry (fixed joint j3 from hand).
/// Returns the URDF's path.
inline std::string write_arm(const TempDir& dir) {
  std::filesystem::create_directories(dir.path() / "meshes");
  std::filesystem::create_directories(dir.path() / "pkg/arm_pkg/meshes");
  dir.write("meshes/forearm.obj", to_obj(forearm_mesh()));
  dir.write("pkg/arm_pkg/package.xml", "<package><name>arm_pkg</name></package>\n");
  dir.write("pkg/arm_pkg/meshes/hand.obj", to_obj(make_box({0.02, 0.03, 0.04}, 2)));
  return dir.write("arm.urdf", R"(<?xml version="1.0"?>
<robot name="arm">
  <link name="base">
    <collision><geometry><box size="0.2 0.1 0.05"/></geometry></collision>
    <collision>
      <origin xyz="0 0 0.05" rpy="0 1.5707963267948966 0"/>
      <geometry><cylinder radius="0.03" length="0.12"/></geometry>
    </collision>
  </link>
  <link name="forearm">
    <collision>
      <origin xyz="0.1 -0.05 0.2" rpy="0.3 -0.4 0.9"/>
      <geometry><mesh filename="meshes/forearm.obj" scale="2 0.5 1.5"/></geometry>
    </collision>
  </link>
  <link name="hand">
    <collision><geometry><mesh filename="package://arm_pkg/meshes/hand.obj"/></geometry></collision>
    <collision>
      <origin xyz="0 0 0.06"/>
      <geometry><sphere radius="0.015"/></geometry>
    </collision>
  </link>
  <link name="tool"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="forearm"/>
    <origin xyz="0 0 0.1" rpy="0 0 0.5"/>
    <axis xyz="0 0 2"/>
    <limit lower="-1.5" upper="1.5" velocity="2" effort="10"/>
  </joint>
  <joint name="j2" type="prismatic">
    <parent link="forearm"/><child link="hand"/>
    <origin xyz="0 0 0.3"/>
    <axis xyz="1 0 0"/>
    <limit lower="0" upper="0.1" velocity="1" effort="5"/>
    <mimic joint="j1" multiplier="0.5" offset="0.01"/>
  </joint>
  <joint name="j3" type="fixed">
    <parent link="hand"/><child link="tool"/>
  </joint>
</robot>
)");
}

}  // namespace medspheres::test
