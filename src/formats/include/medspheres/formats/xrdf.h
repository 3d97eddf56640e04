#pragma once
/// \file
/// XRDF, the Extended Robot Description Format of NVIDIA Isaac (cuMotion) and cuRobo,
/// version 1.0: the collision-sphere part, with the sections cuRobo's XRDF loader
/// (convert_xrdf_to_curobo) requires when the joints are known.
///
/// What cuRobo's XRDF loader requires (v2: NVlabs/curobo a35a708,
/// `curobo/_src/util/xrdf_util.py`; v1: d64c4b0, `src/curobo/util/xrdf_utils.py`). Each item
/// has a test in tests/formats_test.cpp ("XRDF loader contract").
/// - `format: xrdf` (v2 :42, v1 :48) and `format_version` a number compared with 1.0 (v2
///   :45, v1 :51).
/// - `collision: geometry:` names a group of `geometry:` that holds `spheres`: link -> list
///   of {center: [x, y, z], radius: r}, metres, link frame (v2 :55-69, v1 :61-76); every link
///   listed becomes a collision link.
/// - `self_collision:` required with `collision` (v2 :71-93, v1 :78-100): `geometry` the
///   same group, `ignore` a mapping link -> [links] (required, `{}` when empty), and
///   `buffer_distance` a mapping link -> metres (cuRobo's self_collision_buffer).
/// - `modifiers`, optional: a list of one-key maps; `set_base_frame` names the base link (v2
///   :142-150, v1 :151-159), else the URDF's root is the base (v2 :52, v1 :58), and every
///   joint between the two would be in the chain.
/// - `tool_frames` required, a list; the first is the primary end effector (v2 :97-100; v1
///   :104-108 makes it ee_link).
/// - `cspace` required (v2 :103, v1 :111): `joint_names` (the planned joints),
///   `acceleration_limits` and `jerk_limits` (lists, v2 :122-125, v1 :130-134).
/// - `default_joint_positions` required, a mapping joint -> position (v2 :107, v1 :115); every
///   actuated joint of the URDF that cspace does not name is locked at its default there
///   (v2 :111-120, v1 :119-128).
///
/// Written layout:
/// \code{.yaml}
/// format: xrdf
/// format_version: 1.0           # a number: cuRobo compares it with 1.0
/// modifiers:                    # when a base frame is given
///   - set_base_frame: base
/// cspace:                       # when joint names are given
///   joint_names: [j1, j2]
///   acceleration_limits: [15.0, 15.0]
///   jerk_limits: [500.0, 500.0]
/// default_joint_positions: {j1: 0.0, j2: 0.1, finger: 0.0}   # with the cspace
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
///   buffer_distance: {link_a: 0.0}   # when given
/// \endcode
/// The reader takes the geometry group that "collision" names (or the only group when
/// there is no "collision" section). Numbers as yaml_float_text (any YAML 1.1 reader takes
/// them as floats); read back, every sphere is bit-identical.

#include <string>
#include <utility>
#include <vector>

#include "medspheres/formats/robot_spheres.h"

namespace medspheres::formats {

struct XrdfOptions {
  std::string geometry_name = "medspheres_spheres";  ///< the geometry group's name
  /// The base link, written as the modifier set_base_frame when not empty (a robot read from
  /// a URDF whose root hangs from a floating joint has its base below the URDF's root).
  std::string base_frame;
  /// The planned c-space joints (XRDF requires a cspace section for cuMotion); no cspace
  /// section is written when empty.
  std::vector<std::string> joint_names;
  double acceleration_limit = 15.0;  ///< rad/s^2 or m/s^2 per joint, cuRobo's default
  double jerk_limit = 500.0;         ///< rad/s^3 or m/s^3 per joint, cuRobo's default
  /// Every actuated joint's default position (the c-space's retract configuration; a joint
  /// joint_names lacks is locked there); each of joint_names at 0 when empty.
  std::vector<std::pair<std::string, double>> default_positions;
  std::vector<std::string> tool_frames;  ///< written as tool_frames when not empty
  LinkPairLists self_collision_ignore;   ///< self_collision: ignore
  /// self_collision: buffer_distance, link -> metres; not written when empty.
  std::vector<std::pair<std::string, double>> self_collision_buffer;
  /// Written, when it has a name, as the modifier add_frame and its sphere in the geometry
  /// group (robot_spheres.h).
  PlaceholderFrame placeholder;
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
