#pragma once
// A robot and a scene for the robot checker's tests, made in code: a 7-joint arm of
// capsule links with a tool on a fixed joint and two fingers (prismatic, one a mimic),
// each link a triangulated capsule whose covering and inner sets are known in closed form:
// - covering: K balls centred on the axis segment [-h, h] of a capsule of radius rho, at
//   spacing s = 2h / (K - 1), of radius sqrt(rho^2 + (s / 2)^2) (1 + 1e-9): every point
//   within rho of the segment is within that of the nearest centre, so the capsule, and
//   the mesh inscribed in it, are covered (certified);
// - inner: the same centres, radius 0.85 rho, inside the inscribed mesh (16 slices and 4
//   stacks per cap keep its inradius above 0.96 rho).
// Header-only.

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/robot_model.h"

namespace medspheres::test {

struct CapsuleLink {
  std::string name;
  double radius = 0.0, half = 0.0;                         // capsule radius and half axis length
  Eigen::Isometry3d X_LC = Eigen::Isometry3d::Identity();  // the capsule (axis z) in L
};

inline Eigen::Isometry3d pose_of(const Eigen::Vector3d& xyz, double roll = 0.0, double pitch = 0.0,
                                 double yaw = 0.0) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = xyz;
  X.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return X;
}

/// The arm's links with geometry.
inline std::vector<CapsuleLink> capsule_arm_links() {
  std::vector<CapsuleLink> out;
  const double lengths[] = {0.2, 0.25, 0.22, 0.2, 0.18, 0.15, 0.1, 0.08};
  const double radii[] = {0.07, 0.05, 0.045, 0.045, 0.04, 0.035, 0.035, 0.03};
  for (int i = 0; i < 8; ++i)
    out.push_back(
        {"l" + std::to_string(i), radii[i], lengths[i] / 2, pose_of({0, 0, lengths[i] / 2})});
  out.push_back({"tool", 0.025, 0.06, pose_of({0, 0, 0.02}, M_PI / 2)});
  out.push_back({"finger_a", 0.01, 0.02, pose_of({0, 0, 0.03})});
  out.push_back({"finger_b", 0.01, 0.02, pose_of({0, 0, 0.03})});
  return out;
}

/// The capsule's mesh in its link's frame.
inline TriangleMesh capsule_link_mesh(const CapsuleLink& l) {
  TriangleMesh m = make_capsule(l.radius, l.half, 16, 4);
  for (Eigen::Vector3d& v : m.vertices) v = l.X_LC * v;
  return m;
}

/// The covering (radius factor 0) or inner set of K >= 2 balls, in the link frame.
inline SphereSet capsule_set(const CapsuleLink& l, int k, bool cover) {
  SphereSet s;
  const double step = 2 * l.half / (k - 1);
  const double r =
      cover ? std::sqrt(l.radius * l.radius + step * step / 4) * (1 + 1e-9) : 0.85 * l.radius;
  for (int i = 0; i < k; ++i)
    s.spheres.push_back({l.X_LC * Eigen::Vector3d(0, 0, -l.half + i * step), r});
  return s;
}

/// The arm with K covering and K inner balls per link.
inline RobotModel capsule_arm(int k) {
  RobotModel m;
  m.name = "capsule_arm";
  m.root_link = "l0";
  for (const CapsuleLink& l : capsule_arm_links()) {
    Link link;
    link.name = l.name;
    link.spheres.outer = capsule_set(l, k, true);
    link.spheres.inner = capsule_set(l, k, false);
    link.spheres.outer_certificate_json = R"({"certified": true, "method": "closed form"})";
    m.links.push_back(link);
  }
  m.links.push_back({"flange", {}, "no collision geometry"});
  const double lengths[] = {0.2, 0.25, 0.22, 0.2, 0.18, 0.15, 0.1, 0.08};
  for (int i = 1; i < 8; ++i) {
    Joint j;
    j.name = "j" + std::to_string(i);
    j.type = JointType::kRevolute;
    j.parent = "l" + std::to_string(i - 1);
    j.child = "l" + std::to_string(i);
    j.origin = pose_of({0, 0, lengths[i - 1]}, i % 2 ? M_PI / 2 : -M_PI / 2, 0.0, 0.3 * i);
    j.axis = i % 3 == 0 ? Eigen::Vector3d(0, 1, 0) : Eigen::Vector3d(0, 0, 1);
    j.limits = JointLimits{-2.8, 2.8, 2.0, 10.0};
    m.joints.push_back(j);
  }
  Joint flange{"flange_fix",          JointType::kFixed, "l7", "flange",
               pose_of({0, 0, 0.08}), {1, 0, 0},         {},   {}};
  Joint tool{"tool_fix",
             JointType::kFixed,
             "flange",
             "tool",
             pose_of({0, 0, 0.01}, 0, 0, 0.4),
             {1, 0, 0},
             {},
             {}};
  Joint fa{"slide_a",
           JointType::kPrismatic,
           "tool",
           "finger_a",
           pose_of({0, 0.03, 0.04}),
           {0, 1, 0},
           JointLimits{0.0, 0.04, 1.0, 10.0},
           {}};
  Joint fb{"slide_b",
           JointType::kPrismatic,
           "tool",
           "finger_b",
           pose_of({0, -0.03, 0.04}),
           {0, -1, 0},
           JointLimits{0.0, 0.04, 1.0, 10.0},
           JointMimic{"slide_a", 1.0, 0.0}};
  for (const Joint& j : {flange, tool, fa, fb}) m.joints.push_back(j);
  return m;
}

/// n configurations of the arm (7 revolute joints, then the finger), seeded, within the
/// limits.
inline std::vector<double> capsule_arm_configs(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(-2.8, 2.8), slide(0.0, 0.04);
  std::vector<double> q;
  for (std::size_t i = 0; i < n; ++i) {
    for (int j = 0; j < 7; ++j) q.push_back(angle(rng));
    q.push_back(slide(rng));
  }
  return q;
}

}  // namespace medspheres::test
