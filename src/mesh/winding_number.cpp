// Generalized winding numbers on the MeshQuery hierarchy (Barill et al. 2018).
#include <cmath>

#include "mesh_bvh.h"
#include "solid_angle.h"

namespace medspheres {

namespace {

constexpr double kFourPi = 4.0 * 3.14159265358979323846;

// Far-field approximation of the flux integral of g(x - p) = (x - p)/|x - p|^3 over a
// subtree, by Taylor expansion of g about y = centre - p (L = |y|, d = x - centre):
//   g(y + d) = g(y) + J d + H[d, d] / 2 + O(|d|^3 / L^5), with
//   J_ij  = delta_ij / L^3 - 3 y_i y_j / L^5,
//   H_ijk = -3 (delta_ij y_k + delta_ik y_j + delta_jk y_i) / L^5 + 15 y_i y_j y_k / L^7.
// Integrated against n dA, with the moments of WindingExpansion (D, C_i):
//   order 0: y.N / L^3
//   order 1: trace(J D) = trace(D) / L^3 - 3 y^T D y / L^5
//   order 2: (1/2) sum_ijk H_ijk C_ijk
//          = -3/(2 L^5) (2 sum_i (C_i y)_i + sum_i y_i trace(C_i))
//            + 15/(2 L^7) sum_i y_i (y^T C_i y).
// The error of the truncation falls like (radius / L)^5.
double far_field_flux(const detail::WindingExpansion& e, const Eigen::Vector3d& p) {
  const Eigen::Vector3d y = e.centre - p;
  const double l2 = y.squaredNorm();
  const double inv_l2 = 1.0 / l2;
  const double inv3 = inv_l2 / std::sqrt(l2);
  const double inv5 = inv3 * inv_l2;
  double diag = 0.0, trace_term = 0.0, cubic = 0.0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d cy = e.second_moment[i].times(y);
    diag += cy[i];
    trace_term += y[i] * e.second_moment[i].trace();
    cubic += y[i] * y.dot(cy);
  }
  const double order0 = y.dot(e.normal_sum) * inv3;
  const Eigen::Matrix3d& d = e.first_moment;  // D y row by row, as d * y sums it
  const Eigen::Vector3d dy(d(0, 0) * y[0] + d(0, 1) * y[1] + d(0, 2) * y[2],
                           d(1, 0) * y[0] + d(1, 1) * y[1] + d(1, 2) * y[2],
                           d(2, 0) * y[0] + d(2, 1) * y[1] + d(2, 2) * y[2]);
  const double order1 = d.trace() * inv3 - 3.0 * y.dot(dy) * inv5;
  const double order2 = -1.5 * inv5 * (2.0 * diag + trace_term) + 7.5 * inv5 * inv_l2 * cubic;
  return order0 + order1 + order2;
}

}  // namespace

double MeshQuery::winding_number(const Eigen::Vector3d& p) const {
  const detail::MeshBvh& b = impl_->bvh;
  double flux = 0.0;  // sum of solid angles, in steradians
  std::int32_t stack[512];
  int sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const detail::Bvh4Node& node = b.nodes[static_cast<std::size_t>(stack[--sp])];
    for (int k = 0; k < 4; ++k) {
      const std::int32_t c = node.child[k];
      if (c == detail::kEmpty) continue;
      if (c < 0) {
        const detail::QueryTriangle& t = b.triangles[static_cast<std::size_t>(~c)];
        flux += detail::solid_angle(p, t.a, t.a + t.ab, t.a + t.ac);
        continue;
      }
      const detail::WindingExpansion& e = b.expansions[static_cast<std::size_t>(c)];
      if ((p - e.centre).squaredNorm() > b.winding_beta * b.winding_beta * e.radius * e.radius)
        flux += far_field_flux(e, p);
      else
        stack[sp++] = c;
    }
  }
  return flux / kFourPi;
}

double MeshQuery::winding_number_exact(const Eigen::Vector3d& p) const {
  const TriangleMesh& m = impl_->bvh.mesh;
  double flux = 0.0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    flux += detail::solid_angle(p, m.corner(t, 0), m.corner(t, 1), m.corner(t, 2));
  return flux / kFourPi;
}

}  // namespace medspheres
