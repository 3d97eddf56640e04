// BoundedGeometry and its queries: the bounds come from the runtime's one bounds walk
// (medspheres/sphere_tree.h); this file checks construction, maps FCL's transforms and
// geometries to it, and runs FCL's exact mesh distance when the bounds leave a collision
// question undecided.

#include "medspheres/fcl/bounded_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fcl/geometry/shape/sphere.h>
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

// The distance between the balls of \p balls at X_WA (a solid made of them exactly) and the
// FCL geometry g at X_WB, exact when it is <= margin, else some value > margin: the
// runtime's tree-target walk (exact for triangles and boxes, FCL's narrowphase tolerance
// for other primitives), with the margin's successor preset as its upper_bound. A mesh is
// a surface here, as in FCL's mesh distance.
double balls_distance(const SphereTree& balls, const ::fcl::Transform3d& X_WA,
                      const ::fcl::CollisionGeometryd& g, const ::fcl::Transform3d& X_WB,
                      double margin) {
  DistanceOptions options;
  options.upper_bound = std::nextafter(margin, std::numeric_limits<double>::infinity());
  double d = options.upper_bound;
  detail::with_target_view(g, [&](const ProximityTarget& target) {
    d = medspheres::distance(balls, X_WA, target, X_WB, options).distance;
  });
  return d;
}

// The distance from a ball (centre in W) to the FCL geometry g at X_WB, as balls_distance.
double ball_distance(const Sphere& ball_W, const ::fcl::CollisionGeometryd& g,
                     const ::fcl::Transform3d& X_WB, double margin) {
  SphereSet one;
  one.spheres.push_back(ball_W);
  return balls_distance(SphereTree(one), ::fcl::Transform3d::Identity(), g, X_WB, margin);
}

// The balls of \p balls at X_WA against a mesh at X_WB, one ball at a time (ball_distance:
// each small ball descends the mesh from its own box, where balls_distance descends it
// from the bounding ball of all of them; cheaper for a few balls against a large mesh),
// stopping at the first ball within the margin.
double balls_mesh_distance(const SphereTree& balls, const ::fcl::Transform3d& X_WA,
                           const MeshModel& mesh, const ::fcl::Transform3d& X_WB, double margin) {
  double d = std::nextafter(margin, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < balls.num_spheres() && d > margin; ++i) {
    const Sphere s = balls.sphere(i);
    d = std::min(d, ball_distance({X_WA * s.center, s.radius}, mesh, X_WB, margin));
  }
  return d;
}

// An undecided result completed by an exact distance.
CollideResult with_exact(CollideResult out, double margin, double exact) {
  out.path = AnswerPath::mesh;
  out.mesh_distance = exact;
  out.verdict = exact <= margin ? BoundsVerdict::colliding : BoundsVerdict::free;
  return out;
}

// Whether the two sets are the same balls in the same order.
bool same_balls(const SphereSet& a, const SphereSet& b) {
  return a.size() == b.size() && std::equal(a.spheres.begin(), a.spheres.end(), b.spheres.begin(),
                                            [](const Sphere& x, const Sphere& y) {
                                              return x.center == y.center && x.radius == y.radius;
                                            });
}

// The inner set with the mesh's vertices as points (radius 0), at most one per cube of
// side `spacing` (every vertex when spacing is 0). Soundness: the upper bound is the
// distance between two subsets of the solids, min |p - q| over p in A's inner union and q
// in B's; d(A, B) = min over all p in A, q in B is at most that for any subsets of the
// closed solids. A mesh vertex is on the solid's boundary, so in the closed solid, and a
// point of A inside one of B's inner balls (distance <= 0) is a point of both solids. The
// choice of vertices (which cube keeps which) affects only tightness, never soundness.
SphereSet with_surface_points(const std::string& link, const SphereSet& inner,
                              const MeshModel& mesh, double spacing, std::size_t& added) {
  if (!std::isfinite(spacing) || spacing < 0.0)
    throw InputError(link, "surface_point_spacing must be finite and >= 0");
  SphereSet out = inner;
  std::set<std::array<std::int64_t, 3>> taken;
  for (int v = 0; v < mesh.num_vertices; ++v) {
    const Eigen::Vector3d& p = mesh.vertices[v];
    if (!p.allFinite()) throw InputError(link, "the mesh has a non-finite vertex");
    if (spacing > 0.0) {
      const Eigen::Vector3d cell = (p / spacing).array().floor();
      if (!(cell.cwiseAbs().maxCoeff() < 1e18))
        throw InputError(link, "surface_point_spacing is too small for the mesh's extent");
      if (!taken
               .insert({static_cast<std::int64_t>(cell.x()), static_cast<std::int64_t>(cell.y()),
                        static_cast<std::int64_t>(cell.z())})
               .second)
        continue;
    }
    out.spheres.push_back({p, 0.0});
    ++added;
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

// FCL's traversals (BVH pairs, octrees) prune at a preset min_distance and report only
// strictly closer pairs below it: the margin's successor.
double exact_distance(const MeshModel& a, const ::fcl::Transform3d& X_WA,
                      const ::fcl::CollisionGeometryd& b, const ::fcl::Transform3d& X_WB,
                      double margin) {
  // FCL's sphere-to-mesh distance (fcl 0.7) leaves a triangle's distance unset where the
  // ball meets it (sphereTriangleDistance with closest points), so a ball deep in a mesh
  // could read as far from it: a ball goes by the runtime's walk instead, exact for
  // triangles.
  if (b.getNodeType() == ::fcl::GEOM_SPHERE)
    return ball_distance({X_WB.translation(), static_cast<const ::fcl::Sphered&>(b).radius}, a,
                         X_WA, margin);
  ::fcl::DistanceRequestd request;
  ::fcl::DistanceResultd result;
  result.min_distance = std::nextafter(margin, std::numeric_limits<double>::infinity());
  return ::fcl::distance(&a, X_WA, &b, X_WB, request, result);
}

std::shared_ptr<const MeshModel> make_mesh_model(const TriangleMesh& mesh) {
  if (mesh.triangles.empty())
    throw std::invalid_argument("make_mesh_model: the mesh has no triangles");
  return make_bvh_model<::fcl::OBBRSSd>(mesh);
}

bool records_certified_cover(const std::string& json) {
  const nlohmann::json j = nlohmann::json::parse(json, nullptr, false);
  if (!j.is_object()) return false;
  if (json_true(j, "certified")) return true;
  const auto stats = j.find("stats");
  return stats != j.end() && stats->is_object() && json_true(*stats, "certified");
}

bool records_filled_inner(const std::string& json) {
  const nlohmann::json j = nlohmann::json::parse(json, nullptr, false);
  if (!j.is_object()) return false;
  const auto stats = j.find("stats");
  if (stats == j.end() || !stats->is_object()) return false;
  const auto solid = stats->find(kInnerSolidKey);
  return solid != stats->end() && solid->is_string() &&
         solid->get<std::string>() == kInnerSolidFilled;
}

BoundedGeometry::BoundedGeometry(std::string link, const SphereSet& inner, const SphereSet& outer,
                                 std::shared_ptr<const MeshModel> mesh,
                                 const BoundedGeometryOptions& options)
    : BoundedGeometry(std::move(link), inner, outer, records_certified_cover(outer.metadata_json),
                      records_filled_inner(inner.metadata_json), std::move(mesh), options) {}

BoundedGeometry BoundedGeometry::from_link(const std::string& link, const LinkSpheres& spheres,
                                           std::shared_ptr<const MeshModel> mesh,
                                           const BoundedGeometryOptions& options) {
  return BoundedGeometry(link, spheres.inner, spheres.outer,
                         records_certified_cover(spheres.outer_certificate_json),
                         spheres.inner_filled || records_filled_inner(spheres.inner.metadata_json),
                         std::move(mesh), options);
}

BoundedGeometry::BoundedGeometry(std::string link, const SphereSet& inner, const SphereSet& outer,
                                 bool certified, bool filled, std::shared_ptr<const MeshModel> mesh,
                                 const BoundedGeometryOptions& options)
    : link_(std::move(link)),
      mesh_(std::move(mesh)),
      certified_(certified),
      exact_balls_(!filled && same_balls(inner, outer)) {
  check_set(link_, inner, "inner");
  check_set(link_, outer, "outer");
  if (!certified_ && !options.allow_uncertified)
    throw InputError(link_,
                     "the outer sphere set records no certified cover (\"certified\": true); "
                     "bake it with a cover budget, or pass allow_uncertified");
  if (mesh_ && (mesh_->getModelType() != ::fcl::BVH_MODEL_TRIANGLES ||
                mesh_->build_state != ::fcl::BVH_BUILD_STATE_PROCESSED))
    throw InputError(link_, "the mesh is not a finished triangle model (endModel())");
  SphereTreeOptions inner_tree = options.tree;
  inner_tree.allow_points = true;
  // Balls of the filled solid may sit in the link's cavity, outside its material: they are
  // left out, and with the mesh its surface points alone bound the real solid from inside.
  const SphereSet none;
  const SphereSet& held = filled ? none : inner;
  inner_ = mesh_ && (options.surface_points || filled)
               ? SphereTree(with_surface_points(link_, held, *mesh_, options.surface_point_spacing,
                                                surface_points_),
                            inner_tree)
               : SphereTree(held, options.tree);
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
  if (decided.verdict != BoundsVerdict::undecided) return decided;
  if (a.mesh() != nullptr && b.mesh() != nullptr)
    return with_exact(decided, margin, exact_distance(*a.mesh(), X_WA, *b.mesh(), X_WB, margin));
  if (a.exact_balls() && b.mesh() != nullptr)
    return with_exact(decided, margin,
                      balls_mesh_distance(a.outer(), X_WA, *b.mesh(), X_WB, margin));
  if (b.exact_balls() && a.mesh() != nullptr)
    return with_exact(decided, margin,
                      balls_mesh_distance(b.outer(), X_WB, *a.mesh(), X_WA, margin));
  return decided;
}

CollideResult settle(const CollideResult& decided, const BoundedGeometry& a,
                     const ::fcl::Transform3d& X_WA, const ::fcl::CollisionGeometryd& b,
                     const ::fcl::Transform3d& X_WB, double margin) {
  check_margin(margin);
  if (decided.verdict != BoundsVerdict::undecided) return decided;
  if (a.mesh() != nullptr)
    return with_exact(decided, margin, exact_distance(*a.mesh(), X_WA, b, X_WB, margin));
  if (a.exact_balls())
    return with_exact(decided, margin, balls_distance(a.outer(), X_WA, b, X_WB, margin));
  return decided;
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
