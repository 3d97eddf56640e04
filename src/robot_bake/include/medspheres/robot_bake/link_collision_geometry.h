#pragma once
/// \file
/// The two views of a robot's links that the self-collision matrix compares, each indexed
/// by the model's link order and posed by KinematicTree::link_poses (X_WL per link):
/// - LinkSolids: each link's exact solid (its meshed parts and sphere primitives, link
///   frame) held as a fcl::BoundedGeometry: the model's inner and covering sets bound the
///   distance between two solids, and FCL's exact mesh distance settles what they leave
///   undecided. A link without a covering set (a bake with --no-outer) gets the smallest
///   ball around its mesh's vertices (which holds the mesh's convex hull, and so its
///   surface) as one; a link without an inner set gets its sphere primitives or, failing
///   those, the mesh's vertices as points.
/// - PlannerSpheres: the spheres a planner file carries with each link's self-collision
///   buffer, as cuRobo checks them: spheres i of link a and j of link b collide when
///   |c_i - c_j| <= r_i + r_j + buffer_a + buffer_b (a negative buffer shrinks).
///
/// Touching: two solids within distance m "are within m" (m = 0: touching collides); two
/// sphere sets collide when two of their spheres touch or overlap (SphereTree's collide()).
/// Exact geometry: a sphere primitive of a link that also has meshed parts joins the mesh as
/// an icosphere scaled to contain the sphere (its facets outside it), so the exact side never
/// misses a contact of the primitive. Threads: immutable after construction; const queries
/// may run from many threads at once.

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/formats/robot_spheres.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot_model.h"
#include "medspheres/sphere_tree.h"

namespace medspheres {

/// Work done by the exact side, summed over queries.
struct SolidQueryCounts {
  std::size_t queries = 0;       ///< pair questions asked
  std::size_t by_ball = 0;       ///< answered by the two bounding balls alone
  std::size_t by_bounds = 0;     ///< answered by the inner and covering sets
  std::size_t mesh_queries = 0;  ///< answered by FCL's exact mesh distance
  SolidQueryCounts& operator+=(const SolidQueryCounts& o);
};

class LinkSolids {
 public:
  /// \p solids: load_link_solids of the robot the model was baked from (matched by link
  /// name; links without a solid have no geometry here).
  /// \throws InputError naming the link when a solid has no triangles and no spheres but
  ///   the model gives it spheres, or a set is invalid.
  LinkSolids(const RobotModel& model, const std::vector<LinkSolid>& solids);

  std::size_t size() const noexcept { return geometry_.size(); }
  /// Whether link \p i (model order) has a solid.
  bool has(std::size_t i) const { return geometry_.at(i).has_value(); }
  /// The link's covering ball in its frame (contains its solid).
  const Sphere& ball(std::size_t i) const { return balls_.at(i); }

  /// Whether the solids of links \p a and \p b are within \p margin (>= 0) at the poses
  /// \p X (one per model link). Both links must have solids.
  bool within(const std::vector<Eigen::Isometry3d>& X, std::size_t a, std::size_t b, double margin,
              SolidQueryCounts* counts = nullptr) const;

 private:
  std::vector<std::optional<fcl::BoundedGeometry>> geometry_;
  std::vector<Sphere> balls_;
};

class PlannerSpheres {
 public:
  /// \p spheres by link name (links of the model), with \p buffer[link] (metres; missing
  /// links 0).
  /// \throws InputError naming a link that \p model lacks.
  PlannerSpheres(const RobotModel& model, const formats::RobotSpheres& spheres,
                 const std::map<std::string, double>& buffer = {});

  /// Whether link \p i (model order) has spheres.
  bool has(std::size_t i) const { return !trees_.at(i).empty(); }
  /// Whether two spheres of links \p a and \p b collide (touch or overlap, the buffers
  /// applied) at the poses \p X.
  bool collide(const std::vector<Eigen::Isometry3d>& X, std::size_t a, std::size_t b) const;
  /// The deepest overlap of two spheres of links \p a and \p b, the buffers applied:
  /// max (r_i + r_j + buffer_a + buffer_b - |c_i - c_j|), metres (> 0: they overlap), at the
  /// poses \p X; -infinity when a link has no spheres.
  double penetration(const std::vector<Eigen::Isometry3d>& X, std::size_t a, std::size_t b) const;
  /// The same spheres with other buffers.
  PlannerSpheres with_buffer(const std::map<std::string, double>& buffer) const;

 private:
  std::vector<std::string> names_;
  std::vector<SphereTree> trees_;
  std::vector<Sphere> balls_;   // each link's root ball, link frame
  std::vector<double> buffer_;  // by link
};

}  // namespace medspheres
