#pragma once
/// \file
/// The SRDF sidecar: MoveIt's sphere approximation of each link (srdfdom's
/// <link_sphere_approximation>), which leaves the URDF's own collision meshes alone.
/// \code{.xml}
/// <robot name="arm">
///   <link_sphere_approximation link="link_a">
///     <sphere center="x y z" radius="r"/>
///   </link_sphere_approximation>
/// </robot>
/// \endcode
/// As in srdfdom, a link whose only sphere has radius 0 has no spheres; the writer writes
/// that for a link with an empty list. XML through tinyxml2 (names escaped); numbers in
/// their shortest exact form.

#include <string>

#include "medspheres/formats/robot_spheres.h"

namespace medspheres::formats {

/// The SRDF text. \throws InputError for invalid spheres or names.
std::string srdf_spheres_text(const RobotSpheres& spheres, const std::string& robot_name);

/// Every <link_sphere_approximation> of the document, in its order; other SRDF elements
/// are ignored. \throws InputError naming \p source, the link and the problem.
RobotSpheres parse_srdf_spheres(const std::string& text, const std::string& source);

RobotSpheres load_srdf_spheres(const std::string& path);

}  // namespace medspheres::formats
