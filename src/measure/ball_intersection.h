#pragma once
// Private: closed forms for the volume of the intersection of two, three and four balls
// that span a simplex of the dual complex of their union, and for the area of the part
// of each sphere that lies inside the other balls of the simplex. No CGAL here.
//
// Notation: balls B_i = (c_i, r_i), spheres S_i, power pi_i(x) = |x - c_i|^2 - r_i^2,
// d_ij = |c_j - c_i|, u_ij = (c_j - c_i) / d_ij. The radical plane of ij lies at signed
// distance a_ij = (d_ij^2 + r_i^2 - r_j^2) / (2 d_ij) from c_i along u_ij; the cap of S_i
// inside B_j has height h_ij = r_i - a_ij; the circle C_ij = S_i n S_j has radius rho_ij.
// Lengths are in the caller's units, angles in radians.
//
// (1) Decomposition. Let I be the intersection of the balls of a simplex and W_i the
// points of I where pi_i is the largest: W_i = B_i cut by the radical planes of the pairs
// ij, a convex body whose curved face is F_i = S_i n (the other balls). The divergence
// theorem with apex c_i and a_ij + a_ji = d_ij give
//   vol(I) = (1/3) sum_i r_i^3 Omega_i - (1/3) sum_{i<j} d_ij area(D_ij),
// Omega_i the solid angle of F_i seen from c_i, D_ij the flat face shared by W_i and W_j.
// The areas of the sphere pieces are r_i^2 Omega_i.
//
// (2) Solid angles, by Gauss-Bonnet. F_i is bounded by arcs of the circles C_ij, an arc
// of angle phi on C_ij has total geodesic curvature phi cos(beta_ij), cos(beta_ij) =
// a_ij / r_i, and F_i has exterior angles theta at its corners:
//   Omega_i = 2 pi - sum_arcs cos(beta_ij) phi_ij - sum_corners theta.
// On the unit sphere about c_i a corner p and the poles U_j = u_ij, U_k = u_ik form a
// spherical triangle whose angle at U_j is the half-arc psi_ij (below) and whose angle at
// p is theta, so theta = pi + E - psi_ij - psi_ik, E its area. Substituting removes the
// arc angles of degenerate circles from the result. The same holds with the antipodal
// pole -U_j (colunar triangle); we take -U_j when the cap is more than a hemisphere
// (h_ij > r_i), so that in every case the weight of psi_ij is
//   w_ij = sigma_ij - cos(beta_ij) = h_ij / r_i (sigma = +1) or -(2 r_i - h_ij) / r_i (-1),
// which is small whenever C_ij is a small circle, tangent balls included, and E has no
// side near pi (its Van Oosterom-Strackee denominator stays positive).
//
// Two balls (an edge). F_i is a cap; vol(I) is the sum of two caps pi h^2 (3 r - h) / 3.
//
// Three balls (a triangle of K): the spheres meet in p = z +- t n, z in the plane of the
// centres, t >= 0. In the plane of C_ij the radical line of the triple is at signed
// distance s_ij from the circle centre (positive when the centre is outside B_k), and the
// arc of C_ij inside B_k has half-angle psi_ij = atan2(t, s_ij). With g_i the angle of
// the centre triangle at c_i,
//   s_ij = (a_ik - a_ij cos g_i) / sin g_i,     t^2 = rho_ij^2 - s_ij^2,
//   E_i  = 2 atan2(t r_i sin g_i, r_i^2 (1 + s_j s_k cos g_i) + r_i (s_j a_ij + s_k a_ik)),
//   Omega_i = 2 (w_ij psi_ij + w_ik psi_ik - s_j s_k E_i) + (4 pi if s_j = s_k = -1),
// (s_j = sigma_ij, s_k = sigma_ik). D_ij is the circular segment of C_ij inside B_k, of
// area rho^2 psi - s t; summing d_ij s_ij t over the edges gives 2 A t (A the area of the
// centre triangle), so
//   vol = (1/3) sum_i r_i^3 Omega_i - (1/3) sum_ij d_ij rho_ij^2 psi_ij + (2/3) A t.
//
// Four balls (a tetrahedron of K, so its power centre z lies in all four balls). In the
// plane of C_ij the radical lines of ijk and ijl cross at z inside the disc, so the
// points where they meet C_ij alternate around it and the arc inside B_k and B_l is one
// arc, of angle
//   phi_ij = psi_ij(k) + psi_ij(l) - delta_ij,
// delta_ij the dihedral angle of the centre tetrahedron at ij. F_i is a spherical
// triangle whose corners are the triple points of the faces at i, with the exterior
// angles of those faces; the angle sums of the three corner triangles give
//   Omega_i = -pi + sum_j (sigma_ij delta_ij + w_ij phi_ij)
//             - sum_{faces f at i} (sigma sigma' E_i(f) - 2 pi [sigma = sigma' = -1]),
// sigma, sigma' the poles of the two edges of f at i. D_ij is the part of the disc in the
// wedge of the two radical lines at z: rho^2 phi / 2 minus two triangles with apex z.
// Summed over the edges with weights d_ij, z drops out (the sum over faces of area times
// height of z is three times the tetrahedron's volume), leaving
//   vol = (1/3) sum_i r_i^3 Omega_i - (1/6) sum_ij d_ij rho_ij^2 phi_ij
//         + (1/3) sum_faces A_f t_f - vol(centre tetrahedron).
// The power centre of the tetrahedron, ill-conditioned when it is flat, is never formed.
//
// Numerics. Near tangency the arguments of the square roots cancel: rho_ij^2 is the
// product (r_i + r_j - d)(r_i + r_j + d)(d - r_i + r_j)(d + r_i - r_j) / (4 d^2) and t^2 is
// (rho - |s|)(rho + |s|), each factor one rounded sum, both clamped at 0 (the exact
// predicates that chose the simplex guarantee that they are >= 0; only rounding makes
// them negative). When three spheres almost touch in one point t is then known to about
// sqrt(eps) times their size only, but the formulas are smooth in t with a vanishing
// first derivative at t = 0 (the curved faces degenerate with zero slope), so the volume
// error stays of order eps r^3. No formula branches on a rounded value except the choice
// of pole, where both branches are exact identities and equally well conditioned, and the
// choice of the shortest edges for the centre tetrahedron's volume and the normals of its
// dihedral angles (the same identities, rounded least): a needle, one far centre and three
// close ones, keeps its volume, which the far vertex's triple product would bury under
// eps d^3 and with it the dihedral angles. One
// amplification remains: s_ij divides by sin g_i, so a triangle of K whose centres are
// almost collinear (small sin at every vertex) loses accuracy by that factor; such a
// triangle is in K only if its three spheres almost share a circle.

#include <Eigen/Core>

namespace medspheres::detail {

/// Volume of an intersection and total area of its spherical faces.
struct Measure {
  double volume = 0.0;
  double area = 0.0;
};

/// Two balls whose spheres meet: |r0 - r1| <= d <= r0 + r1, d > 0.
struct PairGeometry {
  double d = 0.0;        ///< |c1 - c0|
  double a[2] = {0, 0};  ///< a[q]: signed distance from c_q to the radical plane, towards the other
  double h[2] = {0, 0};  ///< h[q] = r_q - a[q]: height of the cap of S_q inside the other ball
  double rho2 = 0.0;     ///< squared radius of the circle where the spheres meet
};

PairGeometry pair_geometry(const Eigen::Vector3d& c0, double r0, const Eigen::Vector3d& c1,
                           double r1);

/// vol(B0 n B1) and area(S0 n B1) + area(S1 n B0).
Measure pair_measure(const PairGeometry& g, double r0, double r1);

/// Three balls whose spheres meet. Local vertex q is ball q; edge q is the pair opposite
/// vertex q: edge 0 = (1, 2), edge 1 = (0, 2), edge 2 = (0, 1).
struct TripleGeometry {
  double t = 0.0;                ///< half the distance between the two triple points
  double area = 0.0;             ///< area of the triangle of centres
  double psi[3] = {0, 0, 0};     ///< psi[q]: half-angle of the arc of circle q inside ball q
  double excess[3] = {0, 0, 0};  ///< excess[q]: area of the corner triangle E_q (see above)
};

/// Where the spheres of a triple meet: z +- t n, z in the plane of the centres.
struct TriplePoints {
  Eigen::Vector3d z = Eigen::Vector3d::Zero();  ///< midpoint of the two points
  Eigen::Vector3d n = Eigen::Vector3d::Zero();  ///< (c1 - c0) x (c2 - c0), normalised
};

/// \p edges[q] is the pair geometry of edge q. Fills \p points when it is not null.
TripleGeometry triple_geometry(const Eigen::Vector3d c[3], const double r[3],
                               const PairGeometry* const edges[3], TriplePoints* points = nullptr);

/// vol(B0 n B1 n B2) and the area of the part of each sphere inside the other two balls.
Measure triple_measure(const TripleGeometry& g, const double r[3],
                       const PairGeometry* const edges[3]);

/// Four balls spanning a tetrahedron of the dual complex. \p edges[a][b] (a < b) is the
/// pair geometry of local vertices a and b; \p faces[q] the triple geometry of the face
/// opposite local vertex q, whose local vertices are the other three in ascending order.
Measure quadruple_measure(const Eigen::Vector3d c[4], const double r[4],
                          const PairGeometry* const edges[4][4],
                          const TripleGeometry* const faces[4]);

}  // namespace medspheres::detail
