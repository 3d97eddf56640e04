#pragma once
/// \file
/// Closest point on a triangle: the one kernel behind every triangle query (TriangleTree,
/// MeshQuery, the FCL adapter's mesh targets), so that two queries never disagree about
/// one triangle.
///
/// Frame and units: the caller's. Accuracy, for every shape of triangle (slivers and
/// needles included): the returned point lies within 32 u S of the triangle and its
/// distance to p is within 32 u S of the true distance, with u = 2^-53 and
/// S = |p| + |p - a| + L (a the first corner, L the longest edge); the tests check it
/// against a 113-bit oracle. A degenerate triangle (2 area <= 2^-48 L^2) counts as the
/// segment or point it is; among its edges, ties go to ab, then ca, then bc.
/// Pure functions: safe from many threads.

#include <cstdint>

#include <Eigen/Core>

namespace medspheres {

/// The point of triangle (a, b, c) nearest to p (see the file comment).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

namespace detail {

// The prepared form, for hierarchies that query a triangle many times; the free
// function above is prepare_triangle followed by closest_on_triangle.

enum class TriangleShape : std::uint8_t { kRegular, kThin, kDegenerate };

/// Corner a, edges ab = b - a and ac = c - a, their dot products, the query path.
struct QueryTriangle {
  Eigen::Vector3d a, ab, ac;
  double ab_ab = 0, ab_ac = 0, ac_ac = 0;
  TriangleShape shape = TriangleShape::kRegular;
  std::uint8_t longest = 0;  ///< the longest edge: 0 ab, 1 bc, 2 ca
};

/// The plane of a triangle: a lower bound |n.p - offset| - error <= distance(p, triangle)
/// for every p (before the rounding of n.p and offset). Degenerate triangles get n = 0.
struct TrianglePlane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< unit, along (b - a) x (c - a)
  double offset = 0.0;                               ///< n.a
  double error = 0.0;
};

struct PreparedTriangle {
  QueryTriangle triangle;
  TrianglePlane plane;
};

PreparedTriangle prepare_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                  const Eigen::Vector3d& c);

/// The thin and degenerate paths, out of line so that the regular one inlines.
Eigen::Vector3d closest_on_irregular(const Eigen::Vector3d& p, const QueryTriangle& t,
                                     const Eigen::Vector3d& n);

/// Closest point of \p t to \p p; normal() returns its plane's unit normal
/// (TrianglePlane::normal) and is called only where the point depends on it. The regular
/// path, Ericson's Voronoi-region walk, is here to be inlined into traversals
/// (point_triangle.cpp derives its error).
template <class Normal>
inline Eigen::Vector3d closest_on_triangle_with(const Eigen::Vector3d& p, const QueryTriangle& t,
                                                const Normal& normal) {
  if (t.shape != TriangleShape::kRegular) return closest_on_irregular(p, t, normal());
  const Eigen::Vector3d ap = p - t.a;
  const double d1 = t.ab.dot(ap), d2 = t.ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return t.a;  // vertex a
  // The same dot products measured from b and from c.
  const double d3 = d1 - t.ab_ab, d4 = d2 - t.ab_ac;  // ab.(p-b), ac.(p-b)
  if (d3 >= 0.0 && d4 <= d3) return t.a + t.ab;       // vertex b
  // Edge e from corner v, parameter num / (num - rest), when p's projection is outside
  // the edge's line (side <= 0) and within its slab (num >= 0 >= rest).
  Eigen::Vector3d q;
  const auto on_edge = [&q](double side, double num, double rest, const Eigen::Vector3d& v,
                            const Eigen::Vector3d& e) {
    if (!(side <= 0.0 && num >= 0.0 && rest <= 0.0)) return false;
    const double den = num - rest;
    q = den > 0.0 ? Eigen::Vector3d(v + (num / den) * e) : v;
    return true;
  };
  if (on_edge(d1 * d4 - d3 * d2, d1, d3, t.a, t.ab)) return q;  // edge ab
  const double d5 = d1 - t.ab_ac, d6 = d2 - t.ac_ac;            // ab.(p-c), ac.(p-c)
  if (d6 >= 0.0 && d5 <= d6) return t.a + t.ac;                 // vertex c
  if (on_edge(d5 * d2 - d1 * d6, d2, d6, t.a, t.ac)) return q;  // edge ac
  if (on_edge(d3 * d6 - d5 * d4, d4 - d3, d6 - d5, t.a + t.ab, t.ac - t.ab)) return q;  // bc
  // Face interior: the projection onto the plane (well conditioned, unlike the
  // barycentric coordinates on thin triangles).
  const Eigen::Vector3d& n = normal();
  return p - n.dot(ap) * n;
}

inline Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const QueryTriangle& t,
                                           const Eigen::Vector3d& n) {
  return closest_on_triangle_with(p, t, [&n]() -> const Eigen::Vector3d& { return n; });
}

}  // namespace detail
}  // namespace medspheres
