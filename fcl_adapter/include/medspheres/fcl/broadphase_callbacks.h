#pragma once
/// \file
/// Broadphase callbacks for scenes that mix sphere sets, meshes and primitives, modelled
/// on FCL's default ones (fcl/broadphase/default_broadphase_callbacks.h): the same data
/// structs and the same stopping rules, but every pair goes through
/// medspheres::fcl::collide or medspheres::fcl::distance. They work with any
/// fcl::BroadPhaseCollisionManager<double>:
///
/// \code
/// medspheres::fcl::CollisionData data;
/// data.request.num_max_contacts = 4;
/// manager.collide(&data, medspheres::fcl::collision_callback);
/// medspheres::fcl::rethrow_if_failed(data);
/// \endcode
///
/// Errors: a callback catches every exception (none may cross an FCL manager), stores
/// it in data.error, sets data.done and asks the manager to stop; call
/// rethrow_if_failed(data) after the manager returns.

#include <exception>

#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>
#include <fcl/narrowphase/distance_request.h>
#include <fcl/narrowphase/distance_result.h>

namespace medspheres::fcl {

/// As fcl::DefaultCollisionData<double>, plus the error slot.
struct CollisionData {
  ::fcl::CollisionRequestd request;
  ::fcl::CollisionResultd result;
  /// Set when the evaluation may stop: enough contacts (FCL's rule), or an error.
  bool done = false;
  /// The exception a callback caught, if any.
  std::exception_ptr error;
};

/// As fcl::DefaultDistanceData<double>, plus the error slot.
struct DistanceData {
  ::fcl::DistanceRequestd request;
  ::fcl::DistanceResultd result;
  bool done = false;
  std::exception_ptr error;
};

/// As fcl::DefaultCollisionFunction: collides the pair into data->result and returns
/// true (stop) once the result has num_max_contacts contacts, unless enable_cost.
/// \p data must point to a CollisionData.
bool collision_callback(::fcl::CollisionObjectd* o1, ::fcl::CollisionObjectd* o2, void* data);

/// As fcl::DefaultDistanceFunction: updates data->result with the pair, sets \p dist to
/// the result's min_distance, and returns true (stop) once it is <= 0 (touching or
/// overlapping). \p data must point to a DistanceData.
bool distance_callback(::fcl::CollisionObjectd* o1, ::fcl::CollisionObjectd* o2, void* data,
                       double& dist);

/// Rethrows the exception a callback stored, if any.
void rethrow_if_failed(const CollisionData& data);
void rethrow_if_failed(const DistanceData& data);

}  // namespace medspheres::fcl
