#include "medspheres/fcl/broadphase_callbacks.h"

#include "medspheres/fcl/sphere_set_geometry.h"

namespace medspheres::fcl {

bool collision_callback(::fcl::CollisionObjectd* o1, ::fcl::CollisionObjectd* o2, void* data) {
  auto* d = static_cast<CollisionData*>(data);
  if (d->done) return true;
  try {
    collide(o1, o2, d->request, d->result);
    if (!d->request.enable_cost && d->result.isCollision() &&
        d->result.numContacts() >= d->request.num_max_contacts)
      d->done = true;
  } catch (...) {
    d->error = std::current_exception();
    d->done = true;
  }
  return d->done;
}

bool distance_callback(::fcl::CollisionObjectd* o1, ::fcl::CollisionObjectd* o2, void* data,
                       double& dist) {
  auto* d = static_cast<DistanceData*>(data);
  if (d->done) {
    dist = d->result.min_distance;
    return true;
  }
  try {
    distance(o1, o2, d->request, d->result);
  } catch (...) {
    d->error = std::current_exception();
    d->done = true;
  }
  dist = d->result.min_distance;
  if (dist <= 0) return true;
  return d->done;
}

void rethrow_if_failed(const CollisionData& data) {
  if (data.error) std::rethrow_exception(data.error);
}

void rethrow_if_failed(const DistanceData& data) {
  if (data.error) std::rethrow_exception(data.error);
}

}  // namespace medspheres::fcl
