#pragma once
/// \file
/// A robot read from a URDF with urdfdom: the kinematic tree (as RobotModel joints) and,
/// per link, the geometry its solid is made of, as the URDF describes it (no mesh is
/// loaded here; link_solid.h does that).
///
/// Frames: a link's frame L is its URDF link frame. A geometry element (<collision> or
/// <visual>) has its own frame G with pose X_LG = its <origin>; a mesh vertex v of the
/// file lands at X_LG (S v) in L, S = diag(scale). Box, cylinder and sphere primitives are
/// centred on G's origin (a cylinder's axis is G's z axis), as URDF defines them. Units:
/// metres and radians, as URDF's.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/robot/package_path.h"
#include "medspheres/robot_model.h"

namespace medspheres {

enum class PartShape { kMesh, kBox, kCylinder, kSphere, kCapsule };

/// One geometry element of a link.
struct LinkPart {
  PartShape shape = PartShape::kMesh;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< X_LG
  std::string uri;                                           ///< kMesh: filename as written
  std::string path;                                          ///< kMesh: the resolved file
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();           ///< kMesh: S
  /// kBox: the full sides; kCylinder and kCapsule: (radius, radius, length) (a capsule's
  /// length is its cylinder's, without the caps); kSphere: (r, r, r).
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
};

/// The geometry of one link: its <collision> elements, every one, in the URDF's order;
/// with UrdfReadOptions::from_visual its <visual> elements when it has no collision one.
struct UrdfLink {
  std::string name;
  std::vector<LinkPart> parts;  ///< empty: no geometry, no spheres
  bool from_visual = false;     ///< parts are the link's visual elements
};

struct UrdfReadOptions {
  PackageDirs packages;
  /// Use a link's <visual> elements where it has no <collision> element.
  bool from_visual = false;
};

/// A floating or planar joint from the URDF's root link, left out with that link (planners
/// take a fixed base): the model's root is the joint's child. Empty names: none.
struct FreeBase {
  std::string joint;  ///< the joint's name
  std::string type;   ///< "floating" or "planar"
  std::string link;   ///< the root link left out (it carries no geometry)
};

struct UrdfRobot {
  std::string path;             ///< the URDF file as given
  RobotModel model;             ///< name, root link, links (no spheres yet) and joints, URDF order
  std::vector<UrdfLink> links;  ///< same order as model.links
  FreeBase free_base;
};

/// The files \p robot was read from: its URDF, then each mesh file its links name (once).
std::vector<std::string> robot_input_files(const UrdfRobot& robot);

/// Reads the URDF in \p path with urdfdom. Links and joints keep the file's order.
/// \throws InputError whose source is \p path and whose message names the link or joint
///   and the problem: a file that is missing or not well-formed XML, anything urdfdom
///   reports as an error (its message is kept: a geometry it does not know, a malformed
///   vector, ...), a <capsule> without a radius > 0 and a length >= 0 (urdfdom 3 does not
///   know <capsule>: it is read here with tinyxml2), a link with an empty name, a joint
///   whose parent or child link does not exist, a link that is the child of two joints, a
///   joint cycle (no root, or links not reachable from the root), an unsupported joint type
///   (floating and planar are taken only from a root link without geometry or other joints,
///   and left out with it: UrdfRobot::free_base), a mesh name that cannot be resolved
///   (package_path.h), a primitive with a size that is not finite and > 0, or a mesh scale that is
///   not finite and non-zero.
UrdfRobot read_urdf(const std::string& path, const UrdfReadOptions& options = {});

/// The same from URDF text; \p source names it in errors and \p base_dir is the folder
/// relative mesh names are resolved against.
UrdfRobot parse_urdf(const std::string& xml, const std::string& source, const std::string& base_dir,
                     const UrdfReadOptions& options = {});

/// Checks that the robot file \p file (its model \p sets) has exactly the links of \p robot,
/// in any order. \throws InputError whose source is \p file, naming a link of the URDF that
/// it lacks, or saying that it has others.
void require_same_links(const RobotModel& sets, const UrdfRobot& robot, const std::string& file);

}  // namespace medspheres
