#pragma once
/// \file
/// Scene: what render and view draw, in the world frame W: one part for a mesh and its
/// sphere sets, or one part per link of a robot placed at its link poses. Units: the
/// mesh's and the sets' (metres for a robot).

#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "medspheres/robot/link_solid.h"
#include "medspheres/robot_model.h"
#include "medspheres/sphere_set.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres::render {

/// A mesh and the sphere sets fitted to it, placed in W.
struct ScenePart {
  std::string name;                                        ///< the link's name; "" for a lone mesh
  TriangleMesh mesh;                                       ///< in W
  std::vector<Sphere> inner, outer;                        ///< in W
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< X_WL (identity: a lone mesh)
};

struct Scene {
  std::vector<ScenePart> parts;
  std::vector<std::string> warnings;  ///< what was left out, and why
};

/// A lone mesh with its inner and outer sets (either may be empty), W = their frame.
Scene mesh_scene(const TriangleMesh& mesh, const SphereSet& inner, const SphereSet& outer = {});

/// A robot at link poses \p X_WL (one per link of \p model, in its order, as
/// KinematicTree::link_poses gives them): a part per link with a solid or spheres.
/// \p solids are in link frames (load_link_solids; may be empty: spheres only; a sphere
/// element of a link is meshed as an icosphere inside it); \p spheres are in link frames,
/// by link name. A solid or sphere set whose link is not in \p model is left out with a
/// warning (a sphere file made for a variant of the robot). \throws std::invalid_argument
/// when \p X_WL has the wrong size.
Scene robot_scene(const RobotModel& model, const std::vector<Eigen::Isometry3d>& X_WL,
                  const std::vector<LinkSolid>& solids,
                  const std::map<std::string, LinkSpheres>& spheres, const std::string& source);

/// Every part's mesh, concatenated in part order (indices shifted).
TriangleMesh merged_mesh(const Scene& scene);

/// Which set of each part: its inner or its outer one; automatic: the outer set where the
/// part has one (a covering set shows what a planner checks against), else the inner.
enum class SetChoice { automatic, inner, outer };

/// The chosen set of every part, concatenated in part order.
SphereSet merged_spheres(const Scene& scene, SetChoice choice);

}  // namespace medspheres::render
