#pragma once
// A generated 7-joint arm of coarse meshes, for benchmarks and tests that need a robot whose
// links are a few dozen to a few hundred triangles (as the collision meshes of public arm
// descriptions are), without files from outside the repository.
//
// The kinematics follow a Franka-Panda-like chain (joint origins, axes and limits in metres
// and radians): link0 (base) -joint1..joint7 (revolute, z axes)-> link1..link7 -joint8
// (fixed)-> link8 (no geometry) -hand_joint (fixed, yaw -pi/4)-> hand -finger_joint1
// (prismatic along y, 0 to 0.04 m)-> leftfinger, -finger_joint2 (prismatic along -y, mimic of
// finger_joint1)-> rightfinger. Eleven links carry geometry: one closed, outward-wound mesh
// each (a capsule between two points in the link frame, a cylinder for the base and the
// fingers), 32 to 256 triangles, 1472 in all. The shapes are of the arm's size, not copies
// of any vendor's meshes.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "medspheres/triangle_mesh.h"

namespace medspheres::test {

/// One link of the coarse arm with its collision mesh in the link frame (metres).
struct CoarseArmLink {
  std::string name;
  TriangleMesh mesh;
};

/// The eleven links with geometry, in the chain's order (link0 ... link7, hand, leftfinger,
/// rightfinger); the same meshes on every call.
std::vector<CoarseArmLink> coarse_arm_links();

/// The arm's URDF text; link L's collision mesh is `meshes/L.obj` relative to the URDF.
std::string coarse_arm_urdf();

/// Writes `coarse_arm.urdf` and `meshes/<link>.obj` into \p dir (created when missing;
/// files of the same name are replaced) and returns the URDF's path. The bytes are the
/// same on every call, so caches keyed by the files' contents stay valid.
std::string write_coarse_arm(const std::filesystem::path& dir);

/// The number of links with geometry and of movable joints (mimic included) of the arm.
inline constexpr std::size_t kCoarseArmLinks = 11;
inline constexpr std::size_t kCoarseArmRevoluteJoints = 7;

}  // namespace medspheres::test
