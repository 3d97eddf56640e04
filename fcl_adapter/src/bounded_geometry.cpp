// BoundedGeometry and its queries: the bounds come from the runtime's one bounds walk
// (medspheres/sphere_tree.h); this file checks construction, maps FCL's transforms and
// geometries to it, and runs FCL's exact mesh distance when the bounds leave a collision
// question undecided.

#include "medspheres/fcl/bounded_geometry.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <fcl/narrowphase/distance.h>
#include <nlohmann/json.hpp>

#include "fcl_dispatch.h"
#include "medspheres/error.h"

namespace medspheres::fcl {
namespace {

bool json_true(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_boolean() && it->get<bool>();
}

void check_set(const std::string& link, const SphereSet& set, const char* which) {
  if (set.empty()) throw InputError(link, std::string("the ") + which + " sphere set is empty");
  validate_sphere_set(set, link + " (" + which + " set)");
}

void check_margin(double margin) {
  if (!std::isfinite(margin) || margin < 0.0)
    throw std::invalid_argument("medspheres::fcl::collide: margin must be finite and >= 0");
}

// FCL's distance between the exact geometries (a mesh, and a mesh or any FCL geometry),
// exact when it is <= margin, else some value > margin: the margin's successor is preset
// as min_distance, which FCL's traversals (BVH pairs, octrees) prune at and report only
// strictly closer pairs below.
double exact_distance(const MeshModel& a, const ::fcl::Transform3d& X_WA,
                      const ::fcl::CollisionGeometryd& b, const ::fcl::Transform3d& X_WB,
                      double margin) {
  ::fcl::DistanceRequestd request;
  ::fcl::DistanceResultd result;
  result.min_distance = std::nextafter(margin, std::numeric_limits<double>::infinity());
  return ::fcl::distance(&a, X_WA, &b, X_WB, request, result);
}

// The result's verdict completed by the exact distance when undecided and a mesh pair
// exists.
CollideResult finish(CollideResult out, double margin, const MeshModel* mesh_a,
                     const ::fcl::Transform3d& X_WA, const ::fcl::CollisionGeometryd* exact_b,
                     const ::fcl::Transform3d& X_WB) {
  if (out.verdict == BoundsVerdict::undecided && mesh_a != nullptr && exact_b != nullptr) {
    out.path = AnswerPath::mesh;
    out.mesh_distance = exact_distance(*mesh_a, X_WA, *exact_b, X_WB, margin);
    out.verdict = out.mesh_distance <= margin ? BoundsVerdict::colliding : BoundsVerdict::free;
  }
  return out;
}

CollideResult from_decision(const BoundsDecision& d, bool certified) {
  CollideResult out;
  out.verdict = d.verdict;
  out.bounds = d.bounds;
  out.certified = certified;
  return out;
}

}  // namespace

bool records_certified_cover(const std::string& json) {
  const nlohmann::json j = nlohmann::json::parse(json, nullptr, false);
  if (!j.is_object()) return false;
  if (json_true(j, "certified")) return true;
  const auto stats = j.find("stats");
  return stats != j.end() && stats->is_object() && json_true(*stats, "certified");
}

BoundedGeometry::BoundedGeometry(std::string link, const SphereSet& inner, const SphereSet& outer,
                                 std::shared_ptr<const MeshModel> mesh,
                                 const BoundedGeometryOptions& options)
    : BoundedGeometry(std::move(link), inner, outer, records_certified_cover(outer.metadata_json),
                      std::move(mesh), options) {}

BoundedGeometry BoundedGeometry::from_link(const std::string& link, const LinkSpheres& spheres,
                                           std::shared_ptr<const MeshModel> mesh,
                                           const BoundedGeometryOptions& options) {
  return BoundedGeometry(link, spheres.inner, spheres.outer,
                         records_certified_cover(spheres.outer_certificate_json), std::move(mesh),
                         options);
}

BoundedGeometry::BoundedGeometry(std::string link, const SphereSet& inner, const SphereSet& outer,
                                 bool certified, std::shared_ptr<const MeshModel> mesh,
                                 const BoundedGeometryOptions& options)
    : link_(std::move(link)), mesh_(std::move(mesh)), certified_(certified) {
  check_set(link_, inner, "inner");
  check_set(link_, outer, "outer");
  if (!certified_ && !options.allow_uncertified)
    throw InputError(link_,
                     "the outer sphere set records no certified cover (\"certified\": true); "
                     "bake it with a cover budget, or pass allow_uncertified");
  if (mesh_ && (mesh_->getModelType() != ::fcl::BVH_MODEL_TRIANGLES ||
                mesh_->build_state != ::fcl::BVH_BUILD_STATE_PROCESSED))
    throw InputError(link_, "the mesh is not a finished triangle model (endModel())");
  inner_ = SphereTree(inner, options.tree);
  outer_ = SphereTree(outer, options.tree);
}

BoundsResult distance_bounds(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                             const BoundedGeometry& b, const ::fcl::Transform3d& X_WB) {
  BoundsResult r;
  r.bounds = medspheres::distance_bounds(a.inner(), a.outer(), X_WA, b.inner(), b.outer(), X_WB);
  r.certified = a.certified() && b.certified();
  return r;
}

BoundsResult distance_bounds(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                             const ::fcl::CollisionGeometryd& b, const ::fcl::Transform3d& X_WB) {
  BoundsResult r;
  detail::with_target_view(b, [&](const ProximityTarget& target) {
    r.bounds = medspheres::distance_bounds(a.inner(), a.outer(), X_WA, target, X_WB);
  });
  r.certified = a.certified();
  return r;
}

CollideResult decide(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                     const BoundedGeometry& b, const ::fcl::Transform3d& X_WB, double margin) {
  check_margin(margin);
  return from_decision(
      decide_collision(a.inner(), a.outer(), X_WA, b.inner(), b.outer(), X_WB, margin),
      a.certified() && b.certified());
}

CollideResult decide(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                     const ::fcl::CollisionGeometryd& b, const ::fcl::Transform3d& X_WB,
                     double margin) {
  check_margin(margin);
  BoundsDecision d;
  detail::with_target_view(b, [&](const ProximityTarget& target) {
    d = decide_collision(a.inner(), a.outer(), X_WA, target, X_WB, margin);
  });
  return from_decision(d, a.certified());
}

CollideResult settle(const CollideResult& decided, const BoundedGeometry& a,
                     const ::fcl::Transform3d& X_WA, const BoundedGeometry& b,
                     const ::fcl::Transform3d& X_WB, double margin) {
  check_margin(margin);
  return finish(decided, margin, a.mesh(), X_WA, b.mesh(), X_WB);
}

CollideResult settle(const CollideResult& decided, const BoundedGeometry& a,
                     const ::fcl::Transform3d& X_WA, const ::fcl::CollisionGeometryd& b,
                     const ::fcl::Transform3d& X_WB, double margin) {
  check_margin(margin);
  return finish(decided, margin, a.mesh(), X_WA, &b, X_WB);
}

CollideResult collide(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                      const BoundedGeometry& b, const ::fcl::Transform3d& X_WB, double margin) {
  return settle(decide(a, X_WA, b, X_WB, margin), a, X_WA, b, X_WB, margin);
}

CollideResult collide(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                      const ::fcl::CollisionGeometryd& b, const ::fcl::Transform3d& X_WB,
                      double margin) {
  return settle(decide(a, X_WA, b, X_WB, margin), a, X_WA, b, X_WB, margin);
}

}  // namespace medspheres::fcl
