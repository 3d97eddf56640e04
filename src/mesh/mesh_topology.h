#pragma once
// Private: the edge table shared by mesh validation and orientation repair.

#include <array>
#include <cstddef>
#include <vector>

#include "medspheres/triangle_mesh.h"

namespace medspheres::detail {

/// One use of an undirected edge {lo, hi} by a triangle; forward when the triangle
/// runs lo -> hi.
struct HalfEdge {
  int lo = 0;
  int hi = 0;
  int triangle = 0;
  bool forward = true;
};

/// Half-edges sorted by (lo, hi, triangle); edge e owns half_edges[edge_begin[e] ..
/// edge_begin[e + 1]).
struct EdgeTable {
  std::vector<HalfEdge> half_edges;
  std::vector<std::size_t> edge_begin;
  std::size_t num_edges() const { return edge_begin.empty() ? 0 : edge_begin.size() - 1; }
};

/// Throws std::invalid_argument when a triangle has an index out of range.
void check_indices(const TriangleMesh& mesh);

EdgeTable build_edge_table(const TriangleMesh& mesh);

/// True for a triangle with a repeated vertex index: it has no edges and no component.
inline bool is_collapsed(const std::array<int, 3>& t) {
  return t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
}

/// Component label per triangle (connected through shared edges), numbered in order of
/// first triangle, -1 for collapsed triangles; *count receives the number of components.
std::vector<int> triangle_components(const TriangleMesh& mesh, const EdgeTable& edges,
                                     std::size_t* count);

}  // namespace medspheres::detail
