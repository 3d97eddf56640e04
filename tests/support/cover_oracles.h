#pragma once
// Oracles of a sphere set's measures that share no code with the library's: a Monte-Carlo
// union volume, the divergence-theorem volume of a closed mesh, and each ball's protrusion
// from the brute-force point-triangle distance signed by the brute-force winding number.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "medspheres/sphere_set.h"
#include "medspheres/triangle_mesh.h"
#include "support/point_triangle_oracle.h"

namespace medspheres::test {

struct SampledVolume {
  double value = 0.0;
  double sigma = 0.0;  ///< the estimate's standard deviation
};

/// The volume of the union of \p balls from \p n uniform points of their bounding box.
inline SampledVolume sampled_union_volume(const std::vector<Sphere>& balls, std::size_t n,
                                          unsigned seed) {
  Eigen::AlignedBox3d box;
  for (const Sphere& b : balls) {
    box.extend(b.center - Eigen::Vector3d::Constant(b.radius));
    box.extend(b.center + Eigen::Vector3d::Constant(b.radius));
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p =
        box.min() + box.sizes().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    hits += std::any_of(balls.begin(), balls.end(), [&](const Sphere& b) {
      return (p - b.center).squaredNorm() <= b.radius * b.radius;
    });
  }
  const double f = static_cast<double>(hits) / static_cast<double>(n);
  const double v = box.volume();
  return {f * v, v * std::sqrt(f * (1 - f) / static_cast<double>(n))};
}

/// The volume a closed, outward mesh bounds: the sum of its triangles' signed tetrahedra.
inline double divergence_volume(const TriangleMesh& m) {
  double six = 0.0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    six += m.corner(t, 0).dot(m.corner(t, 1).cross(m.corner(t, 2)));
  return six / 6.0;
}

/// The winding number of \p m about \p p: the triangles' solid angles (Van Oosterom and
/// Strackee) over 4 pi.
inline double brute_winding_number(const TriangleMesh& m, const Eigen::Vector3d& p) {
  double sum = 0.0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Eigen::Vector3d a = m.corner(t, 0) - p, b = m.corner(t, 1) - p, c = m.corner(t, 2) - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * M_PI);
}

/// The largest protrusion r - D(c) over \p balls, D the signed distance to the closed mesh
/// \p m (positive inside), both by brute force.
inline double brute_max_protrusion(const TriangleMesh& m, const std::vector<Sphere>& balls) {
  const OracleMesh oracle(m);
  double most = -INFINITY;
  for (const Sphere& b : balls) {
    const double d = oracle.distance(b.center);
    const double signed_d = brute_winding_number(m, b.center) > 0.5 ? d : -d;
    most = std::max(most, b.radius - signed_d);
  }
  return most;
}

}  // namespace medspheres::test
