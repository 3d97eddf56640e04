#pragma once
// Generated solids the cover tests bake, and the sampled oracle of their coverage.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <catch2/catch.hpp>

#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/mesh_generators.h"

namespace medspheres::test {

struct NamedSolid {
  std::string name;
  TriangleMesh mesh;
};

/// A box, a capsule, a sphere and a torus, closed and outward.
inline std::vector<NamedSolid> cover_solids() {
  return {{"box", make_box(Eigen::Vector3d(1.0, 0.6, 0.3), 2)},
          {"capsule", make_capsule(0.3, 0.8, 24, 6)},
          {"sphere", make_icosphere(1.0, 3)},
          {"torus", make_torus(1.0, 0.3, 32, 12)}};
}

/// The largest distance outside the union of \p balls over 20000 area-weighted surface
/// points (seed 3) and every vertex, by fit_metrics' coverage: an independent, sampled
/// check of a cover.
inline double sampled_gap(const TriangleMesh& mesh, const std::vector<Sphere>& balls) {
  const SurfaceSamples s = sample_surface(mesh, 20000, 3);
  return summarize_coverage(s, point_coverage(balls, s.points)).max;
}

/// Whether two sphere lists are the same, bit for bit, in the same order.
inline bool same_spheres(const std::vector<Sphere>& a, const std::vector<Sphere>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].center != b[i].center || a[i].radius != b[i].radius) return false;
  return true;
}

/// Checks that two covers have the same spheres, bit for bit, in the same order.
inline void check_same_spheres(const std::vector<Sphere>& a, const std::vector<Sphere>& b) {
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].center == b[i].center);
    CHECK(a[i].radius == b[i].radius);
  }
}

}  // namespace medspheres::test
