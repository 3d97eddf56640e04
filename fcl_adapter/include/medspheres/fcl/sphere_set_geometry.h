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
/// Why our own entry points. libfcl dispatches fcl::distance and fcl::collide through
/// tables indexed by its closed NODE_TYPE enum, built into the shared library; no one can
/// add a row for a new geometry. medspheres::fcl::distance and collide therefore run
/// every pair that involves a SphereSetGeometry on its sphere tree (SphereTree, see
/// medspheres/sphere_tree.h), against
///   - another SphereSetGeometry;
///   - an fcl::BVHModel of triangles, of any BV type (AABB, OBB, RSS, kIOS, OBBRSS,
///     KDOP16/18/24): the model's own hierarchy is traversed, its leaves are triangles,
///     treated as surfaces (as FCL does: a sphere set inside a closed mesh touching no
///     triangle does not collide with it). The model must be finished (endModel()) and
///     its bounding volumes in the model's frame, as endModel() leaves them (not after
///     makeParentRelative());
///   - every FCL primitive: Box, Sphere, Ellipsoid, Capsule, Cone, Cylinder, Convex,
///     Plane and Halfspace. Each sphere is answered by FCL's own narrowphase for an
///     fcl::Sphere: fcl::distance when apart, else the depth and normal of fcl::collide's
///     contact; for Ellipsoid, Cone and Convex that is libccd's GJK/EPA, within the
///     request's distance_tolerance and gjk_tolerance (in the tests its distances move by
///     up to 1e-4 between two frames of one configuration). Plane and Halfspace are
///     answered in closed form with FCL's own collision conventions (libfcl's
///     sphere-plane and sphere-halfspace distance is not usable);
///   - an fcl::OcTree: its occupied cells, as boxes, with FCL's rules (a cell counts when
///     it is occupied; free and uncertain subtrees are skipped).
/// Every other pair goes unchanged to fcl::distance or fcl::collide, so its result is
/// exactly libfcl's. A sphere set against anything else (fcl::TriangleP, a BVHModel of
/// points, a user-defined geometry) throws std::invalid_argument rather than being
/// forwarded: libfcl would report it as "no collision".
///
/// Guard: a sphere set that reaches libfcl by mistake. Code that calls fcl::distance or
/// fcl::collide directly (or FCL's default broadphase callbacks, compiled without
/// fcl_overloads.h) sends a SphereSetGeometry to libfcl, which has no node type for it;
/// a geometry of unknown type is reported as "no collision". So SphereSetGeometry
/// derives from fcl::CollisionGeometry<double> through fcl::Box<double>, and presents
/// itself to libfcl as a box centred on the origin of its frame that encloses all its
/// spheres: getNodeType() is GEOM_BOX, getObjectType() OT_GEOM, `side` twice the largest
/// |coordinate| + radius along each axis (rounded up; at most the largest finite double,
/// so a set reaching beyond half of it from the origin gets the largest finite box, which
/// then cannot hold all of it). libfcl then answers exactly as for that
/// fcl::Box: wherever it supports a box, it never misses a collision of the spheres, may
/// report collisions they do not have, and reports distances no larger than theirs.
/// Where libfcl does not support a box it does what it does for its own box: it prints
/// "... is not supported" and reports no collision (against fcl::TriangleP) or a
/// distance of the largest double (distance against a BVHModel of AABB, OBB or KDOP
/// nodes), and libfcl 0.7's distance against fcl::Plane or fcl::Halfspace crashes for a
/// box as for every shape. (A box was chosen over a tighter fcl::Convex because libfcl
/// 0.7 also crashes in collide() between a Convex and a Plane.) Identify a sphere set
/// with as_sphere_set(), not with getNodeType().
///
/// Frames and units: tf1, tf2 and the CollisionObjects' transforms pose the geometries
/// in FCL's world frame W; results are in W, in the sphere set's units. Inside namespace
/// medspheres, FCL's namespace must be written ::fcl, since medspheres::fcl is this one.
///
/// Result conventions (FCL's):
///   - nearest points and contact positions are in world coordinates;
///   - result.o1 and result.o2 are the caller's geometries in the caller's order, and
///     b1, b2 are the primitive ids: the sphere's index in its SphereSet for a sphere
///     set, the triangle index for a BVHModel, the query cell id for an octree
///     (fcl::OcTree::getNodeByQueryCellId), Contact::NONE (-1) for a primitive;
///   - a contact normal points from o1 to o2; penetration_depth >= 0; the position is
///     the midpoint of the two objects' deepest points (see medspheres/sphere_tree.h);
///   - a preset result.min_distance is respected: only a pair strictly closer replaces
///     it, and it prunes the search (MoveIt presets it as a threshold);
///   - enable_nearest_points: the points are written only when set. They are the
///     witness points of the reported pair (see medspheres/sphere_tree.h): for a sphere
///     and a primitive, p_sphere = c + r n and p_other = p_sphere + d n, with d the
///     distance and n the unit direction from FCL's answer;
///   - enable_signed_distance: when the objects overlap, min_distance is minus the
///     largest penetration depth over all overlapping pairs, and the nearest points are
///     the two deepest points. When it is not set and the objects overlap, the search
///     stops at the first overlapping pair and min_distance is that pair's signed
///     distance (<= 0, FCL's "implementation defined" negative value);
///   - abs_err and rel_err prune as in FCL's BVH distance (see sphere_tree.h for the
///     guarantee, and for ties);
///   - num_max_contacts caps result.numContacts() (contacts already in the result
///     count, as in FCL); with enable_contact false, contacts carry only o1, o2, b1, b2;
///     num_max_contacts == 0 returns 0 at once; the return value is
///     result.numContacts(), and a request already satisfied returns at once;
///   - a geometry that is not occupied (fcl::CollisionGeometry::isOccupied()) collides
///     with nothing; enable_cost is ignored (no cost sources for sphere sets).
/// Touching is collision, as in FCL's sphere tests.
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
