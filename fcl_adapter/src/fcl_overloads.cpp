// The opt-in non-template fcl::distance and fcl::collide for double. A pair that
// medspheres answers on sphere trees goes to medspheres::fcl; every other pair goes to
// FCL's templates in libfcl, exactly as without this header (a sphere set against a
// geometry medspheres does not support then meets libfcl as its guard box), so that these
// functions, like libfcl's, do not throw for a pair they cannot answer.
//
// Why they work: C++ prefers a non-template function to a template with the same
// parameters, so a call compiled with fcl_overloads.h picks these, and FCL's header-only
// default callbacks (fcl::DefaultCollisionFunction, fcl::DefaultDistanceFunction) find
// them by argument-dependent lookup from their unqualified calls. Null geometries throw
// where libfcl would dereference them; FCL's default callbacks do not catch, hence no
// other exception. Why every translation unit needs the header: one without it calls
// libfcl directly, which sees a sphere set as its enclosing box; and FCL's inline callback
// templates, compiled one way in some units and the other way in others, break the
// one-definition rule, so that the linker may keep either version for the whole program.

#include "medspheres/fcl/fcl_overloads.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include "fcl_dispatch.h"

using medspheres::fcl::detail::answered_on_spheres;

namespace fcl {

double distance(const CollisionObject<double>* o1, const CollisionObject<double>* o2,
                const DistanceRequest<double>& request, DistanceResult<double>& result) {
  if (o1 != nullptr && o2 != nullptr &&
      !answered_on_spheres(o1->collisionGeometry().get(), o1->getTransform(),
                           o2->collisionGeometry().get(), o2->getTransform()))
    return fcl::distance<double>(o1, o2, request, result);
  return medspheres::fcl::distance(o1, o2, request, result);
}

double distance(const CollisionGeometry<double>* o1, const Transform3<double>& tf1,
                const CollisionGeometry<double>* o2, const Transform3<double>& tf2,
                const DistanceRequest<double>& request, DistanceResult<double>& result) {
  if (!answered_on_spheres(o1, tf1, o2, tf2))
    return fcl::distance<double>(o1, tf1, o2, tf2, request, result);
  return medspheres::fcl::distance(o1, tf1, o2, tf2, request, result);
}

std::size_t collide(const CollisionObject<double>* o1, const CollisionObject<double>* o2,
                    const CollisionRequest<double>& request, CollisionResult<double>& result) {
  if (o1 != nullptr && o2 != nullptr &&
      !answered_on_spheres(o1->collisionGeometry().get(), o1->getTransform(),
                           o2->collisionGeometry().get(), o2->getTransform()))
    return fcl::collide<double>(o1, o2, request, result);
  return medspheres::fcl::collide(o1, o2, request, result);
}

std::size_t collide(const CollisionGeometry<double>* o1, const Transform3<double>& tf1,
                    const CollisionGeometry<double>* o2, const Transform3<double>& tf2,
                    const CollisionRequest<double>& request, CollisionResult<double>& result) {
  if (!answered_on_spheres(o1, tf1, o2, tf2))
    return fcl::collide<double>(o1, tf1, o2, tf2, request, result);
  return medspheres::fcl::collide(o1, tf1, o2, tf2, request, result);
}

}  // namespace fcl
