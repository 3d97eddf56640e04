#pragma once
/// \file
/// Which balls may come within a margin of an FCL collision object: a broadphase for many
/// balls (a robot's links' bounding balls) against one scene object, tighter than the
/// object's AABB. An octree's AABB is its whole root cube (kilometres across for
/// centimetre cells), so every ball would need the full octree walk; here the octree's
/// cells (or a mesh's BVH) are searched once for all the balls.
///
/// Frames: ball centres and the object's transform in W. Errors: std::invalid_argument for
/// an object without geometry, or a geometry medspheres::fcl::distance does not accept
/// beside a sphere set. Threads: reads the object only; safe from many threads.

#include <vector>

#include <fcl/narrowphase/collision_object.h>

#include "medspheres/sphere_set.h"

namespace medspheres::fcl {

/// True when the balls \p a and \p b (one frame) are certainly farther apart than
/// \p margin, so that all they contain is: their gap is computed in doubles, so it must
/// exceed the margin by 1e-12 of the magnitudes involved, far above its few ulps of error.
bool balls_apart(const Sphere& a, const Sphere& b, double margin);

/// True when the balls \p a and \p b (one frame) are certainly within \p margin of each
/// other: their gap, computed in doubles, is below the margin by the same allowance.
bool balls_within(const Sphere& a, const Sphere& b, double margin);

/// For each ball of \p balls_W: 0 only when no point of the object's geometry lies within
/// the ball's radius plus \p margin of its centre (certainly: with a rounding allowance),
/// else 1. The test: the object's root bounding volume (its local AABB for a primitive),
/// then, for a mesh or an octree, a search of its hierarchy (node bounds, then the
/// primitives near a ball), cut at a few thousand nodes, after which the balls still open
/// count as near. Boxes and octree cells are solids, meshes surfaces (as in FCL).
std::vector<char> balls_near(const ::fcl::CollisionObjectd& object,
                             const std::vector<Sphere>& balls_W, double margin);

}  // namespace medspheres::fcl
