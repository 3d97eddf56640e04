#pragma once
/// \file
/// The medspheres robot file: a RobotModel as JSON, so that the query side needs neither
/// urdfdom nor the meshes.
///
/// \code{.json}
/// {
///   "format": "medspheres.robot",
///   "version": 1,
///   "name": "arm",
///   "root_link": "base",
///   "links": [
///     {"name": "base", "inner": [[x, y, z, r], ...], "outer": [[x, y, z, r], ...],
///      "outer_certificate": {...}, "note": ""}
///   ],
///   "joints": [
///     {"name": "j1", "type": "revolute", "parent": "base", "child": "l1",
///      "origin": {"xyz": [x, y, z], "quaternion_xyzw": [qx, qy, qz, qw]},
///      "axis": [ax, ay, az],
///      "limits": {"lower": -1, "upper": 1, "velocity": 2, "effort": 10},
///      "mimic": {"joint": "j0", "multiplier": 1, "offset": 0}}
///   ],
///   "planner": {"tool_frames": ["hand"], "tool_frames_from": "gripper",
///               "locked_joints": ["finger"], "default_positions": {"j1": 0, "finger": 0},
///               "default_from": "zero",
///               "self_collision": {"samples": 10000, "seed": 1, "threshold": 0.95,
///                                  "margin": 0.01, "srdf": "", "buffer": {"base": 0},
///                                  "pairs": [["base", "l1", "adjacent", true]]}},
///   "metadata": {...}
/// }
/// \endcode
/// Spheres are in their link's frame, metres. A joint's origin is X_PJ: the translation
/// "xyz" and the rotation as a unit quaternion in (x, y, z, w) order, urdfdom's order. A
/// reader also accepts "rpy" (URDF's fixed-axis roll, pitch, yaw in radians) in place of
/// the quaternion. "type" is fixed, revolute, continuous or prismatic; "limits", "mimic",
/// "outer_certificate", "note" and "planner" may be absent; "inner" and "outer" may be
/// empty. "planner" is the PlannerSetup (planner_setup.h); a pair is [link1, link2, class,
/// ignored], with the SRDF's reason fifth for the class "given". A reader of version 1 that
/// predates "planner" ignores it.
/// "metadata" is kept verbatim (RobotModel::metadata_json); other unknown keys are ignored.
/// Numbers are written in the shortest form that reads back bit-identical, so spheres,
/// translations, axes, limits and mimic factors round-trip exactly; a rotation reads back
/// as the matrix of the quaternion written for it (equal to about 1e-16).

#include <string>

#include "medspheres/robot_model.h"

namespace medspheres {

inline constexpr const char* kRobotFormat = "medspheres.robot";
inline constexpr int kRobotVersion = 1;

/// Reads and validates a robot file.
/// \throws InputError naming \p path (and the link or joint at fault) for a missing or
///   unreadable file, invalid JSON, a wrong format or version, a missing or mistyped key,
///   and every problem validate_robot_model finds.
RobotModel load_robot(const std::string& path);

/// Parses robot-file JSON text; \p source names it in error messages.
RobotModel parse_robot(const std::string& json_text, const std::string& source);

/// The JSON text of \p model. \throws std::invalid_argument when metadata_json or a
/// certificate is not a JSON object.
std::string robot_to_json(const RobotModel& model);

/// The robot-file text \p robot_json (as robot_to_json wrote it) with its "metadata"
/// replaced by the JSON object \p metadata_json: byte for byte the text robot_to_json
/// writes for the same model with that metadata (the other values are copied as read).
/// \throws InputError naming \p source when \p robot_json is not a JSON object;
///   std::invalid_argument when \p metadata_json is not one.
std::string robot_json_with_metadata(const std::string& robot_json,
                                     const std::string& metadata_json, const std::string& source);

/// The "metadata" object of the robot-file text \p robot_json, as JSON text ("{}" when it
/// has none). \throws InputError naming \p source when \p robot_json is not a JSON object.
std::string robot_json_metadata(const std::string& robot_json, const std::string& source);

/// Validates \p model (naming \p path) and writes it atomically (write_file_atomically).
void save_robot(const RobotModel& model, const std::string& path);

}  // namespace medspheres
