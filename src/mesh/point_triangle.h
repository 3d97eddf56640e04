#pragma once
// Private: exact closest point on a triangle, the leaf test of MeshQuery.

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace medspheres::detail {

/// A triangle stored for fast point queries: corner a, edges ab = b - a, ac = c - a,
/// and their dot products.
struct QueryTriangle {
  Eigen::Vector3d a, ab, ac;
  double ab_ab = 0, ab_ac = 0, ac_ac = 0;
  /// True when the triangle is a segment or a point to within rounding: the sine of
  /// its angle at a is below 64 epsilon, or an edge has zero length. Such a triangle
  /// is queried as its three edges.
  bool degenerate = false;

  static QueryTriangle from(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
    QueryTriangle t;
    t.a = a;
    t.ab = b - a;
    t.ac = c - a;
    t.ab_ab = t.ab.dot(t.ab);
    t.ab_ac = t.ab.dot(t.ac);
    t.ac_ac = t.ac.dot(t.ac);
    const double cross2 = t.ab.cross(t.ac).squaredNorm();
    const double eps = 64.0 * std::numeric_limits<double>::epsilon();
    t.degenerate = !(cross2 > eps * eps * t.ab_ab * t.ac_ac) || (b - c).squaredNorm() == 0.0;
    return t;
  }
};

/// A cheap lower bound on the distance from a point to a triangle. For any unit vector
/// n and any point x = a + s ab + t ac of the triangle (s, t >= 0, s + t <= 1),
/// |p - x| >= |n.(p - x)| >= |n.(p - a)| - max(|n.ab|, |n.ac|). With n the computed
/// unit normal the last term is a few ulps for a well-shaped triangle and large for a
/// sliver, whose normal is ill-conditioned; either way the bound holds. `error` stores
/// that term plus the rounding of computing it. Degenerate triangles get a zero normal,
/// hence a bound of zero.
struct TrianglePlane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double offset = 0.0;  ///< n.a
  double error = 0.0;   ///< max(|n.ab|, |n.ac|), rounded up

  static TrianglePlane from(const QueryTriangle& t) {
    TrianglePlane p;
    if (t.degenerate) return p;
    p.normal = t.ab.cross(t.ac).normalized();
    p.offset = p.normal.dot(t.a);
    const double leak = std::max(std::abs(p.normal.dot(t.ab)), std::abs(p.normal.dot(t.ac)));
    const double rounding = 4.0 * std::numeric_limits<double>::epsilon() *
                            (t.ab.cwiseAbs().sum() + t.ac.cwiseAbs().sum());
    p.error = leak + rounding;
    return p;
  }
};

/// Closest point of segment [s, s + d] to p.
inline Eigen::Vector3d closest_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& s,
                                          const Eigen::Vector3d& d) {
  const double dd = d.dot(d);
  if (!(dd > 0.0)) return s;
  const double t = std::clamp(d.dot(p - s) / dd, 0.0, 1.0);
  return s + t * d;
}

/// Closest point of a degenerate triangle: the nearest point of its three edges.
inline Eigen::Vector3d closest_on_edges(const Eigen::Vector3d& p, const QueryTriangle& t) {
  const Eigen::Vector3d b = t.a + t.ab;
  const Eigen::Vector3d q0 = closest_on_segment(p, t.a, t.ab);
  const Eigen::Vector3d q1 = closest_on_segment(p, t.a, t.ac);
  const Eigen::Vector3d q2 = closest_on_segment(p, b, t.ac - t.ab);
  const double e0 = (p - q0).squaredNorm(), e1 = (p - q1).squaredNorm(),
               e2 = (p - q2).squaredNorm();
  if (e0 <= e1 && e0 <= e2) return q0;
  return e1 <= e2 ? q1 : q2;
}

/// Closest point of triangle \p t to \p p. The seven Voronoi regions of the triangle
/// (three vertices, three edges, the face) are told apart with the barycentric
/// quantities below; only two dot products depend on p. Degenerate triangles are
/// queried as their three edges.
inline Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const QueryTriangle& t) {
  if (t.degenerate) return closest_on_edges(p, t);
  const Eigen::Vector3d ap = p - t.a;
  const double d1 = t.ab.dot(ap), d2 = t.ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return t.a;  // vertex a
  // The same dot products measured from b and from c.
  const double d3 = d1 - t.ab_ab, d4 = d2 - t.ab_ac;  // ab.(p-b), ac.(p-b)
  if (d3 >= 0.0 && d4 <= d3) return t.a + t.ab;       // vertex b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {  // edge ab
    const double den = d1 - d3;
    return den > 0.0 ? Eigen::Vector3d(t.a + (d1 / den) * t.ab) : t.a;
  }
  const double d5 = d1 - t.ab_ac, d6 = d2 - t.ac_ac;  // ab.(p-c), ac.(p-c)
  if (d6 >= 0.0 && d5 <= d6) return t.a + t.ac;       // vertex c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {  // edge ac
    const double den = d2 - d6;
    return den > 0.0 ? Eigen::Vector3d(t.a + (d2 / den) * t.ac) : t.a;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {  // edge bc
    const double den = (d4 - d3) + (d5 - d6);
    const Eigen::Vector3d b = t.a + t.ab;
    return den > 0.0 ? Eigen::Vector3d(b + ((d4 - d3) / den) * (t.ac - t.ab)) : b;
  }
  const double sum = va + vb + vc;
  if (sum > 0.0 && std::isfinite(sum)) {  // face interior
    const double v = vb / sum, w = vc / sum;
    if (v >= 0.0 && w >= 0.0 && v + w <= 1.0) return t.a + v * t.ab + w * t.ac;
  }
  // A sliver whose barycentrics rounding pushed out of range: its edges are the answer.
  return closest_on_edges(p, t);
}

/// Signed solid angle of triangle (a, b, c) seen from p, in steradians (Van Oosterom
/// and Strackee 1983): positive when the triangle runs counter-clockwise seen from p's
/// side opposite its normal, i.e. when p is behind it.
inline double solid_angle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d x = a - p, y = b - p, z = c - p;
  const double lx = x.norm(), ly = y.norm(), lz = z.norm();
  const double num = x.dot(y.cross(z));
  const double den = lx * ly * lz + x.dot(y) * lz + y.dot(z) * lx + z.dot(x) * ly;
  return 2.0 * std::atan2(num, den);
}

}  // namespace medspheres::detail
