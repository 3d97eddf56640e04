#pragma once
/// \file
/// Opt-in: non-template overloads of fcl::distance and fcl::collide for double that
/// route through medspheres::fcl::distance and medspheres::fcl::collide. C++ prefers a
/// non-template function to a template with the same parameters, so code recompiled with
/// this header picks sphere sets up unchanged, including FCL's header-only default
/// broadphase callbacks (fcl::DefaultCollisionFunction, fcl::DefaultDistanceFunction),
/// whose unqualified calls find these overloads by argument-dependent lookup. Pairs
/// without a sphere set still end in libfcl, with the same results.
///
/// Like libfcl's, these functions do not throw for a pair they cannot answer (FCL's
/// default callbacks do not catch): a sphere set against a geometry that
/// medspheres::fcl::distance and collide reject (fcl::TriangleP, a BVHModel of points or
/// not finished, a user-defined type) or at a non-finite pose goes to libfcl, which
/// answers for its guard box (see sphere_set_geometry.h). Null geometries still throw
/// std::invalid_argument, where libfcl would dereference them.
///
/// Caveat: include this header in every translation unit of the program that calls
/// fcl::distance or fcl::collide, or instantiates FCL's default callbacks. A translation
/// unit without it calls libfcl directly, which sees a sphere set as its enclosing box
/// (see sphere_set_geometry.h); and FCL's inline callback templates, compiled one way in
/// some units and the other way in others, break the one-definition rule, so that the
/// linker may keep either version for the whole program.

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
