#pragma once
// Private to the fcl_adapter target: the test that distance() and collide() make before
// they walk a sphere tree.

#include <fcl/narrowphase/collision_object.h>

#include "medspheres/fcl/sphere_set_geometry.h"

namespace medspheres::fcl::detail {

/// True when every point of the sphere set \p s (at X_WS) is certainly farther than
/// \p margin from every point of \p g (at X_WG), shown by the set's bounding ball against
/// g's bound alone: another sphere set's bounding ball, a BVHModel's root bounding volume
/// (a finished model of triangles), or the solid of a Box, Sphere, Capsule or Cylinder.
/// Certainly: the gap exceeds the margin by gap_allowance. False whenever that is not
/// shown, and for every other geometry (an octree's bound is its whole root cube; the
/// shapes whose sphere answers come from GJK within a tolerance are left to the walk).
/// Then no sphere of the set is within the margin of g, so the walk would find nothing
/// at or below it: a preset min_distance <= margin stays, and there is no contact (margin
/// 0; touching is a contact). A margin that is not finite gives false.
/// \p g_set is g as a sphere set (as_sphere_set(&g)), which the caller knows already.
bool pair_beyond(const SphereSetGeometry& s, const ::fcl::Transform3d& X_WS,
                 const ::fcl::CollisionGeometryd& g, const SphereSetGeometry* g_set,
                 const ::fcl::Transform3d& X_WG, double margin);

}  // namespace medspheres::fcl::detail
