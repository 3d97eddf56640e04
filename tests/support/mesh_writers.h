#pragma once
// Writers for the mesh formats the loader must read, so that loader tests build their
// input files in code instead of committing them; and small mesh builders for those
// tests.

#include <string>

#include "medspheres/triangle_mesh.h"

namespace medspheres::test {

std::string to_off(const TriangleMesh& m);
std::string to_obj(const TriangleMesh& m,
                   bool unwelded = false);  ///< unwelded: 3 fresh vertices per face
std::string to_stl_ascii(const TriangleMesh& m);
std::string to_stl_binary(const TriangleMesh& m);
std::string to_ply_ascii(const TriangleMesh& m);
/// COLLADA with the mesh placed by a node whose matrix is \p X (row-major 4x4).
std::string to_dae(const TriangleMesh& m, const Eigen::Matrix4d& X);
/// glTF 2 with an embedded base64 buffer and one node per translation in \p offsets,
/// all instancing the same mesh.
std::string to_gltf(const TriangleMesh& m, const std::vector<Eigen::Vector3d>& offsets);

/// The cube [lo, hi]^3 (make_box's triangles), wound outward.
TriangleMesh cube_mesh(double lo, double hi);
/// Appends the vertices and triangles of \p m to \p to; \p inward reverses the winding
/// of every appended triangle.
void append_mesh(TriangleMesh& to, const TriangleMesh& m, bool inward);

}  // namespace medspheres::test
