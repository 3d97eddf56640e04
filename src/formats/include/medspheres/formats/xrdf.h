#pragma once
/// \file
/// XRDF, the Extended Robot Description Format of NVIDIA Isaac (cuMotion) and cuRobo,
/// version 1.0: the collision-sphere part, with the sections cuRobo's XRDF loader
/// (convert_xrdf_to_curobo) requires when the joints are known.
///
/// Written layout:
/// \code{.yaml}
/// format: xrdf
/// format_version: 1.0           # a number: cuRobo compares it with 1.0
/// cspace:                       # when joint names are given
///   joint_names: [j1, j2]
///   acceleration_limits: [15, 15]
///   jerk_limits: [500, 500]
/// default_joint_positions: {j1: 0, j2: 0.1}   # with the cspace
/// tool_frames: [tool]           # when given
/// geometry:
///   medspheres_spheres:
///     spheres:
///       link_a:
///         - {center: [x, y, z], radius: r}
/// collision:
///   geometry: medspheres_spheres
/// self_collision:
///   geometry: medspheres_spheres
///   ignore: {link_a: [link_b]}  # always written ({} when empty): cuRobo requires it
/// \endcode
/// The reader takes the geometry group that "collision" names (or the only group when
/// there is no "collision" section). Numbers are written in their shortest exact form.

#include <string>
#include <vector>

#include "medspheres/formats/robot_spheres.h"

namespace medspheres::formats {

struct XrdfOptions {
  std::string geometry_name = "medspheres_spheres";  ///< the geometry group's name
  /// The c-space joints (XRDF requires a cspace section for cuMotion); no cspace section
  /// is written when empty.
  std::vector<std::string> joint_names;
  double acceleration_limit = 15.0;  ///< rad/s^2 or m/s^2 per joint, cuRobo's default
  double jerk_limit = 500.0;         ///< rad/s^3 or m/s^3 per joint, cuRobo's default
  /// Each joint's default position (the c-space's retract configuration), parallel to
  /// joint_names; 0 for every joint when empty.
  std::vector<double> default_positions;
  std::vector<std::string> tool_frames;  ///< written as tool_frames when not empty
  LinkPairLists self_collision_ignore;   ///< self_collision: ignore
};

/// The XRDF text. \throws InputError for invalid spheres or names.
std::string xrdf_text(const RobotSpheres& spheres, const XrdfOptions& options = {});

/// The spheres of the collision geometry group, per link in the file's order.
/// \throws InputError naming \p source and the problem: not YAML, not "format: xrdf", a
///   missing group, a malformed sphere (naming the link).
RobotSpheres parse_xrdf(const std::string& text, const std::string& source);

RobotSpheres load_xrdf(const std::string& path);
void save_xrdf(const std::string& path, const RobotSpheres& spheres,
               const XrdfOptions& options = {});

}  // namespace medspheres::formats
