// The opt-in non-template fcl::distance and fcl::collide for double. They hand every
// pair to medspheres::fcl, which forwards pairs without a sphere set to FCL's templates.

#include "medspheres/fcl/fcl_overloads.h"

namespace fcl {

double distance(const CollisionObject<double>* o1, const CollisionObject<double>* o2,
                const DistanceRequest<double>& request, DistanceResult<double>& result) {
  return medspheres::fcl::distance(o1, o2, request, result);
}

double distance(const CollisionGeometry<double>* o1, const Transform3<double>& tf1,
                const CollisionGeometry<double>* o2, const Transform3<double>& tf2,
                const DistanceRequest<double>& request, DistanceResult<double>& result) {
  return medspheres::fcl::distance(o1, tf1, o2, tf2, request, result);
}

std::size_t collide(const CollisionObject<double>* o1, const CollisionObject<double>* o2,
                    const CollisionRequest<double>& request, CollisionResult<double>& result) {
  return medspheres::fcl::collide(o1, o2, request, result);
}

std::size_t collide(const CollisionGeometry<double>* o1, const Transform3<double>& tf1,
                    const CollisionGeometry<double>* o2, const Transform3<double>& tf2,
                    const CollisionRequest<double>& request, CollisionResult<double>& result) {
  return medspheres::fcl::collide(o1, tf1, o2, tf2, request, result);
}

}  // namespace fcl
