#pragma once
// sin and cos in floats of an angle already reduced by pi / 2 (|r| <= 0.7854, a hair over
// pi / 4), for the float pass's forward kinematics (kernel_body.h). Written once over a
// lane type V (V + V, V - V, V * V, and `splat` making a V of a float), so that the
// kernel's lanes and a test's plain floats run the same operations; instantiated on the
// kernel's own lane types (internal to its file), it shares no code between the scalar
// and the AVX2 builds.
//
// Taylor polynomials, sin to r^9 and cos to r^10, by Horner's rule in floats.
// Error bound (u = 2^-24, |r| <= 0.7854, r the float nearest a double angle r_d; the
// bound is against sin r_d and cos r_d; gamma_n = n u / (1 - n u)):
// - sin: rounding r_d to r moves sin by <= u |r_d| <= 0.786 u; the series' remainder is
//   <= |r|^11 / 11! <= 0.031 u; z = r^2 and r z carry 2 roundings; the Horner sum
//   ps = -1/6 + z/120 - z^2/5040 + z^3/362880 (each coefficient rounded once, z^k its
//   roundings, two per step) errs by <= gamma_10 (sum of |terms| <= 0.1718), relative
//   <= 10.7 u of |ps| >= 0.1615; so the product r z ps (<= 0.0808) errs by <= 13.7 u of it,
//   1.11 u; the last sum rounds by <= u |sin r| <= 0.708 u. In all <= 2.64 u.
// - cos: rounding r_d to r moves cos by <= |sin r_d| u |r_d| <= 0.556 u; z = r^2 lies
//   within u z of r^2, so 1 - z/2 (z/2 exact) within 0.31 u, rounded by <= u/2 (the
//   value in [0.69, 1]); z^2 pc (<= 0.3805 / 24) errs by <= 3.01 u (z^2) + 10.5 u (the
//   Horner sum 1/24 - z/720 + ..., as for sin) + u (the product) of it, 0.23 u; the last
//   sum rounds by <= u; the series' remainder is <= |r|^12 / 12! <= 0.002 u. In all
//   <= 2.6 u.
// kFloatSinCosError = 3 u bounds both; float_sincos_test measures the error.

namespace medspheres::check::detail {

inline constexpr double kFloatSinCosError = 3.0 / 16777216.0;  // 3 u, u = 2^-24

template <class V, class Splat>
void float_sincos_reduced(V r, V& sr, V& cr, Splat splat) {
  const V z = r * r;
  V ps = splat(static_cast<float>(1.0 / 362880.0));
  ps = ps * z + splat(static_cast<float>(-1.0 / 5040.0));
  ps = ps * z + splat(static_cast<float>(1.0 / 120.0));
  ps = ps * z + splat(static_cast<float>(-1.0 / 6.0));
  V pc = splat(static_cast<float>(-1.0 / 3628800.0));
  pc = pc * z + splat(static_cast<float>(1.0 / 40320.0));
  pc = pc * z + splat(static_cast<float>(-1.0 / 720.0));
  pc = pc * z + splat(static_cast<float>(1.0 / 24.0));
  sr = r + (r * z) * ps;
  cr = (splat(1.0f) - splat(0.5f) * z) + (z * z) * pc;
}

}  // namespace medspheres::check::detail
