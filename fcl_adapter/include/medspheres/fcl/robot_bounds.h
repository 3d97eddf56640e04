#pragma once
/// \file
/// Certified distance bounds and three-valued collision for a whole robot: every link a
/// BoundedGeometry (bounded_geometry.h), posed by forward kinematics from a joint vector,
/// against a scene of FCL collision objects and against itself.
///
/// Self-collision pairs: every two links with a geometry, except the parent and child of a
/// joint (adjacent links) and the pairs the caller disables (for instance an SRDF's
/// <disable_collisions>, read by medspheres/formats/srdf_disabled_collisions.h).
/// Minimum: the smallest lower and the smallest upper over the pairs bound the smallest
/// exact distance (min of lower bounds <= min of distances <= min of upper bounds).
///
/// Frames: q as KinematicTree::link_poses (forward_kinematics.h), X_WB the base pose; the
/// scene objects' transforms are in W. Errors: InputError naming the link for a link with
/// one set empty and the other not, a link whose outer set is not certified (unless
/// allowed), or a disabled pair naming an unknown link; std::invalid_argument for a bad q
/// or a null scene object.
/// Threads: immutable after construction; queries may run from many threads at once.

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "medspheres/fcl/balls_near.h"
#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/robot_model.h"

namespace medspheres::fcl {

/// The order in which robot_collide walks the self pairs, and the witnesses it tests
/// first; they change how soon a colliding configuration is found, never an answer.
/// samples = 0: geometry order (the pairs of geometry i before those of i + 1), all before
/// the scene, and no witnesses. samples > 0: the constructor checks that many seeded
/// configurations (sample_configurations) with the pairs' sphere bounds (decide() at
/// \p margin). Each colliding decision names the pair of inner spheres that proved it; of
/// these the witnesses (RobotBounds::witnesses()) are taken greedily: the one within the
/// margin in the most samples, then the one within it in the most of the rest, and so on
/// while one adds at least samples / 2000 samples (and 1), up to max_witnesses. Then the
/// pairs, greedily too: first the pair certainly colliding in the most samples that no
/// witness holds in (robot_collide walks pairs only in such configurations), then the
/// pair colliding in the most of the rest, and so on; then in the same way over the
/// samples those pairs leave (seen_colliding() pairs in all); the pairs never seen
/// colliding follow in geometry order, and robot_collide walks them after the scene.
struct SelfPairOrder {
  std::size_t samples = 0;
  double margin = 0.0;  ///< finite, >= 0
  unsigned seed = 1;
  std::size_t max_witnesses = 256;
};

/// Two inner spheres, of the geometries a and b of a self pair, each in its link's frame:
/// whenever they are within the margin of each other, the two links are (a sphere of an
/// inner set is a part of the link's solid).
struct SelfWitness {
  std::size_t a = 0, b = 0;  ///< indices into RobotBounds::geometries()
  Sphere in_a, in_b;
};

/// Whether the witness's two spheres are certainly within \p margin of each other (by
/// balls_within) at the poses \p X (RobotBounds::poses, indexed by geometry).
bool witness_holds(const SelfWitness& w, const std::vector<::fcl::Transform3d>& X, double margin);

class RobotBounds {
 public:
  /// Links with both sets empty have no geometry and are left out. \p meshes: exact meshes
  /// by link name (optional, link frame). \p disabled: link pairs excluded from
  /// self-collision, in either order.
  RobotBounds(const RobotModel& model,
              const std::map<std::string, std::shared_ptr<const MeshModel>>& meshes = {},
              const std::vector<std::pair<std::string, std::string>>& disabled = {},
              const BoundedGeometryOptions& options = {}, const SelfPairOrder& order = {});

  const KinematicTree& kinematics() const noexcept { return tree_; }
  /// The links with a geometry, and the index of each in kinematics().link_names().
  const std::vector<BoundedGeometry>& geometries() const noexcept { return geometries_; }
  const std::vector<std::size_t>& link_of() const noexcept { return link_of_; }
  /// Self-collision pairs, as indices into geometries(), first < second, in the order of
  /// the constructor's SelfPairOrder.
  const std::vector<std::pair<std::size_t, std::size_t>>& self_pairs() const noexcept {
    return self_pairs_;
  }
  /// With a SelfPairOrder of samples > 0: how many self pairs (the first ones) were seen
  /// certainly colliding in its samples; the others follow. Else self_pairs().size().
  std::size_t seen_colliding() const noexcept { return seen_colliding_; }
  /// With a SelfPairOrder of samples > 0: the witnesses it picked, in the order taken
  /// (robot_collide tests them first). Else empty.
  const std::vector<SelfWitness>& witnesses() const noexcept { return witnesses_; }
  /// X_WL of every geometry's link (in geometries() order).
  std::vector<::fcl::Transform3d> poses(const Eigen::VectorXd& q,
                                        const Eigen::Isometry3d& X_WB) const;

 private:
  KinematicTree tree_;
  std::vector<BoundedGeometry> geometries_;
  std::vector<std::size_t> link_of_;
  std::vector<std::pair<std::size_t, std::size_t>> self_pairs_;
  std::size_t seen_colliding_ = 0;
  std::vector<SelfWitness> witnesses_;

  void order_self_pairs(const RobotModel& model, const SelfPairOrder& order);
};

/// \p n joint vectors for \p tree (KinematicTree::joint_names order), each entry uniform
/// within its joint's limits ([-pi, pi] for a continuous joint or one without limits),
/// drawn in order from std::mt19937(seed): configuration by configuration, joint by joint.
std::vector<Eigen::VectorXd> sample_configurations(const RobotModel& model,
                                                   const KinematicTree& tree, std::size_t n,
                                                   unsigned seed);

/// One pair's bounds: geometry index `link`; `other` a geometry index (self) or an index
/// into the scene.
struct LinkPairBounds {
  std::size_t link = 0;
  std::size_t other = 0;
  bool self = false;
  DistanceBounds bounds;
};

struct RobotBoundsResult {
  DistanceBounds minimum;             ///< over all pairs (infinite when there is none)
  std::vector<LinkPairBounds> pairs;  ///< every pair, when asked for
  bool certified = true;              ///< false when a link was accepted uncertified
};

/// Bounds of the robot at q against every scene object, and of its self-collision pairs
/// when \p include_self.
RobotBoundsResult robot_bounds(const RobotBounds& robot, const Eigen::VectorXd& q,
                               const std::vector<const ::fcl::CollisionObjectd*>& scene,
                               bool include_self, bool per_pair = false,
                               const Eigen::Isometry3d& X_WB = Eigen::Isometry3d::Identity());

struct RobotCollideResult {
  /// colliding when a pair is, free when every pair is, else undecided (a pair was
  /// undecided and had no mesh to fall back on).
  BoundsVerdict verdict = BoundsVerdict::free;
  std::size_t pairs_tested = 0;    ///< pairs whose sphere bounds were walked
  bool by_witness = false;         ///< a witness decided "colliding", before any walk
  std::size_t mesh_fallbacks = 0;  ///< pairs answered by the exact meshes
  bool certified = true;
};

/// Three-valued collision of the robot at q against the scene (and itself) within margin.
/// With include_self, first the witnesses (RobotBounds::witnesses()), in order: two
/// spheres certainly within the margin (balls_within) decide "colliding" (by_witness) with
/// no walk.
/// Then every pair's sphere bounds (decide()): the first seen_colliding() self pairs, the
/// scene, then the other self pairs (self_pairs() order), stopping at the first certainly
/// colliding pair; a self pair whose links' outer root balls are farther apart than the
/// margin, and a scene pair whose link ball is (balls_near), are free without a walk. Only
/// when no pair certainly collides are the undecided pairs settled by the exact meshes
/// (settle()), stopping at the first colliding one.
RobotCollideResult robot_collide(const RobotBounds& robot, const Eigen::VectorXd& q,
                                 const std::vector<const ::fcl::CollisionObjectd*>& scene,
                                 bool include_self, double margin = 0.0,
                                 const Eigen::Isometry3d& X_WB = Eigen::Isometry3d::Identity());

}  // namespace medspheres::fcl
