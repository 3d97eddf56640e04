#pragma once
/// \file
/// The canonical order of a triangle mesh, so that what is computed from a mesh does not
/// depend on the order its file lists vertices and triangles in.

#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// Reorders \p mesh in place without changing its geometry or winding: vertices sorted by
/// (x, y, z) (lexicographic, -0.0 before +0.0, bit-identical positions keep their relative
/// order), each triangle rotated so that its smallest vertex index comes first, then
/// triangles sorted lexicographically by their three indices. Two meshes that differ only
/// by a permutation of distinct vertices, of triangles and a rotation of corners come out
/// identical. O(n log n). Precondition: every index in range and coordinates not NaN.
void canonicalize_order(TriangleMesh& mesh);

}  // namespace medspheres
