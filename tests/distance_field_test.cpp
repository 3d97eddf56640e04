// DistanceField (src/check/distance_field.h): every cell's bounds bracket the distance
// from its centre to the scene, in closed form (a box and a ball), also beyond the grid's
// reach where the lower bound comes from the boxes' distance transform.

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <catch2/catch.hpp>

#include "../src/check/distance_field.h"
#include "../src/check/scene_grid.h"
#include "medspheres/check/scene.h"

namespace check = medspheres::check;

namespace {

// The distance from p to the box of half sides (0.3, 0.2, 0.025) at the origin and to the
// ball of radius 0.07 at (0.2, -0.1, 0.3), whichever is nearer.
double scene_distance(const double* p) {
  const double half[3] = {0.3, 0.2, 0.025}, centre[3] = {0.2, -0.1, 0.3};
  double out2 = 0.0, in = -1e300, ball2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double e = std::abs(p[k]) - half[k];
    out2 += std::max(e, 0.0) * std::max(e, 0.0);
    in = std::max(in, e);
    ball2 += (p[k] - centre[k]) * (p[k] - centre[k]);
  }
  const double box = out2 > 0.0 ? std::sqrt(out2) : std::max(in, 0.0);
  return std::max(std::min(box, std::sqrt(ball2) - 0.07), 0.0);
}

}  // namespace
using check::detail::DistanceField;
using check::detail::SceneGrid;

TEST_CASE("distance field: each cell's bounds bracket the distance from its centre", "[check]") {
  check::Scene scene;
  scene.add_box({0.6, 0.4, 0.05}, Eigen::Isometry3d::Identity(), "floor");
  scene.add_sphere({0.2, -0.1, 0.3}, 0.07, "sphere");
  const SceneGrid grid(scene, 0.05, 0.0, 4000, 1e-9);
  const DistanceField f(grid, 2);
  REQUIRE_FALSE(f.empty());
  const int* n = f.dims();
  std::size_t c = 0, near = 0;
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x, ++c) {
        const int lower = f.bounds()[c] & 0xFF, upper = f.bounds()[c] >> 8;
        const double p[3] = {f.origin()[0] + f.cell_side() * (x + 0.5),
                             f.origin()[1] + f.cell_side() * (y + 0.5),
                             f.origin()[2] + f.cell_side() * (z + 0.5)};
        const double d = scene_distance(p), tolerance = 1e-12;
        REQUIRE(lower * f.unit() <= d + tolerance);
        if (upper < 255) REQUIRE(upper * f.unit() >= d - tolerance);
        if (d <= grid.reach() - tolerance) {
          ++near;
          REQUIRE(upper < 255);  // exact within reach: an upper bound known
        }
      }
  CHECK(near > 0);
  CHECK(near < c);  // some cells beyond reach: their lower bounds from the transform
}
