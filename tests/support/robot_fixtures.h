#pragma once
// Small robot models for tests: a three-link arm with a revolute, a prismatic, a mimic
// (continuous) and a fixed joint, one origin rotated.

#include <cmath>
#include <string>

#include "medspheres/robot_model.h"

namespace medspheres::test {

inline Link make_link(const std::string& name) {
  Link l;
  l.name = name;
  return l;
}

inline Joint make_joint(const std::string& name, JointType type, const std::string& parent,
                        const std::string& child, const Eigen::Vector3d& xyz,
                        const Eigen::Vector3d& axis = Eigen::Vector3d::UnitZ()) {
  Joint j;
  j.name = name;
  j.type = type;
  j.parent = parent;
  j.child = child;
  j.origin.translation() = xyz;
  j.axis = axis;
  return j;
}

/// base -j1 (revolute about z, origin (0,0,1))-> l1 -j2 (prismatic along x, origin (1,0,0)
/// rotated by rpy (pi/2, 0, 0))-> l2 -j3 (continuous about y, origin (0,0,0.5), mimics j1
/// with multiplier 2 and offset 0.1)-> l3 -tool_joint (fixed, origin (0,0,0.2))-> tool.
inline RobotModel three_link_arm() {
  RobotModel m;
  m.name = "arm";
  m.root_link = "base";
  for (const char* n : {"base", "l1", "l2", "l3", "tool"}) m.links.push_back(make_link(n));
  m.joints.push_back(make_joint("j1", JointType::kRevolute, "base", "l1", {0, 0, 1}));
  m.joints.back().limits = JointLimits{-3.0, 3.0, 2.0, 10.0};
  m.joints.push_back(
      make_joint("j2", JointType::kPrismatic, "l1", "l2", {1, 0, 0}, Eigen::Vector3d::UnitX()));
  m.joints.back().origin.linear() =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  m.joints.back().limits = JointLimits{0.0, 0.5, 0.1, 100.0};
  m.joints.push_back(
      make_joint("j3", JointType::kContinuous, "l2", "l3", {0, 0, 0.5}, Eigen::Vector3d::UnitY()));
  m.joints.back().mimic = JointMimic{"j1", 2.0, 0.1};
  m.joints.push_back(make_joint("tool_joint", JointType::kFixed, "l3", "tool", {0, 0, 0.2}));
  return m;
}

}  // namespace medspheres::test
