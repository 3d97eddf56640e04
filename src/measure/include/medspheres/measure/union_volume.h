#pragma once
/// \file
/// Exact volume and boundary area of a union of balls (paper section 4.2), and the dual
/// complex K of its power-diagram decomposition (the weighted alpha complex at alpha = 0),
/// which the dilation step walks.
///
/// Frame and units: the caller's (frame M, as in sphere_set.h); volumes in units^3, areas in
/// units^2. Which simplices are in K, which balls are hidden and which triple points are
/// v-points is decided exactly (filtered exact predicates on (c_i, r_i^2 rounded)); the
/// measures are closed forms in doubles, continuous in the input, each simplex's within a few
/// eps (k + 1) 4 pi r^3 (area: r^2), r its largest radius.
/// Degenerate input: no balls give 0; a ball equal to an earlier one is dropped (`duplicates`);
/// a ball in the union of the others gets no vertex in K (`hidden`); collinear, coplanar and
/// cospherical centres are handled.
/// Errors: InputError (source "sphere set", naming the ball) for a non-finite coordinate or a
/// radius not finite and > 0; std::invalid_argument beyond INT_MAX balls.
/// Thread safety: a UnionOfBalls is immutable after construction. Method: union_volume.cpp.

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "medspheres/sphere_set.h"

namespace medspheres {

/// What measure_union reports. Indices refer to the input vector.
struct UnionMeasures {
  double volume = 0.0;  ///< vol(union of the balls), units^3
  double area = 0.0;    ///< area of the boundary of the union, units^2

  /// Number of simplices of the dual complex K, by dimension.
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::size_t triangles = 0;
  std::size_t tetrahedra = 0;

  /// Affine dimension of the distinct centres: -1 (no balls) to 3. Below 3 the
  /// triangulation is a lower-dimensional one (collinear or coplanar centres).
  int dimension = -1;

  /// Balls without a vertex in K, ascending: each lies in the union of the others.
  std::vector<int> hidden;
  /// Balls equal (same centre and radius, bitwise) to a ball with a smaller index,
  /// ascending. Each is dropped; the smallest index of the group stays.
  std::vector<int> duplicates;
};

/// A point where three spheres of a triangle of K meet and which lies on the boundary
/// of the union (in no ball's interior).
struct VPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< p_MoV_M
  std::array<int, 3> balls{};                          ///< the triangle, ascending indices
};

/// The circle where the spheres of an edge of K meet, for an edge in no triangle of K.
/// The whole circle then lies on the boundary of the union.
struct EdgeCircle {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< p_MoC_M, on the segment of centres
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< unit, from balls[0]'s centre to balls[1]'s
  double radius = 0.0;                               ///< 0 when the two balls touch
  std::array<int, 2> balls{};                        ///< ascending indices
};

/// Wall-clock seconds spent in each stage of the construction, single-threaded.
struct UnionStageSeconds {
  double triangulation = 0.0;   ///< regular triangulation of the weighted centres
  double classification = 0.0;  ///< faces of the triangulation and the alpha = 0 test
  double measures = 0.0;        ///< inclusion-exclusion, v-points and edge circles
};

/// The union of a set of balls with its dual complex, built once and kept for queries.
class UnionOfBalls {
 public:
  /// Builds the dual complex and the measures of the union of \p balls.
  /// \throws InputError for a non-finite coordinate or a radius that is not > 0.
  explicit UnionOfBalls(const std::vector<Sphere>& balls);

  const UnionMeasures& measures() const noexcept { return measures_; }

  /// Simplices of K as ascending ball indices, each list in lexicographic order.
  const std::vector<int>& complex_vertices() const noexcept { return vertices_; }
  const std::vector<std::array<int, 2>>& complex_edges() const noexcept { return edges_; }
  const std::vector<std::array<int, 3>>& complex_triangles() const noexcept { return triangles_; }
  const std::vector<std::array<int, 4>>& complex_tetrahedra() const noexcept { return tetrahedra_; }

  /// For each triangle of K in the order of complex_triangles(), the points where its
  /// three spheres meet and which lie in no ball's interior: none, one or two. When there
  /// are two (z +- t n, n = (c_j - c_i) x (c_k - c_i) normalised, i < j < k), the one on
  /// the side of n comes first. Three spheres that touch in a single point give one.
  const std::vector<VPoint>& v_points() const noexcept { return v_points_; }

  /// The circles of the edges of K that lie in no triangle of K, in the order of
  /// complex_edges().
  const std::vector<EdgeCircle>& lone_edge_circles() const noexcept { return lone_circles_; }

  const UnionStageSeconds& stage_seconds() const noexcept { return seconds_; }

 private:
  UnionMeasures measures_;
  std::vector<int> vertices_;
  std::vector<std::array<int, 2>> edges_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<std::array<int, 4>> tetrahedra_;
  std::vector<VPoint> v_points_;
  std::vector<EdgeCircle> lone_circles_;
  UnionStageSeconds seconds_;
};

/// Volume, area and dual-complex statistics of the union of \p balls (one-off use of
/// UnionOfBalls).
/// \throws InputError for a non-finite coordinate or a radius that is not > 0.
UnionMeasures measure_union(const std::vector<Sphere>& balls);

}  // namespace medspheres
