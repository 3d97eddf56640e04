#pragma once
/// \file
/// Self-intersection of a triangle mesh: the pairs of its triangles that meet anywhere
/// other than at the vertices and edges they share. Where such pairs exist the
/// divergence-theorem volume counts a doubly covered region twice (fit_metrics.h); the
/// baker fills the winding-number solid instead (mesh_query.h).
///
/// Definitions. Triangles are closed point sets in frame M; every test is exact (CGAL's
/// predicates on the double coordinates, no tolerance).
/// - Corners are the same point when their coordinates are equal (-0.0 == +0.0), whatever
///   their vertex indices: welding changes nothing.
/// - A degenerate triangle (collinear corners: a repeated vertex or zero area) is skipped:
///   it is in no pair and is counted in SelfIntersections::degenerate_triangles.
/// - Two distinct non-degenerate triangles t, u intersect when t n u is not contained in
///   the convex hull of the corners they share, or when they are the same triangle wound
///   alike. By shared corners: none, they meet at all (touching counts: a vertex on a
///   triangle, coplanar overlap); one, p, some point other than p is common; two (edge ab),
///   they are coplanar with their third corners on the same side of ab (folded); three,
///   the same triangle wound alike (doubled surface) is a pair, wound oppositely (the
///   face two glued solids share) is not.
/// So collapsed and duplicate vertices never create a pair, and a closed mesh that is
/// merely tessellated has none.
///
/// Determinism: pairs in increasing order, the same for every thread count. Memory is
/// linear in the triangles plus the pairs found. Method and costs: self_intersection.cpp,
/// docs/measuring.md.

#include <array>
#include <cstddef>
#include <vector>

#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// What find_self_intersections found.
struct SelfIntersections {
  /// Every intersecting pair {t, u} of triangle indices, t < u, in increasing order.
  std::vector<std::array<int, 2>> pairs;
  /// Triangles skipped as degenerate (collinear corners); they are in no pair.
  std::size_t degenerate_triangles = 0;

  /// The number of intersecting pairs.
  std::size_t count() const noexcept { return pairs.size(); }
  /// True when some pair of triangles intersects.
  bool any() const noexcept { return !pairs.empty(); }
};

/// The intersecting pairs of triangles of \p mesh (file comment), with \p threads
/// threads (0: all cores).
/// \throws std::invalid_argument for an index out of range, a non-finite coordinate, more
///   than INT_MAX triangles (preconditions a loaded mesh meets, see check_mesh_usable), or
///   threads outside [0, kMaxThreads] (threads.h).
SelfIntersections find_self_intersections(const TriangleMesh& mesh, int threads = 0);

}  // namespace medspheres
