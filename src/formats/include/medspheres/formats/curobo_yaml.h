#pragma once
/// \file
/// cuRobo's robot configuration YAML: the files cuRobo's loaders take as written, and the
/// reader of their spheres.
///
/// What cuRobo's loaders require (v2: NVlabs/curobo a35a708, `curobo/_src/`; v1: d64c4b0,
/// `src/curobo/`). Each item has a test in tests/formats_test.cpp ("cuRobo loader contract").
/// - Nesting: `robot_cfg: kinematics:` holds the keys below; the mapping is passed whole as
///   keyword arguments to a dataclass, so an unknown key is a TypeError (v2
///   robot/kinematics/kinematics_cfg.py:107-117 into robot/loader/kinematics_loader_cfg.py;
///   v1 cuda_robot_model/cuda_robot_model.py:174-182 and types/robot.py:46-51 into
///   cuda_robot_model/cuda_robot_generator.py). v2 and v1 differ in two keys, so each gets
///   its own file (CuroboLayout).
/// - `base_link`: required, a link name (v2 kinematics_loader_cfg.py:31, v1
///   cuda_robot_generator.py:64).
/// - v2 `tool_frames`: required, a list of links, the first the primary end effector
///   (kinematics_loader_cfg.py:166-167, kinematics_loader.py:239). v1 rejects it.
/// - v1 `ee_link`: required, one link (cuda_robot_generator.py:67), and `link_names`: the
///   other links to report (:73). v2 rejects both.
/// - `collision_spheres`: required key (v2 robot/loader/util.py:48, v1
///   cuda_robot_model/util.py:58): link -> list of {center: [x, y, z], radius: r}, metres,
///   link frame; or a path whose file holds `collision_spheres:` at its top level (v2
///   kinematics_loader_cfg.py:170-176, v1 cuda_robot_generator.py:212-216).
/// - `collision_link_names`: the links to load spheres for (v2 :40, v1 :76); each must be a
///   key of collision_spheres.
/// - `collision_sphere_buffer`: a float (not an int: `isinstance(x, float)`, v2
///   kinematics_loader.py:877, v1 cuda_robot_generator.py:760), metres added to every radius.
/// - `self_collision_buffer`: a mapping link -> metres, required (v2 kinematics_loader.py:866,
///   v1 cuda_robot_generator.py:749 call `.copy()` on it), added to the link's radii in
///   self-collision only.
/// - `self_collision_ignore`: a mapping link -> [links], required (v2
///   robot/types/self_collision_params.py:172, v1 cuda_robot_generator.py:803 call `.keys()`);
///   either direction skips the pair.
/// - `lock_joints`: optional mapping joint -> position (v2 kinematics_loader_cfg.py:84, v1
///   cuda_robot_generator.py:141); v1 looks each up among the kinematic tree's joints
///   (cuda_robot_generator.py:650), v2 refuses mimic joints (kinematics_loader.py:614).
/// - `cspace`: a mapping passed as keyword arguments (v2 kinematics_loader_cfg.py:194 to
///   robot/types/cspace_params.py:21, v1 cuda_robot_generator.py:237 to
///   cuda_robot_model/types.py:154): `joint_names` required; the default configuration is
///   `default_joint_position` in v2 (cspace_params.py:32) and `retract_config` in v1
///   (types.py:165); `max_acceleration`, `max_jerk`, `null_space_weight`,
///   `cspace_distance_weight` per joint. v2 requires the names to hold every joint of its
///   kinematic tree and no other joint that is not locked (kinematics_loader.py:536-646).
/// - v2 divides by the number of sphere pairs that it checks (self_collision_params.py:110):
///   a robot whose spheres sit on one link gets a PlaceholderFrame, as `extra_links: NAME:
///   {parent_link_name, link_name, joint_name, joint_type: FIXED, fixed_transform: [x, y, z,
///   qw, qx, qy, qz]}` (kinematics_loader_cfg.py:185-190 to robot/types/link_params.py:43).
/// - Numbers: cuRobo reads with PyYAML; yaml_float_text writes every number so that any
///   YAML 1.1 reader takes it as a float.
///
/// Read layouts: `collision_spheres` under `robot_cfg: kinematics:`, under a top-level
/// `kinematics:` (cuRobo's newer files, e.g. its Unitree G1), or at the top level (cuRobo's
/// separate sphere files). Every other key is ignored. Read back, every sphere is
/// bit-identical.

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "medspheres/formats/robot_spheres.h"

namespace medspheres::formats {

/// Which file: cuRobo v2's robot configuration, v1's, or the spheres alone.
enum class CuroboLayout {
  kV2,      ///< `format_version: 2.0` at the top, `tool_frames`, cspace default_joint_position
  kV1,      ///< `ee_link` and `link_names`, cspace retract_config
  kSpheres  ///< only `collision_spheres:` at the top level, for a configuration to name
};

struct CuroboOptions {
  CuroboLayout layout = CuroboLayout::kV2;
  std::string base_link;  ///< written when not empty
  std::string urdf_path;  ///< written when not empty (cuRobo takes an absolute path as is)
  /// The planner keys (tool frames, buffers, ignore, cspace) are written when this is not
  /// empty; the first is the primary end effector.
  std::vector<std::string> tool_frames;
  LinkPairLists self_collision_ignore;
  /// Every link with spheres -> metres (written with the tool frames).
  std::vector<std::pair<std::string, double>> self_collision_buffer;
  std::vector<std::string> joint_names;                     ///< cspace joints: every actuated joint
  std::vector<double> default_positions;                    ///< parallel to joint_names
  std::vector<std::pair<std::string, double>> lock_joints;  ///< written when not empty
  double max_acceleration = 15.0;  ///< per joint, cuRobo's default (rad/s^2 or m/s^2)
  double max_jerk = 500.0;         ///< per joint, cuRobo's default (rad/s^3 or m/s^3)
  /// Written, when it has a name, as an `extra_links` entry, a collision link and its
  /// sphere (robot_spheres.h).
  PlaceholderFrame placeholder;
};

/// The YAML text. \throws InputError (source "cuRobo YAML") for invalid spheres or names;
/// std::invalid_argument when default_positions and joint_names differ in size.
std::string curobo_yaml_text(const RobotSpheres& spheres, const CuroboOptions& options = {});

/// The spheres of a cuRobo configuration, per link in the file's order.
/// \throws InputError naming \p source, the link and the problem: not YAML, no
///   "collision_spheres", spheres kept in a separate file (a string), a malformed sphere.
RobotSpheres parse_curobo_yaml(const std::string& text, const std::string& source);

RobotSpheres load_curobo_yaml(const std::string& path);

/// \p text, a configuration curobo_yaml_text wrote, with its `robot_cfg: kinematics:
/// urdf_path` renamed by \p names (path -> path); the text unchanged, byte for byte, when
/// it has no urdf_path or names does not hold it. Every other byte is kept.
/// \throws InputError naming \p source when the text is not YAML.
std::string curobo_yaml_with_urdf_path(const std::string& text,
                                       const std::map<std::string, std::string>& names,
                                       const std::string& source);

/// Writes curobo_yaml_text atomically.
void save_curobo_yaml(const std::string& path, const RobotSpheres& spheres,
                      const CuroboOptions& options = {});

}  // namespace medspheres::formats
