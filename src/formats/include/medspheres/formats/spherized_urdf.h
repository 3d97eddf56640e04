#pragma once
/// \file
/// The spherized URDF: a robot's URDF in which each link's <collision> elements are
/// replaced by one <collision> per sphere, what VAMP's code generator and foam's users
/// load:
/// \code{.xml}
/// <collision><origin xyz="x y z"/><geometry><sphere radius="r"/></geometry></collision>
/// \endcode
/// The XML goes through tinyxml2: every other element, attribute and comment is kept as it
/// was (indentation between elements is tinyxml2's), and names with XML special
/// characters are escaped. Numbers are written in their shortest exact form.

#include <string>

#include "medspheres/formats/robot_spheres.h"

namespace medspheres::formats {

/// \p urdf_text with the <collision> elements of every link named in \p spheres replaced
/// by its spheres (in place of the first old one, or at the link's end). Links not named
/// keep their <collision> elements.
/// \throws InputError naming \p source: not XML, no <robot> root, a link of \p spheres
///   that the URDF does not have, invalid spheres.
std::string spherize_urdf(const std::string& urdf_text, const RobotSpheres& spheres,
                          const std::string& source);

/// The <sphere> collision elements of each link: centre = the collision's origin xyz
/// (rotation is irrelevant for a sphere), in the URDF's link order; links without sphere
/// collisions are left out and other collision geometry is ignored.
/// \throws InputError naming \p source, the link and the problem.
RobotSpheres parse_urdf_spheres(const std::string& urdf_text, const std::string& source);

RobotSpheres load_urdf_spheres(const std::string& path);

}  // namespace medspheres::formats
