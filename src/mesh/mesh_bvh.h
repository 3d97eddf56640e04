#pragma once
// Private: the 4-wide bounding volume hierarchy behind MeshQuery.

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "medspheres/mesh/mesh_query.h"
#include "medspheres/point_triangle.h"

namespace medspheres::detail {

/// A 4-wide node, two cache lines. Child slot k holds an inner node index (>= 0), a
/// triangle (~index, i.e. < 0, into the reordered triangle arrays), or nothing (kEmpty,
/// with an inverted box that no point is near). Boxes are single precision, rounded
/// outward, stored relative to MeshBvh::origin in units of 1 / MeshBvh::box_scale (so
/// that every coordinate lies within [-1, 1], whatever the mesh's size), laid out
/// [axis][child] for 4-lane SIMD.
/// Bit k of triangle_mask is set when slot k holds a triangle.
struct alignas(64) Bvh4Node {
  float lo[3][4];
  float hi[3][4];
  std::int32_t child[4];
  std::uint32_t triangle_mask;
};
static_assert(sizeof(Bvh4Node) == 128, "Bvh4Node layout");

inline constexpr std::int32_t kEmpty = INT32_MIN;

/// A symmetric 3x3 matrix by its six distinct entries (xx, xy, xz, yy, yz, zz): the
/// second moments are symmetric, and this keeps 48 of their 72 bytes. matrix() gives
/// back the very matrix it was made from when that was symmetric.
struct SymmetricMatrix3 {
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  SymmetricMatrix3() = default;
  explicit SymmetricMatrix3(const Eigen::Matrix3d& m)
      : xx(m(0, 0)), xy(m(0, 1)), xz(m(0, 2)), yy(m(1, 1)), yz(m(1, 2)), zz(m(2, 2)) {}
  Eigen::Matrix3d matrix() const {
    Eigen::Matrix3d m;
    m << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    return m;
  }
  /// The product with y, in the order of matrix() * y, without building the matrix
  /// (the winding number's far field calls it for every subtree it accepts).
  Eigen::Vector3d times(const Eigen::Vector3d& y) const {
    return {xx * y[0] + xy * y[1] + xz * y[2], xy * y[0] + yy * y[1] + yz * y[2],
            xz * y[0] + yz * y[1] + zz * y[2]};
  }
  double trace() const { return xx + yy + zz; }
};

/// Far-field data of a subtree, for hierarchical winding numbers. With N_t = a_t n_t
/// the vector area of triangle t and d = x - centre:
/// - centre: the area-weighted centroid; radius: the largest |vertex - centre|;
/// - normal_sum N = sum_t N_t;
/// - first_moment D = sum_t (integral over t of d dA / a_t) N_t^T, i.e. D_ji = sum
///   n_i d_j dA;
/// - second_moment[i] = sum_t (N_t)_i (integral over t of d d^T dA) / a_t, a
///   symmetric 3x3 matrix per normal component i.
struct WindingExpansion {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0.0;
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d first_moment = Eigen::Matrix3d::Zero();
  SymmetricMatrix3 second_moment[3];
};

struct MeshBvh {
  TriangleMesh mesh;                         // the caller's mesh, copied
  std::vector<Bvh4Node> nodes;               // nodes[0] is the root
  std::vector<WindingExpansion> expansions;  // one per node
  std::vector<QueryTriangle> triangles;      // in BVH leaf order
  std::vector<TrianglePlane> planes;         // the same order: the cheap lower bound
  std::vector<int> original;                 // BVH order -> index in mesh.triangles
  // Per node: its triangles, [first, last) in BVH order; during the build only.
  std::vector<std::pair<int, int>> ranges;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // box coordinates are relative to it
  double extent = 0.0;                               // largest side of the mesh's bounding box
  double box_scale = 1.0;  // a power of two: box coordinates are (x - origin) * box_scale
  std::size_t depth = 0;
  double winding_beta = 2.0;

  /// The mesh and options build() takes, else std::invalid_argument.
  static void check(const TriangleMesh& m, const MeshQueryOptions& options);
  void build(TriangleMesh m, const MeshQueryOptions& options);

 private:
  void build_tree();
  void prepare_triangles();
  void build_expansions();
};

}  // namespace medspheres::detail

namespace medspheres {
struct MeshQuery::Impl {
  detail::MeshBvh bvh;
  std::vector<int> order_of;  // mesh triangle index -> BVH order
  // MeshQueryOptions::cap_holes: the caps in a hierarchy of their own (null without caps).
  std::unique_ptr<detail::MeshBvh> caps;
  std::vector<int> caps_order_of;
  TriangleMesh no_caps;  // what cap_mesh() returns without caps
};
}  // namespace medspheres
