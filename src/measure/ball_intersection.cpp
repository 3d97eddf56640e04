#include "ball_intersection.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "medspheres/assert.h"

namespace medspheres::detail {

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;

double clamp_nonnegative(double x) {
  return x > 0.0 ? x : 0.0;
}

// The pair geometry of local vertices v and w of a triangle (edge 3 - v - w).
const PairGeometry& edge_of(const PairGeometry* const edges[3], int v, int w) {
  return *edges[3 - v - w];
}

// Signed distance from c_v to the radical plane of (v, w), towards c_w.
double a_from(const PairGeometry& g, int v, int w) {
  return g.a[v < w ? 0 : 1];
}
double h_from(const PairGeometry& g, int v, int w) {
  return g.h[v < w ? 0 : 1];
}

// The pole chosen on sphere v for the circle it shares with ball w: +1 for the axis
// towards c_w when the cap of sphere v inside ball w is at most a hemisphere, -1 for the
// opposite axis otherwise. Either choice gives an exact identity; this one keeps the
// spherical triangles of the corner terms away from antipodal vertices, where their
// area would jump between 0 and 2 pi under rounding.
int pole(double h, double r) {
  return h <= r ? 1 : -1;
}

// sigma - cos(beta), beta the angular radius of the circle seen from the centre of
// sphere v: h / r for the near pole, -(2 r - h) / r for the far one. Both are small when
// the circle degenerates to a point, which is what makes the arc terms well-conditioned.
double pole_weight(int sigma, double h, double r) {
  return sigma > 0 ? h / r : -(2.0 * r - h) / r;
}

// Six times the volume of the tetrahedron of centres c[0..3], as a triple product from the
// vertex whose three edges have the least product of lengths: its rounding error is a few
// eps times that product, and the difference of two nearby centres is exact. A needle (one
// far centre, three close ones) keeps its volume, which the far vertex would bury under
// eps |e|^3, and with it the dihedral angles atan2(|e| 6V, n0 . n1).
template <class Length>
double six_tetrahedron_volume(const Eigen::Vector3d c[4], const Length& length) {
  int origin = 0;
  double least = 0.0;
  for (int o = 0; o < 4; ++o) {
    double product = 1.0;
    for (int v = 0; v < 4; ++v)
      if (v != o) product *= length(o, v);
    if (o == 0 || product < least) {
      origin = o;
      least = product;
    }
  }
  const int x = (origin + 1) % 4, y = (origin + 2) % 4, z = (origin + 3) % 4;
  return std::abs((c[x] - c[origin]).dot((c[y] - c[origin]).cross(c[z] - c[origin])));
}

}  // namespace

PairGeometry pair_geometry(const Eigen::Vector3d& c0, double r0, const Eigen::Vector3d& c1,
                           double r1) {
  PairGeometry g;
  const double d = (c1 - c0).norm();
  MEDSPHERES_ASSERT(d > 0.0);
  g.d = d;
  // No cancellation beyond the one inherent in the data: the radii are subtracted first,
  // so that d + (r1 - r0) is within a few eps of d when d << r (two nearly coincident balls
  // of equal radius); (d - r0) + r1 would round at the scale of r0, and h = r d / d would
  // carry an error of eps r^2 / d. The exact predicates guarantee the factors >= 0.
  const double overlap = clamp_nonnegative(r0 + r1 - d);  // 0: externally tangent
  const double room0 = clamp_nonnegative(d + (r1 - r0));  // 0: ball 1 inside ball 0, tangent
  const double room1 = clamp_nonnegative(d + (r0 - r1));  // 0: ball 0 inside ball 1, tangent
  g.h[0] = std::min(overlap * room0 / (2.0 * d), 2.0 * r0);
  g.h[1] = std::min(overlap * room1 / (2.0 * d), 2.0 * r1);
  g.a[0] = r0 - g.h[0];
  g.a[1] = r1 - g.h[1];
  g.rho2 = overlap * (r0 + r1 + d) * room0 * room1 / (4.0 * d * d);
  return g;
}

Measure pair_measure(const PairGeometry& g, double r0, double r1) {
  Measure m;
  m.volume =
      kPi / 3.0 * (g.h[0] * g.h[0] * (3.0 * r0 - g.h[0]) + g.h[1] * g.h[1] * (3.0 * r1 - g.h[1]));
  m.area = 2.0 * kPi * (r0 * g.h[0] + r1 * g.h[1]);
  return m;
}

TripleGeometry triple_geometry(const Eigen::Vector3d c[3], const double r[3],
                               const PairGeometry* const edges[3], TriplePoints* points) {
  TripleGeometry g;
  double sin_g[3], cos_g[3];
  Eigen::Vector3d normal[3];
  for (int v = 0; v < 3; ++v) {
    const int w = (v + 1) % 3, x = (v + 2) % 3;
    const Eigen::Vector3d p = c[w] - c[v], q = c[x] - c[v];
    normal[v] = p.cross(q);  // (c1 - c0) x (c2 - c0) for every v (cyclic order)
    const double lengths = edge_of(edges, v, w).d * edge_of(edges, v, x).d;
    sin_g[v] = normal[v].norm() / lengths;
    cos_g[v] = p.dot(q) / lengths;
  }
  // The cross product of the two shorter edges is the most accurate one.
  int widest = 0;
  for (int v = 1; v < 3; ++v)
    if (edges[v]->d > edges[widest]->d) widest = v;
  g.area = 0.5 * normal[widest].norm();

  // s[q], the offset of the radical line in the plane of circle q = (v, w), from the
  // endpoint whose angle is better conditioned.
  double s[3];
  for (int q = 0; q < 3; ++q) {
    const int v = (q + 1) % 3, w = (q + 2) % 3;
    const int from = sin_g[v] >= sin_g[w] ? v : w, to = from == v ? w : v;
    s[q] = (a_from(edge_of(edges, from, q), from, q) -
            a_from(edge_of(edges, from, to), from, to) * cos_g[from]) /
           sin_g[from];
  }
  int roomiest = 0;
  for (int q = 1; q < 3; ++q)
    if (edges[q]->rho2 > edges[roomiest]->rho2) roomiest = q;
  const double rho = std::sqrt(edges[roomiest]->rho2), offset = std::abs(s[roomiest]);
  g.t = std::sqrt(clamp_nonnegative((rho - offset) * (rho + offset)));

  for (int q = 0; q < 3; ++q) g.psi[q] = std::atan2(g.t, s[q]);
  for (int v = 0; v < 3; ++v) {
    const int w = (v + 1) % 3, x = (v + 2) % 3;
    const PairGeometry& ew = edge_of(edges, v, w);
    const PairGeometry& ex = edge_of(edges, v, x);
    const int sw = pole(h_from(ew, v, w), r[v]), sx = pole(h_from(ex, v, x), r[v]);
    // Van Oosterom-Strackee for the spherical triangle (p, sw u_vw, sx u_vx) on the unit
    // sphere about c_v, p the direction to a triple point: its determinant is
    // t sin(g_v) / r_v, its dot products a_vw / r_v, a_vx / r_v and cos(g_v).
    g.excess[v] = 2.0 * std::atan2(g.t * r[v] * sin_g[v],
                                   r[v] * r[v] * (1.0 + sw * sx * cos_g[v]) +
                                       r[v] * (sw * a_from(ew, v, w) + sx * a_from(ex, v, x)));
  }
  if (points != nullptr) {
    points->n = normal[widest] / normal[widest].norm();
    const Eigen::Vector3d u01 = (c[1] - c[0]) / edges[2]->d;
    points->z = c[0] + edges[2]->a[0] * u01 + s[2] * points->n.cross(u01);
  }
  return g;
}

Measure triple_measure(const TripleGeometry& g, const double r[3],
                       const PairGeometry* const edges[3]) {
  Measure m;
  for (int v = 0; v < 3; ++v) {
    const int w = (v + 1) % 3, x = (v + 2) % 3;
    const PairGeometry& ew = edge_of(edges, v, w);
    const PairGeometry& ex = edge_of(edges, v, x);
    const double hw = h_from(ew, v, w), hx = h_from(ex, v, x);
    const int sw = pole(hw, r[v]), sx = pole(hx, r[v]);
    // Solid angle of the two-gon of sphere v inside the other two balls.
    double omega = 2.0 * (pole_weight(sw, hw, r[v]) * g.psi[x] +
                          pole_weight(sx, hx, r[v]) * g.psi[w] - sw * sx * g.excess[v]);
    if (sw < 0 && sx < 0) omega += 4.0 * kPi;
    m.area += r[v] * r[v] * omega;
    m.volume += r[v] * r[v] * r[v] * omega / 3.0;
  }
  for (int q = 0; q < 3; ++q) m.volume -= edges[q]->d * edges[q]->rho2 * g.psi[q] / 3.0;
  m.volume += 2.0 / 3.0 * g.area * g.t;
  return m;
}

Measure quadruple_measure(const Eigen::Vector3d c[4], const double r[4],
                          const PairGeometry* const edges[4][4],
                          const TripleGeometry* const faces[4]) {
  auto edge = [&](int v, int w) -> const PairGeometry& {
    return v < w ? *edges[v][w] : *edges[w][v];
  };
  auto length = [&](int v, int w) { return edge(v, w).d; };
  const double six_volume = six_tetrahedron_volume(c, length);
  // Index of tet vertex v among the vertices of the face opposite x.
  auto local = [](int v, int x) { return v - (v > x ? 1 : 0); };

  double phi[4][4] = {}, dihedral[4][4] = {};
  for (int a = 0; a < 4; ++a) {
    for (int b = a + 1; b < 4; ++b) {
      int o[2], k = 0;
      for (int v = 0; v < 4; ++v)
        if (v != a && v != b) o[k++] = v;
      // e x (c_o - c_a) = e x (c_o - c_b): the shorter difference rounds less.
      const Eigen::Vector3d e = c[b] - c[a];
      auto normal = [&](int far) {
        return e.cross(c[far] - c[length(far, a) <= length(far, b) ? a : b]);
      };
      const Eigen::Vector3d n0 = normal(o[0]), n1 = normal(o[1]);
      // |n0 x n1| = |e| * |det(e, c_o0 - c_a, c_o1 - c_a)|.
      const double delta = std::atan2(edges[a][b]->d * six_volume, n0.dot(n1));
      // Arc of the circle of (a, b) inside ball o0 comes from the face (a, b, o0), the
      // face opposite o1, and the other way round.
      const double psi0 = faces[o[1]]->psi[local(o[0], o[1])];
      const double psi1 = faces[o[0]]->psi[local(o[1], o[0])];
      dihedral[a][b] = dihedral[b][a] = delta;
      phi[a][b] = phi[b][a] = psi0 + psi1 - delta;
    }
  }
  Measure m;
  for (int a = 0; a < 4; ++a) {
    int sigma[4] = {0, 0, 0, 0};
    double omega = -kPi;
    for (int b = 0; b < 4; ++b) {
      if (b == a) continue;
      const double h = h_from(edge(a, b), a, b);
      sigma[b] = pole(h, r[a]);
      omega += sigma[b] * dihedral[a][b] + pole_weight(sigma[b], h, r[a]) * phi[a][b];
    }
    for (int x = 0; x < 4; ++x) {
      if (x == a) continue;
      int y = -1, z = -1;
      for (int v = 0; v < 4; ++v) {
        if (v == a || v == x) continue;
        (y < 0 ? y : z) = v;
      }
      omega -= sigma[y] * sigma[z] * faces[x]->excess[local(a, x)];
      if (sigma[y] < 0 && sigma[z] < 0) omega += 2.0 * kPi;
    }
    m.area += r[a] * r[a] * omega;
    m.volume += r[a] * r[a] * r[a] * omega / 3.0;
  }
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      m.volume -= edges[a][b]->d * edges[a][b]->rho2 * phi[a][b] / 6.0;
  for (int x = 0; x < 4; ++x) m.volume += faces[x]->area * faces[x]->t / 3.0;
  m.volume -= six_volume / 6.0;
  return m;
}

}  // namespace medspheres::detail
