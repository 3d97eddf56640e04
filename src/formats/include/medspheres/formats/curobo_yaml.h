#pragma once
/// \file
/// cuRobo's robot configuration YAML, the sphere part of it.
///
/// Written layout (spheres inline, as cuRobo's current configurations hold them):
/// \code{.yaml}
/// format_version: 2.0
/// robot_cfg:
///   kinematics:
///     base_link: base            # when known
///     collision_link_names: [link_a, link_b]
///     collision_spheres:
///       link_a:
///         - {center: [x, y, z], radius: r}
///     collision_sphere_buffer: 0.0
///     self_collision_ignore: {link_a: [link_b]}   # when given
/// \endcode
/// cuRobo's loaders read "robot_cfg: kinematics:" (the older one: RobotConfig.from_dict of
/// the file's "robot_cfg"; the current one, load_robot_yaml, also takes "kinematics:" at
/// the top level or a bare kinematics mapping); neither reads "format_version", which
/// marks the layout for other readers. Read
/// layouts: "collision_spheres" under "robot_cfg: kinematics:", under a top-level
/// "kinematics:" (cuRobo's newer files, e.g. its Unitree G1), or at the top level (cuRobo's
/// separate sphere files). Every other key is ignored. Numbers are written in their
/// shortest exact form: read back, every sphere is bit-identical.

#include <string>

#include "medspheres/formats/robot_spheres.h"

namespace medspheres::formats {

struct CuroboOptions {
  std::string base_link;  ///< written as kinematics.base_link when not empty
  /// Written as kinematics.self_collision_ignore when not empty.
  LinkPairLists self_collision_ignore;
};

/// The YAML text. \throws InputError (source "cuRobo YAML") for invalid spheres or names.
std::string curobo_yaml_text(const RobotSpheres& spheres, const CuroboOptions& options = {});

/// The spheres of a cuRobo configuration, per link in the file's order.
/// \throws InputError naming \p source, the link and the problem: not YAML, no
///   "collision_spheres", spheres kept in a separate file (a string), a malformed sphere.
RobotSpheres parse_curobo_yaml(const std::string& text, const std::string& source);

RobotSpheres load_curobo_yaml(const std::string& path);

/// Writes curobo_yaml_text atomically.
void save_curobo_yaml(const std::string& path, const RobotSpheres& spheres,
                      const CuroboOptions& options = {});

}  // namespace medspheres::formats
