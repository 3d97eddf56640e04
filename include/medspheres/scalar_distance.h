#pragma once
/// \file
/// Distances between 3-vectors and an affine map of one, written out in scalars with the
/// same operations in the same order as Eigen's expressions, so the same bits: the
/// sanitizer builds instrument every vector temporary of an Eigen expression, and the
/// covering bake and the checker's table bake take these millions of times.
/// Pure functions: safe from many threads.

#include <cmath>

#include <Eigen/Core>

namespace medspheres::detail {

/// (a - b).squaredNorm(): ((dx^2 + dy^2) + dz^2).
inline double squared_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return dx * dx + dy * dy + dz * dz;
}

/// (a - b).norm().
inline double distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::sqrt(squared_distance(a, b));
}

/// R * x + p: each row's products summed left to right, then p added. Only where no
/// contraction into fused multiply-adds is allowed (-ffp-contract=off), or the order of
/// rounding is the compiler's.
inline Eigen::Vector3d affine(const Eigen::Matrix3d& R, const Eigen::Vector3d& x,
                              const Eigen::Vector3d& p) {
  Eigen::Vector3d y;
  for (int i = 0; i < 3; ++i) y[i] = R(i, 0) * x[0] + R(i, 1) * x[1] + R(i, 2) * x[2] + p[i];
  return y;
}

}  // namespace medspheres::detail
