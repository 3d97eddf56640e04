// The point-triangle kernel of point_triangle.h: its accuracy, derived, and the paths
// that are not inlined.
//
// Accuracy. Let u = 2^-53 (half of machine epsilon), a the triangle's first corner, L
// its longest edge, 2A = |(b - a) x (c - a)| twice its area, kappa = L^2 / 2A (1.15 for
// an equilateral triangle, at least 1 / sin of the smallest angle) and
// S = |p| + |p - a| + L. For every shape of triangle, the kernel returns a
// point within C u S of the triangle, at a distance from p within C u S of the true
// distance, C a small constant. (|p| is there because rounding the returned point's
// coordinates alone costs u |p|.) tests/mesh_query_test.cpp checks C <= 32 against a
// 113-bit oracle; measured, C < 2 on the thin path for widths 1e-2 .. 1e-16, C < 6 on
// the regular path, and C <= 16 (the inradius bound below) on degenerate triangles
// just under the threshold. The path is chosen once per triangle, by prepare_triangle:
//
// - Regular (kappa <= kThinKappa = 8; over 91% of the triangles of every one of the test
//   meshes of tests/support/shared_meshes.h, 100% of most): Ericson's Voronoi-region
//   walk (Real-Time Collision Detection, 5.1.5). To first order: each dot product d = e.(p - v)
//   (edge e, corner v) is off by ~6 u |e| S. The edge tests va, vb, vc equal 2A |e| s_e, s_e the
//   signed in-plane distance of p's projection to the line of edge e; where the region matters (the
//   projection within 2L of the triangle) they are off by ~70 u |e_1| |e_2| L S, so a
//   projection is put on the wrong side of an edge line only within ~70 kappa u S of
//   it. Edge parameters (d1 / (d1 - d3) and the like) are off by ~25 kappa u S along
//   the edge (2A <= L |e| bounds L / |e| by kappa). The vertex regions are tested first,
//   by slab tests off by only ~6 u S, so a wrong side near a sharp corner is still
//   caught there. In the face region the point is the projection p - (n.(p - a)) n with
//   the accurate normal n below, off by ~4 u S. So the error is O(kappa u S) (measured:
//   about 1.5 kappa u S at worst). The face point is not taken as a + v ab + w ac,
//   with v and w the quotients of va, vb, vc by their sum 4 A^2: that point is off by
//   O(kappa^2 u S), eps / width^2 on slivers.
//   Why 8: the regular path's error grows like kappa and the thin path's does not, but
//   the thin path costs more (a cross product per edge line it tests). At kappa <= 8
//   the regular path measures below 6 u S, less than the degenerate path's 16, and at
//   most 9% of the triangles of any of the test meshes take the thin path.
// - Thin (kappa > kThinKappa): the same seven regions, each told by tests that are well
//   conditioned whatever the shape. A vertex or edge region by slab tests along each
//   edge (dot products with that edge, measured from that edge's own corners: off by
//   ~6 u S in distance units) and, for an edge, the side of its line in the plane, by
//   the sign of (n x e).(p - v), off by ~10 u S given n accurate to a few u. These
//   describe each region exactly, in any order, so a wrong answer from any one test
//   only moves the point by as much as that test's error. The face needs p's
//   projection inside the three edge lines and inside the slab of the longest edge: the
//   three lines alone would admit projections up to 10 u S / sin(t / 2) beyond a
//   corner of angle t, unbounded on slivers, but the slab cuts them off at the two
//   ends of the longest edge, and the third corner, opposite the longest edge, has the
//   largest angle, at least 60 degrees; a projection wrongly taken as inside is then
//   within ~20 u S of the triangle. The face point is the projection, off by ~4 u S,
//   edge points have their parameter off by ~4 u S along the edge. If rounding puts p
//   in no region, p is within a few u S of a region boundary and the nearest of the
//   three edge points is as good.
// - Degenerate (2A <= kDegenerateArea L^2, which includes zero-length edges and
//   collinear corners): the nearest point of the three edge segments, as the segment
//   or point the triangle is. If the triangle has any area at all, its points are
//   within its inradius 2A / perimeter <= kDegenerateArea L / 2 = 16 u L of its edges.
//
// The accurate normal. A sliver's normal is ill-conditioned in its rounded edges: a
// relative error u in b - a turns the computed normal by u L / width. n is therefore
// computed from the exact edge differences (two-term expansions) and exact products
// (fma), once per triangle at build time: its error is a few u |n| + O(u^2 L^2), that is
// a few u in direction as long as 2A >= kDegenerateArea L^2 = 32 u L^2.

#include "medspheres/point_triangle.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace medspheres {
namespace detail {
namespace {

// Triangles whose kappa = longest edge^2 / (2 area) exceeds this take the thin path (see
// above). An equilateral triangle has kappa = 1.15, a right isosceles one 2; kappa = 8 is
// about a right triangle with legs 1 and 1/8 (smallest angle 7 degrees) or an isosceles
// one with base 1 and height 1/8 (14 degrees).
constexpr double kThinKappa = 8.0;
// Triangles with 2 area <= this times longest edge^2 are queried as their edges.
constexpr double kDegenerateArea = 0x1p-48;

// x - y = hi + lo exactly (Knuth's two-sum of x and -y).
struct TwoTerm {
  double hi = 0.0, lo = 0.0;
};
TwoTerm exact_difference(double x, double y) {
  const double s = x - y;
  const double z = s - x;
  return {s, (x - (s - z)) - (y + z)};
}

// x y - fl(x y), exactly: one fma where the target has the instruction; otherwise
// Dekker's product of Veltkamp's halves, which is exact (and equal to the fma) when
// neither the halves overflow nor the partial products underflow, that is for
// 2^-450 <= |x|, |y| <= 2^500, and std::fma (a library call) outside that range.
double product_error(double x, double y, double xy) {
#if defined(__FMA__)
  return std::fma(x, y, -xy);
#else
  const double ax = std::abs(x), ay = std::abs(y);
  if (!(ax >= 0x1p-450 && ax <= 0x1p500 && ay >= 0x1p-450 && ay <= 0x1p500))
    return x == 0.0 || y == 0.0 ? 0.0 : std::fma(x, y, -xy);
  constexpr double kSplit = 0x1p27 + 1.0;
  const double cx = kSplit * x, xh = cx - (cx - x), xl = x - xh;
  const double cy = kSplit * y, yh = cy - (cy - y), yl = y - yh;
  return ((xh * yh - xy) + xh * yl + xl * yh) + xl * yl;
#endif
}

// (b - a) x (c - a) for exact corners, with an error of a few ulps of the result plus
// O(u^2 |b - a| |c - a|). Each component x_j y_k - x_k y_j is expanded over the exact
// two-term edges: the leading products are exact (product_error), their difference is exact
// (two-sum), and the remaining terms are O(u |x| |y|) and rounded once more.
Eigen::Vector3d accurate_cross(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c) {
  TwoTerm x[3], y[3];
  for (int i = 0; i < 3; ++i) {
    x[i] = exact_difference(b[i], a[i]);
    y[i] = exact_difference(c[i], a[i]);
  }
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const double p1 = x[j].hi * y[k].hi, e1 = product_error(x[j].hi, y[k].hi, p1);
    const double p2 = x[k].hi * y[j].hi, e2 = product_error(x[k].hi, y[j].hi, p2);
    const TwoTerm lead = exact_difference(p1, p2);
    const double tail = lead.lo + (e1 - e2) + (x[j].hi * y[k].lo + x[j].lo * y[k].hi) -
                        (x[k].hi * y[j].lo + x[k].lo * y[j].hi) +
                        (x[j].lo * y[k].lo - x[k].lo * y[j].lo);
    out[i] = lead.hi + tail;
  }
  return out;
}

// Closest point of segment [s, s + d] to p.
Eigen::Vector3d closest_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& s,
                                   const Eigen::Vector3d& d) {
  const double dd = d.dot(d);
  if (!(dd > 0.0)) return s;
  const double t = std::clamp(d.dot(p - s) / dd, 0.0, 1.0);
  return s + t * d;
}

// The nearest point of the triangle's three edges; ties to ab, then ca, then bc.
Eigen::Vector3d closest_on_edges(const Eigen::Vector3d& p, const QueryTriangle& t) {
  const Eigen::Vector3d b = t.a + t.ab;
  const Eigen::Vector3d q0 = closest_on_segment(p, t.a, t.ab);
  const Eigen::Vector3d q1 = closest_on_segment(p, t.a, t.ac);
  const Eigen::Vector3d q2 = closest_on_segment(p, b, t.ac - t.ab);
  const double e0 = (p - q0).squaredNorm(), e1 = (p - q1).squaredNorm(),
               e2 = (p - q2).squaredNorm();
  if (e0 <= e1 && e0 <= e2) return q0;
  return e1 <= e2 ? q1 : q2;
}

// The thin path (see above): the Voronoi regions of the triangle, each told by tests that
// stay well conditioned whatever its shape. Vertex and edge regions by slab tests along
// each edge (dot products with that edge, measured from its own corners) and, for an
// edge, the side of its line in the plane (the in-plane normals n x ab, ac x n and n x bc
// point inward, n being along ab x ac); the face by the three line sides and the slab of
// the longest edge. \p n is the accurate unit normal.
Eigen::Vector3d closest_on_thin(const Eigen::Vector3d& p, const QueryTriangle& t,
                                const Eigen::Vector3d& n) {
  const Eigen::Vector3d ap = p - t.a;
  const double d1 = t.ab.dot(ap), d2 = t.ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return t.a;  // vertex a
  const Eigen::Vector3d bc = t.ac - t.ab, bp = ap - t.ab, cp = ap - t.ac;
  const double d3 = t.ab.dot(bp), e1 = bc.dot(bp);  // ab.(p-b), bc.(p-b)
  if (d3 >= 0.0 && e1 <= 0.0) return t.a + t.ab;    // vertex b
  const double d6 = t.ac.dot(cp), e2 = bc.dot(cp);  // ac.(p-c), bc.(p-c)
  if (d6 >= 0.0 && e2 >= 0.0) return t.a + t.ac;    // vertex c
  // Edge parameter num / den within (0, 1], without 0 / 0 if den underflowed.
  auto fraction = [](double num, double den) { return num < den ? num / den : 1.0; };
  const double s_ab = n.cross(t.ab).dot(ap);
  const bool in_ab = d1 >= 0.0 && d3 <= 0.0;
  if (s_ab < 0.0 && in_ab) return t.a + fraction(d1, t.ab_ab) * t.ab;  // edge ab
  const double s_ac = t.ac.cross(n).dot(ap);
  const bool in_ac = d2 >= 0.0 && d6 <= 0.0;
  if (s_ac < 0.0 && in_ac) return t.a + fraction(d2, t.ac_ac) * t.ac;  // edge ac
  const double s_bc = n.cross(bc).dot(bp);
  const bool in_bc = e1 >= 0.0 && e2 <= 0.0;
  if (s_bc < 0.0 && in_bc) return t.a + t.ab + fraction(e1, bc.dot(bc)) * bc;  // edge bc
  const bool in_longest = t.longest == 0 ? in_ab : t.longest == 1 ? in_bc : in_ac;
  if (s_ab >= 0.0 && s_ac >= 0.0 && s_bc >= 0.0 && in_longest) return p - n.dot(ap) * n;
  // Rounding put p in no region, so it is within a few u S of a boundary between
  // regions, where the nearest edge point is as good.
  return closest_on_edges(p, t);
}

}  // namespace

namespace {

// The corner, edges, dot products and longest edge of (a, b, c); returns the longest
// edge's squared length.
double fill_edges(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  QueryTriangle* t) {
  t->a = a;
  t->ab = b - a;
  t->ac = c - a;
  t->ab_ab = t->ab.dot(t->ab);
  t->ab_ac = t->ab.dot(t->ac);
  t->ac_ac = t->ac.dot(t->ac);
  const double l2[3] = {t->ab_ab, (c - b).squaredNorm(), t->ac_ac};
  t->longest = static_cast<std::uint8_t>(std::max_element(l2, l2 + 3) - l2);
  return l2[t->longest];
}

// The path of a triangle whose accurate 2 area is area2 (see above).
TriangleShape shape_of(double area2, double longest2) {
  if (!(area2 > kDegenerateArea * longest2)) return TriangleShape::kDegenerate;
  return longest2 > kThinKappa * area2 ? TriangleShape::kThin : TriangleShape::kRegular;
}

// The accurate normal, as prepare_triangle stores it.
Eigen::Vector3d accurate_normal(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                const Eigen::Vector3d& c) {
  return accurate_cross(a, b, c).normalized();
}

}  // namespace

PreparedTriangle prepare_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                  const Eigen::Vector3d& c) {
  PreparedTriangle out;
  QueryTriangle& t = out.triangle;
  const double longest2 = fill_edges(a, b, c, &t);
  const Eigen::Vector3d cross = accurate_cross(a, b, c);
  t.shape = shape_of(cross.norm(), longest2);
  if (t.shape == TriangleShape::kDegenerate) return out;  // a zero plane: a bound of zero
  // The plane bound: for any unit n and any point x = a + s ab + t ac of the triangle
  // (s, t >= 0, s + t <= 1), |p - x| >= |n.(p - x)| >= |n.(p - a)| - max(|n.ab|, |n.ac|).
  // With the accurate normal the last term is a few ulps of the edges for every
  // non-degenerate shape; either way the bound holds. `error` is that term plus the
  // rounding of computing it.
  TrianglePlane& plane = out.plane;
  plane.normal = cross.normalized();
  plane.offset = plane.normal.dot(t.a);
  const double leak = std::max(std::abs(plane.normal.dot(t.ab)), std::abs(plane.normal.dot(t.ac)));
  const double rounding = 4.0 * std::numeric_limits<double>::epsilon() *
                          (t.ab.cwiseAbs().sum() + t.ac.cwiseAbs().sum());
  plane.error = leak + rounding;
  return out;
}

Eigen::Vector3d closest_on_irregular(const Eigen::Vector3d& p, const QueryTriangle& t,
                                     const Eigen::Vector3d& n) {
  return t.shape == TriangleShape::kThin ? closest_on_thin(p, t, n) : closest_on_edges(p, t);
}

}  // namespace detail

// The one-off query gives the prepared query's answer, bit for bit, without paying for
// the accurate cross product where the answer does not depend on it. The plain cross
// product P of the rounded edges is within 16 u (|ab|^2 + |ac|^2) of the exact one (each
// component's two products and difference are off by ~3 u of |x_j y_k| + |x_k y_j|, whose
// sum over the components is at most 1.5 (|ab|^2 + |ac|^2), and the rounded edges add as
// much), and the accurate one's norm is within a few u of the exact. So when |P| minus that
// slack still passes both tests of shape_of, the triangle is regular, and the accurate
// normal is needed only in the face region. Otherwise (near a threshold, thin or
// degenerate) the triangle is prepared in full.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  detail::QueryTriangle t;
  const double longest2 = detail::fill_edges(a, b, c, &t);
  const double slack = 0x1p-48 * (t.ab_ab + t.ac_ac);
  const double area2_low = t.ab.cross(t.ac).norm() - slack;
  if (detail::shape_of(area2_low, longest2) == detail::TriangleShape::kRegular)
    return detail::closest_on_triangle_with(p, t, [&] { return detail::accurate_normal(a, b, c); });
  const detail::PreparedTriangle full = detail::prepare_triangle(a, b, c);
  return detail::closest_on_triangle(p, full.triangle, full.plane.normal);
}

}  // namespace medspheres
