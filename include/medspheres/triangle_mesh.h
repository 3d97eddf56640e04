#pragma once
/// \file
/// TriangleMesh: an indexed triangle mesh, the plain data that every part of
/// medspheres passes around. It lives in the runtime target (Eigen only), so that a
/// sphere tree can query a mesh without linking the loaders.

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace medspheres {

/// Vertices and triangles, in the mesh's own frame and units (frame M).
/// A triangle lists three indices into vertices. Orientation convention: seen from
/// outside the solid, a triangle's vertices run counter-clockwise, so that
/// (v1 - v0) x (v2 - v0) points out of the solid.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;

  std::size_t num_vertices() const noexcept { return vertices.size(); }
  std::size_t num_triangles() const noexcept { return triangles.size(); }

  /// Corner k (0, 1, 2) of triangle t. Preconditions: t < num_triangles(), k < 3.
  const Eigen::Vector3d& corner(std::size_t t, int k) const {
    return vertices[static_cast<std::size_t>(triangles[t][static_cast<std::size_t>(k)])];
  }

  /// Axis-aligned bounds of all vertices, referenced by a triangle or not.
  /// An empty box for a mesh without vertices.
  Eigen::AlignedBox3d bounds() const {
    Eigen::AlignedBox3d box;
    for (const auto& v : vertices) box.extend(v);
    return box;
  }
};

}  // namespace medspheres
