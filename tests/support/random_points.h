#pragma once
// Seeded random points for tests and benchmarks.

#include <cstddef>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/triangle_mesh.h"

namespace medspheres::test {

/// A point of triangle (a, b, c), uniformly distributed: two uniform numbers in [0, 1)
/// folded into the triangle's half of the unit square. Draws exactly two numbers.
template <class Rng>
Eigen::Vector3d random_point_on_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                         const Eigen::Vector3d& c, Rng& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  double s = u01(rng), r = u01(rng);
  if (s + r > 1) {
    s = 1 - s;
    r = 1 - r;
  }
  return a + s * (b - a) + r * (c - a);
}

/// n points near the surface of \p m: each a random point of a random triangle, moved by
/// up to \p offset along each axis.
inline std::vector<Eigen::Vector3d> near_surface_points(const TriangleMesh& m, std::size_t n,
                                                        unsigned seed, double offset) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> s(-1.0, 1.0);
  std::uniform_int_distribution<std::size_t> pick(0, m.triangles.size() - 1);
  std::vector<Eigen::Vector3d> pts;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t t = pick(rng);
    const Eigen::Vector3d on =
        random_point_on_triangle(m.corner(t, 0), m.corner(t, 1), m.corner(t, 2), rng);
    pts.push_back(on + offset * Eigen::Vector3d(s(rng), s(rng), s(rng)));
  }
  return pts;
}

/// Up to n points uniform in \p box for which inside(p) holds, from at most 200 n tries.
template <class Inside>
std::vector<Eigen::Vector3d> points_inside(const Eigen::AlignedBox3d& box, std::size_t n,
                                           unsigned seed, Inside inside) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Vector3d> pts;
  std::size_t tries = 0;
  while (pts.size() < n && tries < 200 * n) {
    ++tries;
    const Eigen::Vector3d p =
        box.min() + box.sizes().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    if (inside(p)) pts.push_back(p);
  }
  return pts;
}

}  // namespace medspheres::test
