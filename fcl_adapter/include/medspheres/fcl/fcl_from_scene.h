#pragma once
/// \file
/// FCL collision objects of a check::Scene (medspheres/check/scene.h): the way back of
/// scene_from_fcl.h, so that a caller who holds the world as a check::Scene (the Python
/// module's CheckScene) hands it to CertifiedChecker, whose mesh fallback queries FCL.
///
/// Spheres, boxes, capsules and cylinders become FCL's primitives (its conventions are the
/// Scene's); a mesh becomes a BVHModel<OBBRSS> (a surface, as in the Scene); each cell of a
/// `cells` object becomes a box of its side, axis-aligned at its centre (an octomap's
/// leaves, one FCL object each). scene_from_fcl of the objects gives the same obstacles
/// (the cells as boxes). Frames: W.
/// Errors: std::invalid_argument naming the object (its index and name) for a point cloud:
/// FCL has no geometry of a point, so the mesh fallback could not settle a pair with it
/// (give its points as cells of the sensor's resolution, add_cells).

#include <memory>
#include <vector>

#include <fcl/narrowphase/collision_object.h>

#include "medspheres/check/scene.h"

namespace medspheres::fcl {

struct FclObjects {
  std::vector<std::unique_ptr<::fcl::CollisionObjectd>> owned;
  std::vector<const ::fcl::CollisionObjectd*> objects;  ///< owned's, in the Scene's order
};

FclObjects fcl_from_scene(const check::Scene& scene);

}  // namespace medspheres::fcl
