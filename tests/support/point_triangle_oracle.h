#pragma once
// Test oracle: the distance from a point to a triangle and to a mesh, in 113-bit binary
// floating point (__float128; where the compiler has none, long double, whose 64 bits
// cover the slivers below only down to w = 1e-4 L), by a different construction from
// the library's.
//
// Construction: an orthonormal frame (x along the longest edge P0 P1, y towards the
// third corner P2, z normal) and then a 2D problem: the distance is
// sqrt(Z^2 + d2^2), with Z the query's normal coordinate and d2 the distance of its
// in-plane coordinates (X, Y) to the 2D triangle (0, 0), (L, 0), (x2, w): zero when
// (X, Y) is on the inner side of the three edges, otherwise the distance to the nearest
// edge segment.
//
// Conditioning. The inputs are doubles, so every difference of two coordinates of
// similar magnitude is exact in 113 bits. The ill-conditioned step is the direction of
// y = ((P2 - P0) - x2 x) / w, whose error is u_q L / w (u_q = 2^-113, L the longest edge,
// w the triangle's height over it); it moves (X, Y, Z) by u_q |p - P0| L / w. The 2D
// edge tests are off by u_q (|p - P0| + L), which near a corner of angle t moves the
// answer by that over t, t >= w / L. For slivers down to w = 1e-12 L all of this stays
// below 1e-21 (|p - P0| + L), far below the 1e-16 a double result resolves. Triangles
// with w <= 2^-56 L (collinear or coincident corners, to within an eighth of a double
// ulp of L) are the segment P0 P1, which then holds the third corner to within w.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "medspheres/triangle_mesh.h"

namespace medspheres::test {

#if defined(__SIZEOF_FLOAT128__)
__extension__ typedef __float128 OracleReal;
#else
typedef long double OracleReal;
#endif

namespace oracle_detail {

struct V3 {
  OracleReal x = 0, y = 0, z = 0;
  V3() = default;
  V3(OracleReal a, OracleReal b, OracleReal c) : x(a), y(b), z(c) {}
  explicit V3(const Eigen::Vector3d& v) : x(v.x()), y(v.y()), z(v.z()) {}
  V3 operator+(const V3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  V3 operator-(const V3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  V3 operator*(OracleReal s) const { return {x * s, y * s, z * s}; }
  OracleReal dot(const V3& o) const { return x * o.x + y * o.y + z * o.z; }
  V3 cross(const V3& o) const { return {y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x}; }
};

// Square root to full OracleReal precision: Newton's iteration from the double root,
// with the argument scaled by even powers of two into double's range first.
inline OracleReal root(OracleReal v) {
  if (!(v > 0)) return 0;
  const OracleReal big = static_cast<OracleReal>(std::ldexp(1.0, 400));
  const OracleReal half_big = static_cast<OracleReal>(std::ldexp(1.0, 200));
  OracleReal scale = 1;
  while (v > big) {
    v /= big;
    scale *= half_big;
  }
  while (v < 1 / big) {
    v *= big;
    scale /= half_big;
  }
  OracleReal r = std::sqrt(static_cast<double>(v));
  for (int i = 0; i < 3; ++i) r = (r + v / r) / 2;
  return r * scale;
}

// Squared distance from (x, y) to the 2D segment from (x0, y0) to (x1, y1).
inline OracleReal segment2(OracleReal x, OracleReal y, OracleReal x0, OracleReal y0, OracleReal x1,
                           OracleReal y1) {
  const OracleReal dx = x1 - x0, dy = y1 - y0, px = x - x0, py = y - y0;
  const OracleReal dd = dx * dx + dy * dy;
  OracleReal t = dd > 0 ? (px * dx + py * dy) / dd : 0;
  t = std::min<OracleReal>(1, std::max<OracleReal>(0, t));
  const OracleReal ex = px - t * dx, ey = py - t * dy;
  return ex * ex + ey * ey;
}

}  // namespace oracle_detail

/// Squared distance from p to triangle (a, b, c), in OracleReal (see the file comment).
inline OracleReal oracle_distance2(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                   const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  using oracle_detail::V3;
  const V3 v[3] = {V3(a), V3(b), V3(c)};
  int k = 0;
  OracleReal l2 = -1;
  for (int i = 0; i < 3; ++i) {
    const V3 e = v[(i + 1) % 3] - v[i];
    if (e.dot(e) > l2) {
      l2 = e.dot(e);
      k = i;
    }
  }
  const V3 &p0 = v[k], &p1 = v[(k + 1) % 3], &p2 = v[(k + 2) % 3];
  const V3 ap = V3(p) - p0;
  if (!(l2 > 0)) return ap.dot(ap);  // one point
  const OracleReal len = oracle_detail::root(l2);
  const V3 ux = (p1 - p0) * (1 / len);
  const OracleReal x = ap.dot(ux);
  const V3 r = p2 - p0;
  const OracleReal x2 = r.dot(ux);
  const V3 h = r - ux * x2;
  const OracleReal w = oracle_detail::root(h.dot(h));
  // Collinear to within 2^-56 len: the segment p0 p1, within u len / 8 of p2. (Below
  // that, the direction of h is mostly rounding: exactly collinear corners give a
  // nonzero h of order u_q len.)
  if (!(w > len * static_cast<OracleReal>(std::ldexp(1.0, -56)))) {
    const OracleReal t = std::min(len, std::max<OracleReal>(0, x));
    const V3 e = ap - ux * t;
    return e.dot(e);
  }
  const V3 uy = h * (1 / w);
  const V3 uz = ux.cross(uy);
  const OracleReal y = ap.dot(uy), z = ap.dot(uz);
  // 2D triangle (0, 0), (len, 0), (x2, w), counter-clockwise.
  const bool inside =
      y >= 0 && (x2 - len) * y - w * (x - len) >= 0 && -x2 * (y - w) + w * (x - x2) >= 0;
  OracleReal d2 = 0;
  if (!inside) {
    d2 = std::min({oracle_detail::segment2(x, y, 0, 0, len, 0),
                   oracle_detail::segment2(x, y, len, 0, x2, w),
                   oracle_detail::segment2(x, y, x2, w, 0, 0)});
  }
  return z * z + d2;
}

/// Distance from p to triangle (a, b, c), rounded to double.
inline double oracle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return static_cast<double>(oracle_detail::root(oracle_distance2(p, a, b, c)));
}

/// Distance from points to a mesh, by branch and bound over the triangles' bounding boxes
/// (computed once, for many queries): every triangle whose box is not provably farther
/// than the best so far is evaluated by oracle_distance2, starting with the one of the
/// nearest box. Holds a reference to the mesh.
class OracleMesh {
 public:
  explicit OracleMesh(const TriangleMesh& m) : mesh_(m), lo_(m.triangles.size()), hi_(lo_) {
    for (std::size_t t = 0; t < lo_.size(); ++t) {
      const Eigen::Vector3d &a = m.corner(t, 0), &b = m.corner(t, 1), &c = m.corner(t, 2);
      lo_[t] = a.cwiseMin(b).cwiseMin(c);
      hi_[t] = a.cwiseMax(b).cwiseMax(c);
    }
  }

  /// The distance from p to the mesh; also the index of a nearest triangle.
  double distance(const Eigen::Vector3d& p, int* nearest = nullptr) const {
    std::size_t first = 0;
    double first_lower = lower(0, p);
    for (std::size_t t = 1; t < lo_.size(); ++t) {
      const double l = lower(t, p);
      if (l < first_lower) {
        first = t;
        first_lower = l;
      }
    }
    const TriangleMesh& m = mesh_;
    OracleReal best2 =
        oracle_distance2(p, m.corner(first, 0), m.corner(first, 1), m.corner(first, 2));
    double best = static_cast<double>(oracle_detail::root(best2));
    if (nearest != nullptr) *nearest = static_cast<int>(first);
    for (std::size_t t = 0; t < lo_.size(); ++t) {
      if (t == first || lower(t, p) > best) continue;
      const OracleReal d2 = oracle_distance2(p, m.corner(t, 0), m.corner(t, 1), m.corner(t, 2));
      if (d2 < best2) {
        best2 = d2;
        best = static_cast<double>(oracle_detail::root(d2));
        if (nearest != nullptr) *nearest = static_cast<int>(t);
      }
    }
    return best;
  }

 private:
  // The distance from p to triangle t's box (hypot where squares could overflow), rounded
  // down by far more than its rounding error.
  double lower(std::size_t t, const Eigen::Vector3d& p) const {
    const Eigen::Vector3d d = (lo_[t] - p).cwiseMax(p - hi_[t]).cwiseMax(0.0);
    const double box =
        d.maxCoeff() < 1e150 ? std::sqrt(d.squaredNorm()) : std::hypot(d.x(), d.y(), d.z());
    return box * (1 - 1e-14);
  }

  const TriangleMesh& mesh_;
  std::vector<Eigen::Vector3d> lo_, hi_;
};

/// OracleMesh(m).distance(p, nearest), for a single query.
inline double oracle_mesh_distance(const TriangleMesh& m, const Eigen::Vector3d& p,
                                   int* nearest = nullptr) {
  return OracleMesh(m).distance(p, nearest);
}

}  // namespace medspheres::test
