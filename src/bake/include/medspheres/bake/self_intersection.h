#pragma once
/// \file
/// Self-intersection of a triangle mesh: the pairs of its triangles that meet anywhere
/// other than at the vertices and edges they share. A mesh that has such pairs need not
/// bound a solid the way its divergence-theorem volume assumes: a region inside two
/// overlapping parts is counted twice (fit_metrics.h); the baker fills the solid the
/// winding-number inside test defines instead (mesh_query.h).
///
/// Definitions. Triangles are closed point sets in frame M; every test is exact (CGAL's
/// exact predicates on the double coordinates; nothing is constructed, no tolerance).
/// - Two corners are the same point when their coordinates are equal (bit-identical up to
///   -0.0 == +0.0), whatever their vertex indices: the result does not depend on whether the
///   mesh was welded.
/// - A degenerate triangle is one whose three corners are collinear (a repeated vertex,
///   or zero area exactly). It has no plane and no interior; it is skipped: it is in no
///   pair, and SelfIntersections::degenerate_triangles counts it.
/// - Two distinct non-degenerate triangles t and u form an intersecting pair when t n u
///   is not contained in the convex hull of the corners they share (nothing, a point or
///   an edge), or when they are the same triangle wound alike. By the number of shared
///   corners:
///   - none: they meet at all. Touching counts: a vertex on another triangle, an edge on
///     an edge, two coplanar triangles that overlap or meet along a segment. So two boxes
///     pressed face to face intersect where their faces overlap, unless the faces are
///     triangulated alike (the last case);
///   - one, p: some point other than p is in both; equivalently (for non-degenerate
///     triangles) the edge of t opposite p meets u, or the edge of u opposite p meets t;
///   - two, the edge ab: t and u are coplanar and their third corners lie on the same
///     side of the line ab, i.e. they fold onto each other. Two triangles that share an
///     edge and are not coplanar meet only along it;
///   - three: the same triangle twice. Wound alike (the same cyclic order of corners) it
///     is a pair: the surface is doubled there, as where two overlapping solids share part
///     of a face, and the enclosed volume counts the region behind it twice. Wound
///     oppositely it is not: it is the face two solids glued together share (two
///     tetrahedra joined by a face), and the volume and the winding number are those of
///     their union. Only here does the winding matter.
/// Collapsed and duplicate vertices therefore never create a pair on their own, and a
/// closed mesh that is merely tessellated has none.
///
/// Method. Bounding boxes of the non-degenerate triangles (closed boxes, so touching
/// boxes are candidates), candidate pairs from CGAL's box_self_intersection_d, then the
/// exact test above on each candidate with OpenMP threads, 2^20 candidates at a time:
/// memory stays linear in the triangles (plus the pairs found) even where the candidates
/// are quadratic, as in a fan of n triangles around one vertex (the way CAD tools cap a
/// cylinder), whose n^2 / 2 triangle pairs all have meeting boxes. The reference is CGAL's
/// Polygon_mesh_processing::self_intersections, whose test for triangles sharing one or
/// two corners this is; it is not used because CGAL 5.5 offers it only for halfedge
/// meshes, which cannot hold non-manifold edges (the meshes medspheres must accept have
/// them), and it reports each degenerate triangle as a pair with itself.
///
/// Cost: the box search is sequential (CGAL runs it in parallel only with TBB, which
/// medspheres does not use) and takes most of the time; the exact tests are parallel. On
/// one core about 0.17 s for the 100k-triangle Stanford dragon (690k candidate pairs),
/// 0.2 s for a 43k-triangle gear assembly with 55k intersecting pairs, and 4 s for a flat
/// fan of 20k triangles around one vertex (2e8 candidate pairs, most settled by comparing
/// the boxes of an edge and a triangle before any exact predicate).
///
/// Determinism: the pairs are listed in increasing order, the same for every thread
/// count.
///
/// Errors: an index out of range, a non-finite coordinate or more than INT_MAX triangles
/// throws std::invalid_argument (preconditions: a loaded mesh meets them, see
/// check_mesh_usable in mesh_report.h), and so does a thread count outside
/// [0, kMaxThreads] (threads.h).

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
  /// True when some pair of triangles intersects (see the file comment).
  bool any() const noexcept { return !pairs.empty(); }
};

/// The intersecting pairs of triangles of \p mesh (file comment), with \p threads
/// threads (0: all cores).
/// \throws std::invalid_argument for an index out of range, a non-finite coordinate, or
///   threads outside [0, kMaxThreads].
SelfIntersections find_self_intersections(const TriangleMesh& mesh, int threads = 0);

}  // namespace medspheres
