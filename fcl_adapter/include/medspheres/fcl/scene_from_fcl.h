#pragma once
/// \file
/// A check::Scene (medspheres/check/scene.h) from FCL collision objects, so that a caller
/// who holds its world as FCL objects hands the same objects to the robot checker.
///
/// Taken over: boxes, spheres, capsules and cylinders (FCL's conventions: centred on the
/// object's frame, capsule and cylinder along its z axis, `lz` the axis length), triangle
/// meshes (BVHModel with AABB, OBB, RSS or OBBRSS nodes; a surface, as in FCL), and
/// octrees: the leaves FCL counts as occupied (OcTree::toBoxes, isNodeOccupied) as cubes,
/// axis-aligned cells when the object is not rotated, boxes otherwise (so one FCL object
/// may give several scene objects: `source` maps them back). Frames: W, as the objects'
/// transforms.
/// Errors: std::invalid_argument naming the object's index for a null object or a
/// geometry of another kind (cones, planes, half-spaces, convex, ellipsoids).

#include <vector>

#include <fcl/narrowphase/collision_object.h>

#include "medspheres/check/scene.h"

namespace medspheres::fcl {

struct FclScene {
  check::Scene scene;
  std::vector<std::size_t> source;  ///< per scene object: its index in the FCL objects
};

FclScene scene_from_fcl(const std::vector<const ::fcl::CollisionObjectd*>& objects);

}  // namespace medspheres::fcl
