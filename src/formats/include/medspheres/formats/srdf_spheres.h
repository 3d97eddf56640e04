#pragma once
/// \file
/// The SRDF sidecar: MoveIt's sphere approximation of each link (srdfdom's
/// <link_sphere_approximation>), which leaves the URDF's own collision meshes alone, and the
/// pairs a planner skips with the reason MoveIt's setup assistant would give
/// (srdf_disabled_collisions.h).
/// \code{.xml}
/// <robot name="arm">
///   <link_sphere_approximation link="link_a">
///     <sphere center="x y z" radius="r"/>
///   </link_sphere_approximation>
///   <disable_collisions link1="link_a" link2="link_b" reason="Adjacent"/>
/// </robot>
/// \endcode
/// As in srdfdom, a link whose only sphere has radius 0 has no spheres; the writer writes
/// that for a link with an empty list. XML through tinyxml2 (names escaped); numbers in
/// their shortest exact form.

#include <string>
#include <vector>

#include "medspheres/formats/robot_spheres.h"
#include "medspheres/formats/srdf_disabled_collisions.h"

namespace medspheres::formats {

/// The SRDF text: the spheres, then \p disabled. \throws InputError for invalid spheres or
/// names.
std::string srdf_spheres_text(const RobotSpheres& spheres, const std::string& robot_name,
                              const std::vector<DisabledCollision>& disabled = {});

/// Every <link_sphere_approximation> of the document, in its order; other SRDF elements
/// are ignored. \throws InputError naming \p source, the link and the problem.
RobotSpheres parse_srdf_spheres(const std::string& text, const std::string& source);

RobotSpheres load_srdf_spheres(const std::string& path);

}  // namespace medspheres::formats
