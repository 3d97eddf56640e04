#pragma once
// Generated arms for the self-collision tests and benchmark: URDF text of primitives only
// (boxes, cylinders, spheres), so that no mesh file is needed, with a gripper and a joint
// that moves no geometry.

#include <cmath>
#include <random>
#include <string>

namespace medspheres::test {

/// A serial arm on a box base: \p arm_joints revolute joints (alternately about z and y,
/// limits about +-2.6 rad, one joint with limits that exclude 0), links of random lengths
/// (cylinders and boxes, seeded by \p seed), a sphere primitive at the elbow, a flange
/// without geometry, a hand carrying two fingers on prismatic joints (the right one a mimic
/// of the left when \p mimic_finger), and a "sensor" frame without geometry on a revolute
/// joint off the first link. Link names: base, link1..linkN, flange, hand, left_finger,
/// right_finger, sensor. Metres and radians.
inline std::string generated_arm_urdf(unsigned seed, int arm_joints, bool mimic_finger = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> length(0.18, 0.32), radius(0.03, 0.05);
  const auto num = [](double v) { return std::to_string(v); };
  std::string u = "<?xml version=\"1.0\"?>\n<robot name=\"generated_arm_" + std::to_string(seed) +
                  "\">\n  <link name=\"base\"><collision><geometry><box size=\"0.25 0.25 0.1\"/>"
                  "</geometry></collision></link>\n";
  std::string parent = "base";
  double parent_length = 0.05;
  for (int i = 1; i <= arm_joints; ++i) {
    const std::string link = "link" + std::to_string(i);
    const double l = length(rng), r = radius(rng);
    const bool box = i % 3 == 2;
    u += "  <link name=\"" + link + "\"><collision><origin xyz=\"0 0 " + num(l / 2) +
         "\"/><geometry>" +
         (box ? "<box size=\"" + num(1.6 * r) + " " + num(1.6 * r) + " " + num(l) + "\"/>"
              : "<cylinder radius=\"" + num(r) + "\" length=\"" + num(l) + "\"/>") +
         "</geometry></collision>";
    if (i == 2)
      u += "<collision><origin xyz=\"0 0 " + num(l) + "\"/><geometry><sphere radius=\"" +
           num(1.2 * r) + "\"/></geometry></collision>";
    u += "</link>\n";
    const bool about_z = i % 2 == 1;
    const std::string limits =
        i == 3 ? "lower=\"0.3\" upper=\"2.4\"" : "lower=\"-2.6\" upper=\"2.6\"";
    u += "  <joint name=\"joint" + std::to_string(i) + "\" type=\"revolute\"><parent link=\"" +
         parent + "\"/><child link=\"" + link + "\"/><origin xyz=\"0 0 " + num(parent_length) +
         "\"/><axis xyz=\"" + (about_z ? "0 0 1" : "0 1 0") + "\"/><limit " + limits +
         " velocity=\"2\" effort=\"10\"/></joint>\n";
    parent = link;
    parent_length = l;
  }
  u += "  <link name=\"flange\"/>\n  <joint name=\"flange_joint\" type=\"fixed\"><parent link=\"" +
       parent + "\"/><child link=\"flange\"/><origin xyz=\"0 0 " + num(parent_length) +
       "\"/></joint>\n";
  u += "  <link name=\"hand\"><collision><origin xyz=\"0 0 0.02\"/><geometry><box "
       "size=\"0.06 0.16 0.04\"/></geometry></collision></link>\n"
       "  <joint name=\"hand_joint\" type=\"fixed\"><parent link=\"flange\"/><child "
       "link=\"hand\"/></joint>\n";
  for (const char* side : {"left", "right"}) {
    const bool left = side[0] == 'l';
    u += std::string("  <link name=\"") + side +
         "_finger\"><collision><origin xyz=\"0 0 0.03\"/><geometry><box size=\"0.02 0.02 "
         "0.06\"/></geometry></collision></link>\n";
    u += std::string("  <joint name=\"") + side +
         "_finger_joint\" type=\"prismatic\"><parent link=\"hand\"/><child link=\"" + side +
         "_finger\"/><origin xyz=\"0 " + (left ? "0.012" : "-0.012") + " 0.04\"/><axis xyz=\"0 " +
         (left ? "1" : "-1") +
         " 0\"/><limit lower=\"0\" upper=\"0.05\" velocity=\"0.2\" effort=\"20\"/>" +
         (!left && mimic_finger ? "<mimic joint=\"left_finger_joint\"/>" : "") + "</joint>\n";
  }
  u += "  <link name=\"sensor\"/>\n  <joint name=\"sensor_joint\" type=\"revolute\"><parent "
       "link=\"link1\"/><child link=\"sensor\"/><origin xyz=\"0.05 0 0.05\"/><axis xyz=\"1 0 "
       "0\"/><limit lower=\"-1\" upper=\"1\" velocity=\"1\" effort=\"1\"/></joint>\n</robot>\n";
  return u;
}

}  // namespace medspheres::test
