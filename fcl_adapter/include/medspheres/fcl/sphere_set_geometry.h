#pragma once
/// \file
/// SphereSetGeometry: a sphere set as an FCL collision geometry, and distance() and
/// collide() with exactly the signatures of fcl::distance and fcl::collide (double).
///
/// \code
/// #include <medspheres/fcl/sphere_set_geometry.h>
/// #include <medspheres/io.h>
/// medspheres::SphereSet s = medspheres::load_sphere_set("link.spheres.json");
/// auto g = std::make_shared<medspheres::fcl::SphereSetGeometry>(s);
/// fcl::CollisionObjectd a(g, X_WA), b(g, X_WB);
/// fcl::DistanceRequestd req; req.enable_nearest_points = true; fcl::DistanceResultd res;
/// double d = medspheres::fcl::distance(&a, &b, req, res);
/// \endcode
///
/// Pairs with a SphereSetGeometry run on its sphere tree (medspheres/sphere_tree.h)
/// against
///   - another SphereSetGeometry;
///   - an fcl::BVHModel of triangles of any BV type (AABB, OBB, RSS, kIOS, OBBRSS,
///     KDOP16/18/24), traversing the model's own hierarchy. Triangles are surfaces, as in
///     FCL (a sphere set inside a closed mesh touching no triangle does not collide). The
///     model must be finished (endModel()), its BVs in the model's frame (not after
///     makeParentRelative());
///   - every FCL primitive (Box, Sphere, Ellipsoid, Capsule, Cone, Cylinder, Convex, Plane,
///     Halfspace): each sphere gets FCL's own fcl::Sphere narrowphase answer (fcl::distance
///     when apart, else fcl::collide's depth and normal; for Ellipsoid, Cone and Convex,
///     libccd's GJK/EPA within the request's distance_tolerance and gjk_tolerance); Plane
///     and Halfspace in closed form with FCL's collision conventions;
///   - an fcl::OcTree: its occupied cells as boxes, with FCL's rules (free and uncertain
///     subtrees skipped).
/// Every other pair goes unchanged to fcl::distance or fcl::collide (libfcl's result). A
/// sphere set against anything else (fcl::TriangleP, a BVHModel of points, a user-defined
/// geometry) throws std::invalid_argument.
///
/// Guard: to libfcl (a direct fcl::distance or fcl::collide call, or FCL's default
/// callbacks without fcl_overloads.h) a SphereSetGeometry is an fcl::Box: GEOM_BOX,
/// OT_GEOM, centred on the origin of its frame, `side` twice the largest |coordinate| +
/// radius per axis (rounded up, at most the largest finite double). Where libfcl supports
/// a box it then never misses a collision of the spheres, may report collisions they do
/// not have, and reports distances no larger than theirs; where it does not, it does what
/// it does for a box (sphere_set_geometry.cpp lists the cases). Identify a sphere set
/// with as_sphere_set(), not with getNodeType().
///
/// Frames and units: tf1, tf2 and the CollisionObjects' transforms pose the geometries
/// in FCL's world frame W; results are in W, in the sphere set's units. Inside namespace
/// medspheres, FCL's namespace must be written ::fcl, since medspheres::fcl is this one.
///
/// Result conventions (FCL's):
///   - points in W; result.o1, o2 are the caller's geometries in the caller's order; b1, b2
///     the primitive ids: the sphere's index in its SphereSet, the triangle index of a
///     BVHModel, the query cell id of an octree (fcl::OcTree::getNodeByQueryCellId),
///     Contact::NONE (-1) for a primitive;
///   - a contact normal points from o1 to o2; penetration_depth >= 0; the position is the
///     midpoint of the two objects' deepest points (sphere_tree.h). Touching is collision;
///   - a preset result.min_distance is respected: only a strictly closer pair replaces it,
///     and it prunes the search (MoveIt presets it as a threshold). Before any walk, the
///     set's bounding ball is tested against the other geometry's bound (a sphere set's
///     bounding ball, a BVHModel's root volume, a box, sphere, capsule or cylinder); a pair
///     certainly farther apart than min_distance (by 1e-12 of the magnitudes) returns at
///     once, as collide() does for a pair certainly apart. The answer is the walk's;
///   - enable_nearest_points: points written only when set. They are the witness points
///     of the reported pair (sphere_tree.h); for a sphere and a primitive, p_sphere =
///     c + r n and p_other = p_sphere + d n, d the distance, n the unit direction of FCL's
///     answer;
///   - enable_signed_distance: when the objects overlap, min_distance is minus the largest
///     penetration depth over all overlapping pairs, at the two deepest points. Unset, the
///     search stops at the first overlapping pair, min_distance its signed distance (<= 0,
///     FCL's "implementation defined" negative value);
///   - abs_err and rel_err prune as in FCL's BVH distance (guarantee and ties:
///     sphere_tree.h);
///   - num_max_contacts caps result.numContacts(), contacts already in the result
///     included; 0 returns 0 at once, and a request already satisfied returns at once;
///     the return value is result.numContacts(); with enable_contact false, contacts carry
///     only o1, o2, b1, b2;
///   - a geometry that is not occupied (isOccupied()) collides with nothing; enable_cost
///     is ignored (sphere sets have no cost sources).
///
/// Thread safety: distance() and collide() only read the geometries; any number of
/// threads may query the same geometries at once. Building an fcl::CollisionObject calls
/// computeLocalAABB(), which writes the geometry's AABB members (as for every FCL
/// geometry): build the objects before sharing a geometry across threads.

#include <cstddef>
#include <memory>

#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>
#include <fcl/narrowphase/distance_request.h>
#include <fcl/narrowphase/distance_result.h>

#include "medspheres/sphere_set.h"
#include "medspheres/sphere_tree.h"

namespace medspheres::fcl {

class SphereSetGeometry final : public ::fcl::Box<double> {
 public:
  /// Copies \p set and builds its sphere tree (RSS nodes by default).
  /// \throws InputError (source "sphere set") for a sphere with a non-finite coordinate
  ///   or a radius that is not finite and > 0.
  /// \throws std::invalid_argument for an empty set (FCL geometries are not empty) or
  ///   bad options.
  explicit SphereSetGeometry(const SphereSet& set, const SphereTreeOptions& options = {});

  const SphereSet& sphere_set() const noexcept { return set_; }
  const SphereTree& tree() const noexcept { return tree_; }
  /// A ball, in the set's frame, that contains every sphere: the tree root's bounding
  /// ball (SphereTree::bounding_ball(0)). distance() and collide() test it against the
  /// other geometry's bound before they walk the tree.
  const Sphere& bounding_ball() const noexcept { return bound_; }

  /// Sets aabb_local to the smallest axis-aligned box of the spheres in the geometry's
  /// frame, aabb_center to its centre, and aabb_radius to the radius of the smallest
  /// ball about aabb_center that contains every sphere, max_i |c_i - aabb_center| + r_i,
  /// rounded up. fcl::CollisionObject::computeAABB() uses the last two for rotated
  /// objects, so the world box contains every sphere at any pose.
  void computeLocalAABB() override;

  /// Mass properties of a union of balls are not provided: these throw std::logic_error
  /// instead of reporting the guard box's values.
  double computeVolume() const override;
  ::fcl::Vector3d computeCOM() const override;
  ::fcl::Matrix3d computeMomentofInertia() const override;

 private:
  SphereSet set_;
  SphereTree tree_;
  Sphere bound_;
};

/// The SphereSetGeometry behind \p geometry, or nullptr when it is something else.
const SphereSetGeometry* as_sphere_set(const ::fcl::CollisionGeometryd* geometry) noexcept;

/// fcl::distance for double, with sphere sets (see the file comment).
double distance(const ::fcl::CollisionObjectd* o1, const ::fcl::CollisionObjectd* o2,
                const ::fcl::DistanceRequestd& request, ::fcl::DistanceResultd& result);

double distance(const ::fcl::CollisionGeometryd* o1, const ::fcl::Transform3d& tf1,
                const ::fcl::CollisionGeometryd* o2, const ::fcl::Transform3d& tf2,
                const ::fcl::DistanceRequestd& request, ::fcl::DistanceResultd& result);

/// fcl::collide for double, with sphere sets (see the file comment).
std::size_t collide(const ::fcl::CollisionObjectd* o1, const ::fcl::CollisionObjectd* o2,
                    const ::fcl::CollisionRequestd& request, ::fcl::CollisionResultd& result);

std::size_t collide(const ::fcl::CollisionGeometryd* o1, const ::fcl::Transform3d& tf1,
                    const ::fcl::CollisionGeometryd* o2, const ::fcl::Transform3d& tf2,
                    const ::fcl::CollisionRequestd& request, ::fcl::CollisionResultd& result);

}  // namespace medspheres::fcl
