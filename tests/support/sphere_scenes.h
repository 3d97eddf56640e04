#pragma once
// Seeded scenes of two random sphere sets at random poses, from far apart to deeply
// overlapping, and the tree options the query tests sweep. Header-only.

#include <cstddef>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "medspheres/sphere_set.h"
#include "medspheres/sphere_tree.h"
#include "support/sphere_fixtures.h"

namespace medspheres::test {

/// Two sphere sets, each in its own frame, and their poses in W.
struct SetPairScene {
  SphereSet a, b;
  Eigen::Isometry3d X_WA, X_WB;
};

/// How random_set_pairs draws scene k.
struct SceneMix {
  std::size_t max_spheres = 120;  ///< each set has 1 to max_spheres spheres
  int sheet_a_period = 3;         ///< A is a sheet (random_sheet_set) when k % this == 0
  int sheet_b_period = 4;         ///< the same for B; 0: never
  double spread_step = 0.5;       ///< poses translate within spread_step (1 + k % cycle)
  int spread_cycle = 7;
};

/// \p count scenes drawn from \p seed: the two sizes, then A, B, X_WA and X_WB.
inline std::vector<SetPairScene> random_set_pairs(unsigned seed, int count,
                                                  const SceneMix& mix = {}) {
  std::mt19937 rng(seed);
  auto is_sheet = [](int k, int period) { return period > 0 && k % period == 0; };
  std::vector<SetPairScene> scenes;
  for (int k = 0; k < count; ++k) {
    SetPairScene s;
    const std::size_t na = 1 + static_cast<std::size_t>(rng() % mix.max_spheres);
    const std::size_t nb = 1 + static_cast<std::size_t>(rng() % mix.max_spheres);
    s.a = is_sheet(k, mix.sheet_a_period) ? random_sheet_set(rng, na) : random_sphere_set(rng, na);
    s.b = is_sheet(k, mix.sheet_b_period) ? random_sheet_set(rng, nb) : random_sphere_set(rng, nb);
    const double spread = mix.spread_step * (1 + k % mix.spread_cycle);
    s.X_WA = random_pose(rng, spread);
    s.X_WB = random_pose(rng, spread);
    scenes.push_back(s);
  }
  return scenes;
}

/// RSS and ball trees, with leaves of 1 and of 4 spheres.
inline std::vector<SphereTreeOptions> all_tree_options() {
  std::vector<SphereTreeOptions> out;
  for (BoundingVolumeKind kind : {BoundingVolumeKind::rss, BoundingVolumeKind::ball}) {
    for (int leaf : {1, 4}) {
      SphereTreeOptions o;
      o.kind = kind;
      o.max_leaf_size = leaf;
      out.push_back(o);
    }
  }
  return out;
}

}  // namespace medspheres::test
