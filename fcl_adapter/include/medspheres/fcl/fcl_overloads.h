#pragma once
/// \file
/// Opt-in: non-template overloads of fcl::distance and fcl::collide for double that route
/// pairs with a sphere set through medspheres::fcl::distance and collide, so that code
/// recompiled with this header, FCL's default broadphase callbacks included, picks sphere
/// sets up unchanged. Pairs without a sphere set end in libfcl, with the same results.
///
/// Errors: like libfcl's, these do not throw for a pair they cannot answer: a sphere set
/// against a geometry medspheres::fcl rejects, or at a non-finite pose, goes to libfcl,
/// which answers for its guard box (sphere_set_geometry.h). Null geometries throw
/// std::invalid_argument.
///
/// Caveat: include this header in every translation unit that calls fcl::distance or
/// fcl::collide or instantiates FCL's default callbacks; otherwise libfcl sees sphere sets
/// as their guard boxes there, and the one-definition rule breaks (fcl_overloads.cpp).

#include <cstddef>

#include "medspheres/fcl/sphere_set_geometry.h"

namespace fcl {

double distance(const CollisionObject<double>* o1, const CollisionObject<double>* o2,
                const DistanceRequest<double>& request, DistanceResult<double>& result);

double distance(const CollisionGeometry<double>* o1, const Transform3<double>& tf1,
                const CollisionGeometry<double>* o2, const Transform3<double>& tf2,
                const DistanceRequest<double>& request, DistanceResult<double>& result);

std::size_t collide(const CollisionObject<double>* o1, const CollisionObject<double>* o2,
                    const CollisionRequest<double>& request, CollisionResult<double>& result);

std::size_t collide(const CollisionGeometry<double>* o1, const Transform3<double>& tf1,
                    const CollisionGeometry<double>* o2, const Transform3<double>& tf2,
                    const CollisionRequest<double>& request, CollisionResult<double>& result);

}  // namespace fcl
