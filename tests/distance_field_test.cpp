// DistanceField's block level (src/check/distance_field.h): every block's byte is the
// least lower byte of its cells, so a lower bound at each of their centres that the kernel
// may test before the cells themselves; and every cell's own bounds bracket the distance
// from its centre (SceneGrid::nearest, exact where the scene is within reach).

#include <algorithm>
#include <cstddef>

#include <catch2/catch.hpp>

#include "../src/check/distance_field.h"
#include "../src/check/scene_grid.h"
#include "medspheres/check/scene.h"

namespace check = medspheres::check;
using check::detail::DistanceField;
using check::detail::SceneGrid;

TEST_CASE("distance field: each block holds the least lower bound of its cells", "[check]") {
  check::Scene scene;
  scene.add_box({0.6, 0.4, 0.05}, Eigen::Isometry3d::Identity(), "floor");
  scene.add_sphere({0.2, -0.1, 0.3}, 0.07, "sphere");
  const SceneGrid grid(scene, 0.05, 0.0, 4000, 1e-9);
  const DistanceField f(grid, 2);
  REQUIRE_FALSE(f.empty());
  const int* n = f.dims();
  const int* nb = f.block_dims();
  constexpr int s = DistanceField::kBlockShift;
  for (int k = 0; k < 3; ++k) REQUIRE(nb[k] == (n[k] + (1 << s) - 1) >> s);
  const std::size_t blocks = std::size_t(nb[0]) * nb[1] * nb[2];
  std::vector<int> least(blocks, 256);
  std::size_t c = 0, near = 0;
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x, ++c) {
        const int lower = f.bounds()[c] & 0xFF, upper = f.bounds()[c] >> 8;
        const double p[3] = {f.origin()[0] + f.cell_side() * (x + 0.5),
                             f.origin()[1] + f.cell_side() * (y + 0.5),
                             f.origin()[2] + f.cell_side() * (z + 0.5)};
        const double d = grid.nearest(p, grid.reach());
        REQUIRE(lower * f.unit() <= d);
        if (d <= grid.reach()) {
          ++near;
          REQUIRE(upper * f.unit() >= d);
        }
        int& b = least[(x >> s) + std::size_t(nb[0]) * ((y >> s) + std::size_t(nb[1]) * (z >> s))];
        b = std::min(b, lower);
      }
  CHECK(near > 0);
  CHECK(near < c);  // some cells beyond reach: their lower bounds from the transform
  for (std::size_t b = 0; b < blocks; ++b) REQUIRE(int(f.block_lower()[b]) == least[b]);
}
