#pragma once
// Per-link sphere lists for format tests: seeded random spheres, a link name full of XML
// and YAML special characters, and the URDF those links belong to.

#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "medspheres/formats/robot_spheres.h"

namespace medspheres::test {

/// The awkward link name every format must carry unchanged.
inline const std::string kAwkwardLink = "arm<&>\"'#: [1]";

/// Three links (base, kAwkwardLink, tool) with 4, 9 and 1 random spheres: coordinates
/// over many magnitudes, so that printing with too few digits would show.
inline formats::RobotSpheres random_robot_spheres(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-9.0, 1.0);
  auto number = [&] { return u(rng) * std::pow(10.0, e(rng)); };
  formats::RobotSpheres out;
  const std::pair<const char*, int> links[] = {{"base", 4}, {kAwkwardLink.c_str(), 9}, {"tool", 1}};
  for (const auto& [name, n] : links) {
    formats::LinkSphereList l{name, {}};
    for (int i = 0; i < n; ++i)
      l.spheres.push_back({{number(), number(), number()}, std::abs(number()) + 1e-12});
    out.push_back(l);
  }
  return out;
}

/// A URDF with the links of random_robot_spheres: mesh and primitive collisions, one with
/// a rotated origin, visuals, a comment and joints.
inline std::string awkward_urdf() {
  return R"(<?xml version="1.0"?>
<robot name="awk&amp;ward">
  <!-- kept as it was -->
  <link name="base">
    <visual><geometry><mesh filename="package://pkg/base.stl" scale="0.001 0.001 0.001"/></geometry></visual>
    <collision><origin xyz="0 0 0.1" rpy="0 1.5707963 0"/><geometry><mesh filename="package://pkg/base.stl"/></geometry></collision>
    <collision><geometry><box size="0.1 0.2 0.3"/></geometry></collision>
  </link>
  <link name="arm&lt;&amp;&gt;&quot;&apos;#: [1]">
    <inertial><mass value="1.5"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <collision><geometry><cylinder radius="0.05" length="0.4"/></geometry></collision>
  </link>
  <link name="tool"/>
  <link name="no_spheres">
    <collision><geometry><sphere radius="0.02"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="arm&lt;&amp;&gt;&quot;&apos;#: [1]"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <joint name="j2" type="fixed">
    <parent link="arm&lt;&amp;&gt;&quot;&apos;#: [1]"/><child link="tool"/>
  </joint>
  <joint name="j3" type="fixed">
    <parent link="tool"/><child link="no_spheres"/>
  </joint>
</robot>
)";
}

inline bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

/// True when \p a and \p b hold the same links, in the same order, with bit-identical spheres.
inline bool identical(const formats::RobotSpheres& a, const formats::RobotSpheres& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].link != b[i].link || a[i].spheres.size() != b[i].spheres.size()) return false;
    for (std::size_t k = 0; k < a[i].spheres.size(); ++k) {
      const Sphere &s = a[i].spheres[k], &t = b[i].spheres[k];
      if (!same_bits(s.radius, t.radius)) return false;
      for (int c = 0; c < 3; ++c)
        if (!same_bits(s.center[c], t.center[c])) return false;
    }
  }
  return true;
}

}  // namespace medspheres::test
