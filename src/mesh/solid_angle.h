#pragma once
// Private: the signed solid angle of a triangle, the term of every winding number.

#include <cmath>

#include <Eigen/Core>

namespace medspheres::detail {

/// Signed solid angle of triangle (a, b, c) seen from p, in steradians (Van Oosterom
/// and Strackee 1983): positive when the triangle runs counter-clockwise seen from p's
/// side opposite its normal, i.e. when p is behind it.
inline double solid_angle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Written out in scalars, in Eigen's order of operations (the same bits as the vector
  // expressions): the sanitizer builds instrument every vector temporary, and this term is
  // most of their winding numbers' time.
  const double x0 = a[0] - p[0], x1 = a[1] - p[1], x2 = a[2] - p[2];
  const double y0 = b[0] - p[0], y1 = b[1] - p[1], y2 = b[2] - p[2];
  const double z0 = c[0] - p[0], z1 = c[1] - p[1], z2 = c[2] - p[2];
  const double lx = std::sqrt(x0 * x0 + x1 * x1 + x2 * x2);
  const double ly = std::sqrt(y0 * y0 + y1 * y1 + y2 * y2);
  const double lz = std::sqrt(z0 * z0 + z1 * z1 + z2 * z2);
  const double num = x0 * (y1 * z2 - y2 * z1) + x1 * (y2 * z0 - y0 * z2) + x2 * (y0 * z1 - y1 * z0);
  const double xy = x0 * y0 + x1 * y1 + x2 * y2, yz = y0 * z0 + y1 * z1 + y2 * z2;
  const double zx = z0 * x0 + z1 * x1 + z2 * x2;
  const double den = lx * ly * lz + xy * lz + yz * lx + zx * ly;
  return 2.0 * std::atan2(num, den);
}

}  // namespace medspheres::detail
