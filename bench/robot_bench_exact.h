#pragma once
// bench_robot's exact side: FCL's exact queries for the robot against the scene and itself,
// over the same pairs as medspheres::fcl::RobotBounds. A link's exact geometry is its mesh
// (BVHModel<OBBRSS>, link frame) and its sphere primitives (fcl::Sphere). Pairs whose
// world AABBs are farther apart than the margin are skipped (a broadphase: the AABBs
// contain the geometries, so the skip never changes the answer). FCL's meshes are surfaces:
// a sphere primitive wholly inside a mesh touches no triangle, so a sphere whose centre a
// mesh's solid holds (winding number, Solids) is at distance 0 from it; a sphere against a
// mesh with a solid is measured by its MeshQuery, not by FCL.

#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "medspheres/fcl/robot_bounds.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_set.h"

namespace medspheres::bench {

/// A link's exact geometry, in its frame.
struct ExactLink {
  std::shared_ptr<const fcl::MeshModel> mesh;  ///< may be null
  std::vector<Sphere> spheres;                 ///< sphere primitives
};

/// The solids of mesh geometries (links' and scene objects'), for the inside test.
using Solids = std::map<const ::fcl::CollisionGeometryd*, std::shared_ptr<const MeshQuery>>;

class ExactRobot {
 public:
  /// Exact geometry by link name; \p robot gives the geometries' order and the self pairs.
  /// With \p skip_beyond, collide() also skips a scene pair when the part's bounding ball
  /// is certainly farther than the margin from the object (fcl::balls_near: an octree's
  /// occupied cells rather than its root cube's AABB), as robot_collide does.
  ExactRobot(const fcl::RobotBounds& robot, const std::map<std::string, ExactLink>& links,
             const std::vector<const ::fcl::CollisionObjectd*>& scene, Solids solids = {},
             bool skip_beyond = false);

  /// Links of the robot without exact geometry (left out of every exact query).
  std::size_t missing_links() const { return missing_; }

  /// Whether some pair is within \p margin at the poses \p X (RobotBounds::poses):
  /// FCL's distance per pair with the margin preset as min_distance (FCL prunes at it), in
  /// RobotBounds' pair order, stopping at the first pair within it.
  bool collide(const std::vector<::fcl::Transform3d>& X, bool include_self, double margin);

  /// How many pairs are within \p margin at the poses \p X, each by FCL's distance with the
  /// margin preset (AABBs farther apart skipped), with no stop: every link against the scene
  /// objects whose entry of \p use is set, then the self pairs when \p include_self.
  std::size_t pairs_within(const std::vector<::fcl::Transform3d>& X, const std::vector<char>& use,
                           bool include_self, double margin);

  /// The smallest exact distance over all pairs (0 when some pair touches or overlaps:
  /// FCL's negative answers are clamped), pairs visited by increasing AABB distance.
  double distance(const std::vector<::fcl::Transform3d>& X, bool include_self);

  /// The exact distance of one pair (geometry index \p link against geometry \p other when
  /// \p self, else against scene object \p other), clamped to 0.
  double pair(const std::vector<::fcl::Transform3d>& X, std::size_t link, std::size_t other,
              bool self);

  /// The self pairs (geometry indices) within \p margin at the poses \p X.
  std::vector<std::pair<std::size_t, std::size_t>> self_pairs_within(
      const std::vector<::fcl::Transform3d>& X, double margin);

 private:
  struct Part {
    std::unique_ptr<::fcl::CollisionObjectd> object;
    ::fcl::Transform3d X_LP;  // the part in its link's frame
  };
  struct Candidate {
    double aabb_distance;
    const ::fcl::CollisionObjectd *a, *b;
    std::size_t link, other;  // geometry indices (other: scene index unless self)
  };
  void pose(const std::vector<::fcl::Transform3d>& X);
  void add(std::vector<Candidate>& out, const ::fcl::CollisionObjectd* a,
           const ::fcl::CollisionObjectd* b, std::size_t link, std::size_t other,
           double below) const;
  std::vector<Candidate> candidates(bool include_scene, std::size_t self_from, std::size_t self_to,
                                    double below) const;

  const fcl::RobotBounds& robot_;
  std::vector<const ::fcl::CollisionObjectd*> scene_;
  std::vector<std::vector<Part>> links_;  // by geometry index; empty: no exact geometry
  std::size_t missing_ = 0;
  Solids solids_;
  bool skip_beyond_ = false;
  double pair_distance(const ::fcl::CollisionObjectd* a, const ::fcl::CollisionObjectd* b,
                       double below) const;
  std::optional<double> sphere_to_solid(const ::fcl::CollisionObjectd* s,
                                        const ::fcl::CollisionObjectd* m) const;
};

}  // namespace medspheres::bench
