#pragma once
/// \file
/// MeshQuery: exact closest points and a robust inside test on a triangle mesh, the hot
/// loop of baking. Queries and results are in the mesh's frame M and units.
///
/// closest_point(p): the nearest point of the mesh over all triangles (a degenerate one
/// counts as its segment or point), its distance and its triangle. Exact to the
/// kernel's bound (medspheres/point_triangle.h) for every finite p, however far;
/// TriangleTree uses the same kernel and gives the same answers. Ties: the triangle the
/// traversal finds first, which depends only on the mesh and p, never on threads.
///
/// winding_number(p): the generalized winding number (Jacobson et al. 2013), 1 inside
/// and 0 outside a closed outward-wound mesh, graceful on open or self-intersecting ones;
/// evaluated hierarchically (Barill et al. 2018, second order, see winding_beta).
/// inside(p) is winding_number(p) > 0.5; on the surface itself it is unspecified.
///
/// Thread safety: every const member may be called from many threads at once.

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "medspheres/triangle_mesh.h"

namespace medspheres {

struct MeshQueryOptions {
  /// Hierarchical winding numbers: a subtree of radius r is replaced by its expansion
  /// when the query is farther than beta r from its centre (error per subtree ~ beta^-5).
  /// Larger is more exact and slower; must be finite and > 1.
  double winding_beta = 2.0;
  /// Close the holes of an open mesh for closest_point() (not for the winding number):
  /// each chain of boundary_loops() gets a fan of triangles from its vertices' centroid,
  /// numbered after the mesh's triangles (cap_mesh()), so that a ball sized by the
  /// distance does not leak out through a hole. Exact for convex planar holes, an
  /// approximation otherwise; no effect on a mesh without boundary edges.
  bool cap_holes = false;
};

namespace detail {
struct ClosestPointAccess;
}

/// The nearest point of the mesh to a query point.
struct ClosestPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< p_MoN_M, on triangle `triangle`
  /// |p - point|^2, rounded; +infinity when that overflows a double (|p - point| beyond
  /// about 1.3e154), which distance() does not.
  double squared_distance = 0.0;
  /// Index into TriangleMesh::triangles; with cap_holes, mesh().num_triangles() + k for
  /// triangle k of cap_mesh().
  int triangle = -1;
  /// |p - point|, computed without overflow: finite for every finite query point, and
  /// equal to sqrt(squared_distance) whenever that is finite.
  double distance() const;

 private:
  friend struct detail::ClosestPointAccess;
  double distance_ = 0.0;
};

/// Counters of one query, for benchmarks (the BVH statistics of a run).
struct QueryCounters {
  std::uint64_t nodes_visited = 0;     ///< 4-wide nodes whose children were tested
  std::uint64_t triangles_tested = 0;  ///< exact point-triangle evaluations
};

/// Shape of the hierarchy, reported next to timings.
struct MeshBvhStats {
  std::size_t triangles = 0;
  std::size_t cap_triangles = 0;  ///< MeshQueryOptions::cap_holes (in a hierarchy of their own)
  std::size_t nodes = 0;          ///< 4-wide inner nodes
  std::size_t depth = 0;          ///< longest root-to-triangle path, in 4-wide nodes
  std::size_t bytes = 0;          ///< memory held by the query structure
};

/// What a ray meets on the mesh (MeshQuery::cast_ray).
struct RayCrossings {
  double t = std::numeric_limits<double>::infinity();  ///< nearest crossing; +infinity: none
  int triangle = -1;                                   ///< its index into mesh().triangles
  /// With count_all: the sum over every crossing of +1 where the ray enters the solid
  /// (against the outward normal (b - a) x (c - a)) and -1 where it leaves; else 0.
  int winding = 0;
};

class MeshQuery {
 public:
  /// Builds the hierarchy over \p mesh (which is copied; the original may go away).
  /// \throws std::invalid_argument for a mesh without triangles, with non-finite
  ///   coordinates or with out-of-range indices (use check_mesh_usable first to get a
  ///   message for users), or for winding_beta <= 1.
  explicit MeshQuery(const TriangleMesh& mesh, const MeshQueryOptions& options = {});
  /// The same, taking over \p mesh instead of copying it.
  explicit MeshQuery(TriangleMesh&& mesh, const MeshQueryOptions& options = {});
  ~MeshQuery();
  MeshQuery(MeshQuery&&) noexcept;
  MeshQuery& operator=(MeshQuery&&) noexcept;
  MeshQuery(const MeshQuery&) = delete;
  MeshQuery& operator=(const MeshQuery&) = delete;

  /// Exact nearest point; see the file comment.
  /// \throws std::invalid_argument if p is not finite.
  ClosestPoint closest_point(const Eigen::Vector3d& p, QueryCounters* counters = nullptr) const;

  /// As closest_point(p), but starts from triangle \p hint_triangle as the best
  /// candidate. The answer's distance is identical; a good hint (the triangle nearest to
  /// a nearby point) only makes the search faster. On exact ties the triangle returned
  /// may differ from the unhinted query.
  /// \throws std::invalid_argument unless hint_triangle is a triangle as closest_point()
  ///   numbers them (caps included) and p is finite.
  ClosestPoint closest_point(const Eigen::Vector3d& p, int hint_triangle,
                             QueryCounters* counters = nullptr) const;

  /// Hierarchical generalized winding number at p.
  double winding_number(const Eigen::Vector3d& p) const;

  /// The same sum over every triangle, without the hierarchy (for tests and oracles).
  double winding_number_exact(const Eigen::Vector3d& p) const;

  /// winding_number(p) > 0.5.
  bool inside(const Eigen::Vector3d& p) const { return winding_number(p) > 0.5; }

  /// Batch forms: result i belongs to point i. They use \p threads threads (0: all
  /// cores; threads.h) and give bit-identical answers for every thread count. Both throw
  /// std::invalid_argument for threads outside [0, kMaxThreads], closest_points also if
  /// a point is not finite.
  std::vector<ClosestPoint> closest_points(const std::vector<Eigen::Vector3d>& points,
                                           int threads = 0) const;
  std::vector<double> winding_numbers(const std::vector<Eigen::Vector3d>& points,
                                      int threads = 0) const;

  /// The crossings of the ray origin + t direction, t in [0, limit), with the triangles
  /// of mesh() (not the caps), by the Moller-Trumbore test in double precision; the
  /// hierarchy culls only boxes the ray provably misses, so the answer is that of the
  /// test over every triangle. A triangle the ray lies in the plane of is not crossed.
  /// Ties in t: the triangle found first, which depends only on the mesh and the ray.
  /// \throws std::invalid_argument unless origin and direction are finite, direction
  ///   is nonzero and limit is not NaN.
  RayCrossings cast_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                        double limit = std::numeric_limits<double>::infinity(),
                        bool count_all = false) const;

  const TriangleMesh& mesh() const;
  /// The hole caps (MeshQueryOptions::cap_holes): a mesh of its own, empty when there are
  /// none.
  const TriangleMesh& cap_mesh() const;
  /// The corners of triangle \p t as closest_point() numbers it: a triangle of mesh(),
  /// or, from mesh().num_triangles() on, one of cap_mesh().
  /// \throws std::out_of_range for any other index.
  std::array<Eigen::Vector3d, 3> triangle_corners(int t) const;
  MeshBvhStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace medspheres
