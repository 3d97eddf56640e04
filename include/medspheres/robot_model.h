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
  std::string parent;  ///< parent link name
  std::string child;   ///< child link name
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< X_PJ
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();          ///< unit, in J
  std::optional<JointLimits> limits;
  std::optional<JointMimic> mimic;
};

/// The spheres of one link, in its frame: an inner set (inside the link's solid) and a
/// covering set (its union contains the solid's surface), either may be empty.
struct LinkSpheres {
  SphereSet inner;
  SphereSet outer;
  /// The outer set's coverage certificate, as recorded by the bake (JSON object text;
  /// empty when the outer set is not certified).
  std::string outer_certificate_json;
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

  const Link* find_link(const std::string& name) const;
  const Joint* find_joint(const std::string& name) const;
};

}  // namespace medspheres
