#pragma once
// Private to the fcl_adapter target: what the opt-in fcl:: overloads need to know from
// the dispatch.

#include <functional>

#include <fcl/narrowphase/collision_object.h>

#include "medspheres/proximity_target.h"

namespace medspheres::fcl::detail {

/// True when medspheres::fcl::distance and collide answer the pair on a sphere tree: one
/// geometry is a sphere set, the other a sphere set or a supported geometry (see
/// sphere_set_geometry.h), and both transforms are finite. Also true when a geometry is
/// null, so that the caller gets medspheres' error rather than libfcl's crash.
bool answered_on_spheres(const ::fcl::CollisionGeometryd* o1, const ::fcl::Transform3d& tf1,
                         const ::fcl::CollisionGeometryd* o2, const ::fcl::Transform3d& tf2);

/// Calls f with the ProximityTarget view of \p g (a BVHModel of triangles, an FCL
/// primitive or an octree; FCL's default narrowphase tolerances), as the dispatch sees it.
/// \throws std::invalid_argument for a geometry the dispatch does not support.
void with_target_view(const ::fcl::CollisionGeometryd& g,
                      const std::function<void(const ProximityTarget&)>& f);

}  // namespace medspheres::fcl::detail
