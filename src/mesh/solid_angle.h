#pragma once
// Private: the signed solid angle of a triangle, the term of every winding number.

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace medspheres::detail {

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
