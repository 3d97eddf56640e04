#pragma once
/// \file
/// RobotModel: a robot's kinematic tree and its per-link sphere sets, the plain data that
/// the robot file stores and that the query side needs (no urdfdom, no meshes).
///
/// Frames: every link has its own frame L (the URDF link frame). A joint's origin is
/// X_PJ, the pose of the joint frame J in the parent link frame P; at joint value q the
/// child frame is X_PC = X_PJ * motion(q), where motion is a rotation of q rad about
/// `axis` (revolute, continuous) or a translation of q m along it (prismatic), and the
/// identity for fixed joints. Units: metres and radians. Spheres of a link are in L.

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/planner_setup.h"
#include "medspheres/sphere_set.h"

namespace medspheres {

enum class JointType { kFixed, kRevolute, kContinuous, kPrismatic };

/// A joint that copies another: q = multiplier * q_source + offset.
struct JointMimic {
  std::string joint;  ///< the source joint's name
  double multiplier = 1.0;
  double offset = 0.0;
};

struct JointLimits {
  double lower = 0.0;  ///< rad or m; both 0 when the URDF gives none
  double upper = 0.0;
  double velocity = 0.0;
  double effort = 0.0;
};

struct Joint {
  std::string name;
  JointType type = JointType::kFixed;
  std::string parent;                                        ///< parent link name
  std::string child;                                         ///< child link name
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< X_PJ
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();           ///< unit, in J
  std::optional<JointLimits> limits;
  std::optional<JointMimic> mimic;
};

/// A joint that is a coordinate of the configuration: neither fixed nor a mimic, which
/// follows its source.
inline bool is_actuated(const Joint& j) {
  return j.type != JointType::kFixed && !j.mimic;
}

/// The spheres of one link, in its frame: an inner set (inside the link's solid) and a
/// covering set (its union contains the solid's surface), either may be empty.
struct LinkSpheres {
  SphereSet inner;
  SphereSet outer;
  /// The outer set's coverage certificate, as recorded by the bake (JSON object text;
  /// empty when the outer set is not certified).
  std::string outer_certificate_json;
  /// The inner set lies in the link's filled solid (a thin shell closed, its cavity filled:
  /// `medspheres robot --fill`), not in its material: its balls may sit in the cavity, so
  /// they prove nothing about the material. Certified queries then leave them out.
  bool inner_filled = false;
};

struct Link {
  std::string name;
  LinkSpheres spheres;
  /// Why a link has no spheres ("no collision geometry"), empty otherwise.
  std::string note;
};

struct RobotModel {
  std::string name;
  std::string root_link;
  std::vector<Link> links;    ///< in the URDF's order
  std::vector<Joint> joints;  ///< in the URDF's order
  /// Provenance kept verbatim (URDF path, mesh sha256s, options, per-link statistics),
  /// JSON object text.
  std::string metadata_json;
  /// Tool frames, default configuration and self-collision matrix (planner_setup.h); none
  /// for a model that was not baked with them.
  std::optional<PlannerSetup> planner;

  /// The link or joint of that name, or nullptr. Linear in the number of links/joints.
  const Link* find_link(const std::string& name) const;
  const Joint* find_joint(const std::string& name) const;
};

/// The lower-case name of a joint type as URDF spells it ("fixed", "revolute", ...).
const char* joint_type_name(JointType type);

/// Checks that \p model is one kinematic tree that forward kinematics can walk:
/// - link and joint names are non-empty and unique;
/// - every joint names existing parent and child links, and they differ;
/// - no link is the child of two joints; exactly one link is no joint's child, and it is
///   `root_link` (when `root_link` is empty it is not checked); every link is reached from
///   it (so there is no cycle);
/// - origins, axes, limits and mimic factors are finite; a moving joint's axis is not
///   zero; limits have lower <= upper;
/// - a mimic joint moves, names an existing moving joint other than itself, and following
///   mimic sources from it never comes back to it;
/// - every sphere is valid (validate_sphere_set);
/// - the planner setup, when present, names links and joints of the model
///   (validate_planner_setup).
/// \param source the robot file's name (or "robot model"), first in every message.
/// \throws InputError "<source>: joint "j2": ..." naming the link or joint and the problem.
void validate_robot_model(const RobotModel& model, const std::string& source);

}  // namespace medspheres
