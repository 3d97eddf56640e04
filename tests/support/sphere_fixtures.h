#pragma once
// Seeded random sphere sets and poses, and brute-force oracles over sphere pairs, for
// the SphereTree and FCL adapter tests. Header-only.

#include <cmath>
#include <cstddef>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/sphere_set.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres::test {

/// n spheres with centres in [-extent, extent]^3 and radii in [r_min, r_max].
inline SphereSet random_sphere_set(std::mt19937& rng, std::size_t n, double extent = 1.0,
                                   double r_min = 0.02, double r_max = 0.2) {
  std::uniform_real_distribution<double> pos(-extent, extent);
  std::uniform_real_distribution<double> rad(r_min, r_max);
  SphereSet set;
  for (std::size_t i = 0; i < n; ++i)
    set.spheres.push_back({Eigen::Vector3d(pos(rng), pos(rng), pos(rng)), rad(rng)});
  return set;
}

/// Spheres along a noisy surface patch, like a medial sheet: flat clusters that RSS fits.
inline SphereSet random_sheet_set(std::mt19937& rng, std::size_t n) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SphereSet set;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = u(rng), y = 0.5 * u(rng);
    const double z = 0.3 * std::sin(3.0 * x) * std::cos(2.0 * y) + 0.01 * u(rng);
    set.spheres.push_back({Eigen::Vector3d(x, y, z), 0.05 + 0.04 * (1.0 + u(rng))});
  }
  return set;
}

/// A uniformly random rotation and a translation in [-extent, extent]^3.
inline Eigen::Isometry3d random_pose(std::mt19937& rng, double extent) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> t(-extent, extent);
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = Eigen::Vector3d(t(rng), t(rng), t(rng));
  return X;
}

/// The signed distance |c_b - c_a| - (r_a + r_b) of two spheres, centres mapped to W.
inline double pair_signed_distance(const Sphere& a, const Eigen::Isometry3d& X_WA, const Sphere& b,
                                   const Eigen::Isometry3d& X_WB) {
  return ((X_WB * b.center) - (X_WA * a.center)).norm() - (a.radius + b.radius);
}

/// Smallest pair signed distance over all sphere pairs, and the pair.
struct BrutePair {
  double value = std::numeric_limits<double>::infinity();
  std::size_t a = 0;
  std::size_t b = 0;
};

inline BrutePair brute_min(const SphereSet& a, const Eigen::Isometry3d& X_WA, const SphereSet& b,
                           const Eigen::Isometry3d& X_WB) {
  BrutePair best;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t j = 0; j < b.size(); ++j) {
      const double d = pair_signed_distance(a.spheres[i], X_WA, b.spheres[j], X_WB);
      if (d < best.value) best = {d, i, j};
    }
  }
  return best;
}

/// A closed, outward-wound star-shaped blob: a UV sphere of the given radius whose
/// rings are modulated by a few bumps; 2 segments (rings - 1) triangles.
inline TriangleMesh bumpy_sphere(int rings, int segments, double radius) {
  TriangleMesh m;
  m.vertices.push_back(Eigen::Vector3d(0, 0, radius));
  for (int i = 1; i < rings; ++i) {
    const double theta = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2 * M_PI * j / segments;
      const double r = radius * (1 + 0.15 * std::sin(3 * phi) * std::sin(2 * theta));
      m.vertices.push_back(r * Eigen::Vector3d(std::sin(theta) * std::cos(phi),
                                               std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  m.vertices.push_back(Eigen::Vector3d(0, 0, -radius));
  const int south = static_cast<int>(m.vertices.size()) - 1;
  auto ring = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i + 1 < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
  for (int j = 0; j < segments; ++j)
    m.triangles.push_back({south, ring(rings - 1, j + 1), ring(rings - 1, j)});
  return m;
}

/// Extent of a set about its frame's origin, for tolerances.
inline double set_extent(const SphereSet& s) {
  double e = 0.0;
  for (const Sphere& x : s.spheres) e = std::max(e, x.center.norm() + x.radius);
  return e;
}

}  // namespace medspheres::test
