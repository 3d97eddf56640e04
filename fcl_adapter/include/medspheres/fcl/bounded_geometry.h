#pragma once
/// \file
/// BoundedGeometry: a link (or any solid) held as an inner sphere set (inside the solid),
/// an outer covering sphere set (its union contains the solid's surface, certified), and
/// optionally the exact mesh; certified distance bounds and a three-valued collision test
/// on them, with the exact mesh as fallback.
///
/// Why the bounds hold (medspheres/sphere_tree.h, "certified distance bounds"): the solid
/// contains the union of its inner set, and its surface lies inside the union of its outer
/// set. For two disjoint solids the closest points lie on the surfaces, so
///   d(outer A, outer B) <= d(A, B) <= d(inner A, inner B).
/// The inner side may hold points of radius 0 as well (the mesh's vertices, on the
/// surface and so in the closed solid): every pair of them is still a pair of solid points.
/// Overlapping solids whose surfaces meet have overlapping outer unions (lower = 0).
/// Assumed: no solid lies wholly inside another without surface contact, unless the outer
/// set also contains the interior (a cover certificate certifies only the surface; the
/// bake's covers fill the interior at sample points but do not certify it). Against an
/// FCL geometry, the geometry itself stands on both sides, so the same argument holds with
/// d(A, G) between d(outer A, G) and d(inner A, G).
///
/// Frames and units: sets and mesh in the link frame A; poses X_WA place it in W.
/// Errors: medspheres::InputError naming the link for an empty set, an invalid ball, or an
/// uncertified outer set without allow_uncertified; std::invalid_argument for non-finite
/// poses, a negative margin, or an FCL geometry the dispatch does not support.
/// Threads: a BoundedGeometry is immutable; any number of threads may query it at once.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision_object.h>

#include "medspheres/robot_model.h"
#include "medspheres/sphere_set.h"
#include "medspheres/sphere_tree.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres::fcl {

using MeshModel = ::fcl::BVHModel<::fcl::OBBRSSd>;

struct BoundedGeometryOptions {
  /// Accept an outer set whose certificate is missing or false; every result then carries
  /// certified = false.
  bool allow_uncertified = false;
  SphereTreeOptions tree;  ///< options of both sphere trees
  /// With a mesh: the mesh's vertices join the inner set as points (radius 0). A vertex
  /// lies on the solid's surface, so it is a point of the closed solid and the inner
  /// distance stays an upper bound; it reaches grazing contacts that the inner balls do
  /// not. At most one vertex per cube of side surface_point_spacing (link units, > 0), or
  /// every vertex when it is 0.
  bool surface_points = true;
  double surface_point_spacing = 0.0;
};

/// FCL's exact mesh of \p mesh (in its own frame) with bounding volumes BV, finished
/// (endModel()). A mesh without triangles gives an empty model.
template <class BV>
std::shared_ptr<::fcl::BVHModel<BV>> make_bvh_model(const TriangleMesh& mesh) {
  auto model = std::make_shared<::fcl::BVHModel<BV>>();
  std::vector<::fcl::Triangle> tris;
  tris.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) tris.emplace_back(t[0], t[1], t[2]);
  model->beginModel(static_cast<int>(tris.size()), static_cast<int>(mesh.vertices.size()));
  model->addSubModel(mesh.vertices, tris);
  model->endModel();
  return model;
}

/// FCL's exact mesh of \p mesh (in its own frame), finished (endModel()), as BoundedGeometry
/// takes it. \throws std::invalid_argument for a mesh without triangles.
std::shared_ptr<const MeshModel> make_mesh_model(const TriangleMesh& mesh);

/// FCL's distance between a mesh and any FCL geometry (a mesh a surface), exact when it is
/// <= margin, else some value > margin (the search pruned there).
double exact_distance(const MeshModel& a, const ::fcl::Transform3d& X_WA,
                      const ::fcl::CollisionGeometryd& b, const ::fcl::Transform3d& X_WB,
                      double margin);

/// True when \p json (a sphere-set file's metadata, or a link's outer_certificate_json)
/// records a certified cover: "certified": true at the top level or in "stats".
/// Malformed or empty text is not certified.
bool records_certified_cover(const std::string& json);

/// True when \p json (an inner set's metadata) records an inner set of a link's filled
/// solid (filled_solid.h: "stats": {"inner_solid": "filled"}, as `medspheres robot` bakes
/// thin-shelled links): its balls lie in the link closed with its cavity filled, not in
/// its thin material. BoundedGeometry leaves such balls out (so does from_link for
/// LinkSpheres::inner_filled): with a mesh it bounds the solid from inside by the mesh's
/// surface points alone (whatever options.surface_points says); without one the link has
/// no inner bounds, and no pair with it is proven colliding.
bool records_filled_inner(const std::string& json);

/// The stats key and value of records_filled_inner.
inline constexpr const char* kInnerSolidKey = "inner_solid";
inline constexpr const char* kInnerSolidFilled = "filled";

class BoundedGeometry {
 public:
  /// \p link names the geometry in messages. The outer set's certificate is read from
  /// outer.metadata_json (records_certified_cover). \p mesh, when given, is the exact
  /// solid in frame A, a finished triangle model.
  /// \throws InputError (source: the link) as the file comment says.
  BoundedGeometry(std::string link, const SphereSet& inner, const SphereSet& outer,
                  std::shared_ptr<const MeshModel> mesh = nullptr,
                  const BoundedGeometryOptions& options = {});

  /// From a robot link's sets; the certificate is spheres.outer_certificate_json.
  static BoundedGeometry from_link(const std::string& link, const LinkSpheres& spheres,
                                   std::shared_ptr<const MeshModel> mesh = nullptr,
                                   const BoundedGeometryOptions& options = {});

  const std::string& link() const noexcept { return link_; }
  /// The inner set, with the mesh's surface points when options.surface_points.
  const SphereTree& inner() const noexcept { return inner_; }
  /// How many surface points the inner set holds.
  std::size_t surface_points() const noexcept { return surface_points_; }
  const SphereTree& outer() const noexcept { return outer_; }
  const MeshModel* mesh() const noexcept { return mesh_.get(); }
  /// False only when accepted through allow_uncertified.
  bool certified() const noexcept { return certified_; }
  /// True when the inner and the outer set are the same balls: the solid is their union
  /// (inside it and containing its surface), as for a link made of sphere primitives.
  /// Its side of the bounds is then exact, and settle() needs no mesh of its own.
  bool exact_balls() const noexcept { return exact_balls_; }

 private:
  BoundedGeometry(std::string link, const SphereSet& inner, const SphereSet& outer, bool certified,
                  bool filled, std::shared_ptr<const MeshModel> mesh,
                  const BoundedGeometryOptions& options);

  std::string link_;
  SphereTree inner_;
  SphereTree outer_;
  std::shared_ptr<const MeshModel> mesh_;
  bool certified_ = false;
  bool exact_balls_ = false;
  std::size_t surface_points_ = 0;
};

/// lower <= d <= upper (see the file comment), with whether both outer sets are certified.
struct BoundsResult {
  DistanceBounds bounds;
  bool certified = true;
};

/// Which computation gave a collide() answer.
enum class AnswerPath {
  spheres,  ///< the bounds decided
  /// Undecided by the bounds; the exact geometry decided: FCL's mesh distance (OBBRSS),
  /// or, for a geometry with exact_balls() and for an fcl::Sphere against a mesh, the
  /// balls against the other side (a mesh a surface) by the sphere tree's exact walk (not
  /// FCL's sphere-to-mesh distance, which leaves a triangle that meets the ball unset).
  mesh,
};

struct CollideResult {
  /// free or colliding when decided; undecided only when no mesh could decide.
  BoundsVerdict verdict = BoundsVerdict::undecided;
  AnswerPath path = AnswerPath::spheres;
  DistanceBounds bounds;  ///< as tight as the verdict needed (BoundsDecision)
  /// When the mesh answered: the exact distance (meshes are surfaces), exact when it is
  /// <= margin, otherwise some value > margin (the search is pruned at the margin).
  double mesh_distance = -1.0;
  bool certified = true;
};

BoundsResult distance_bounds(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                             const BoundedGeometry& b, const ::fcl::Transform3d& X_WB);

/// Against an FCL geometry that medspheres::fcl::distance accepts beside a sphere set
/// (a BVHModel of triangles, a primitive, an octree).
BoundsResult distance_bounds(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                             const ::fcl::CollisionGeometryd& b, const ::fcl::Transform3d& X_WB);

/// "Colliding" means d <= margin (margin finite, >= 0). When the bounds leave it undecided
/// and both meshes are present (or one mesh and the other's exact_balls()), the exact
/// distance decides (path mesh).
CollideResult collide(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                      const BoundedGeometry& b, const ::fcl::Transform3d& X_WB,
                      double margin = 0.0);

/// As above against an FCL geometry; the fallback needs a's mesh or exact_balls().
CollideResult collide(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                      const ::fcl::CollisionGeometryd& b, const ::fcl::Transform3d& X_WB,
                      double margin = 0.0);

/// collide() in two steps, for callers that weigh many pairs before touching a mesh (a
/// robot: one certainly colliding pair makes every mesh query moot). decide() is the
/// bounds' verdict alone (path spheres, possibly undecided); settle() completes an
/// undecided result with the exact meshes as collide() does and returns a decided one
/// unchanged. collide(a, X_WA, b, X_WB, m) == settle(decide(a, X_WA, b, X_WB, m), ...).
CollideResult decide(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                     const BoundedGeometry& b, const ::fcl::Transform3d& X_WB, double margin = 0.0);
CollideResult decide(const BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                     const ::fcl::CollisionGeometryd& b, const ::fcl::Transform3d& X_WB,
                     double margin = 0.0);
CollideResult settle(const CollideResult& decided, const BoundedGeometry& a,
                     const ::fcl::Transform3d& X_WA, const BoundedGeometry& b,
                     const ::fcl::Transform3d& X_WB, double margin = 0.0);
CollideResult settle(const CollideResult& decided, const BoundedGeometry& a,
                     const ::fcl::Transform3d& X_WA, const ::fcl::CollisionGeometryd& b,
                     const ::fcl::Transform3d& X_WB, double margin = 0.0);

}  // namespace medspheres::fcl
