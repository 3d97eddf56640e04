// SphereSetGeometry, and the reasons behind the contract in sphere_set_geometry.h.
//
// Why our own entry points. libfcl dispatches fcl::distance and fcl::collide through
// tables indexed by its closed NODE_TYPE enum, built into the shared library; no one can
// add a row for a new geometry. So medspheres::fcl::distance and collide (fcl_dispatch.cpp)
// take every pair that involves a SphereSetGeometry, and forward every other pair. A
// sphere set against a geometry they do not support throws rather than being forwarded,
// because libfcl would report it as "no collision". Plane and Halfspace are answered in
// closed form because libfcl's sphere-plane and sphere-halfspace distance is not usable.
// libccd's GJK (Ellipsoid, Cone, Convex): in the tests its distances move by up to 1e-4
// between two frames of one configuration.
//
// The guard. Code that calls fcl::distance or fcl::collide directly (or FCL's default
// broadphase callbacks, compiled without fcl_overloads.h) sends a SphereSetGeometry to
// libfcl, which has no node type for it and reports a geometry of unknown type as "no
// collision". Deriving from fcl::Box makes libfcl answer exactly as for the box that
// encloses the spheres, conservative wherever it supports a box. Where libfcl does not
// support a box it does what it does for its own box: it prints "... is not supported"
// and reports no collision (against fcl::TriangleP) or a distance of the largest double
// (distance against a BVHModel of AABB, OBB or KDOP nodes), and libfcl 0.7's distance
// against fcl::Plane or fcl::Halfspace crashes for a box as for every shape. A box was
// chosen over a tighter fcl::Convex because libfcl 0.7 also crashes in collide() between a
// Convex and a Plane. A set reaching beyond half the largest finite double from the
// origin gets the largest finite box, which then cannot hold all of it.

#include "medspheres/fcl/sphere_set_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <typeinfo>
#include <vector>

namespace medspheres::fcl {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

const SphereSet& checked(const SphereSet& set) {
  validate_sphere_set(set, "sphere set");
  if (set.empty()) throw std::invalid_argument("SphereSetGeometry: the sphere set is empty");
  return set;
}

// The side lengths of the box centred on the origin of the set's frame that encloses every
// sphere: twice the largest |coordinate| + radius along each axis, rounded up, and at most
// the largest finite double. (validate_sphere_set keeps |coordinate| + radius finite, but
// twice it, or its widening, may overflow: the largest finite side is then the largest
// box there is, where an infinite one would give libfcl infinite and NaN extents.)
::fcl::Vector3d guard_box_sides(const SphereSet& set) {
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
  for (const Sphere& s : set.spheres)
    half = half.cwiseMax(s.center.cwiseAbs() + Eigen::Vector3d::Constant(s.radius));
  // Rounding of the sums: widen by a few ulps of the extent.
  const Eigen::Vector3d sides =
      2.0 * (half + Eigen::Vector3d::Constant(16 * kEps * half.maxCoeff()));
  return sides.cwiseMin(std::numeric_limits<double>::max());
}

}  // namespace

SphereSetGeometry::SphereSetGeometry(const SphereSet& set, const SphereTreeOptions& options)
    : ::fcl::Box<double>(guard_box_sides(checked(set))),
      set_(set),
      tree_(set, options),
      bound_(tree_.bounding_ball(0)) {}

void SphereSetGeometry::computeLocalAABB() {
  ::fcl::AABBd box;
  box.min_ = set_.bounds().min();
  box.max_ = set_.bounds().max();
  aabb_local = box;
  aabb_center = box.center();
  double radius = 0.0;
  for (const Sphere& s : set_.spheres)
    radius = std::max(radius, (s.center - aabb_center).norm() + s.radius);
  aabb_radius = radius + 16 * kEps * (aabb_center.norm() + radius);
}

double SphereSetGeometry::computeVolume() const {
  throw std::logic_error("SphereSetGeometry: the volume of a union of balls is not provided");
}

::fcl::Vector3d SphereSetGeometry::computeCOM() const {
  throw std::logic_error(
      "SphereSetGeometry: the centre of mass of a union of balls is not provided");
}

::fcl::Matrix3d SphereSetGeometry::computeMomentofInertia() const {
  throw std::logic_error(
      "SphereSetGeometry: the moment of inertia of a union of balls is not provided");
}

// SphereSetGeometry is final: its exact type identifies it, which costs a comparison of
// type names where dynamic_cast walks the class hierarchy (every query asks, twice).
const SphereSetGeometry* as_sphere_set(const ::fcl::CollisionGeometryd* geometry) noexcept {
  if (geometry == nullptr || typeid(*geometry) != typeid(SphereSetGeometry)) return nullptr;
  return static_cast<const SphereSetGeometry*>(geometry);
}

}  // namespace medspheres::fcl
