// DistanceField (src/check/distance_field.h): every cell's bounds bracket the distance
// from its centre to the scene, in closed form (a box and a ball), also beyond the grid's
// reach where the lower bound comes from the boxes' distance transform; and the grid and
// the field built on several threads are those built on one.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "../src/check/distance_field.h"
#include "../src/check/scene_grid.h"
#include "medspheres/check/scene.h"
#include "medspheres/mesh/mesh_generators.h"

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

TEST_CASE("scene grid and distance field: the same on 1, 2 and 3 threads", "[check]") {
  // Every kind of element, a point cloud of a few thousand points among them, so that the
  // elements fall into several chunks of the grid's build.
  check::Scene scene;
  scene.add_box({0.6, 0.4, 0.05}, Eigen::Isometry3d::Identity(), "floor");
  scene.add_sphere({0.2, -0.1, 0.3}, 0.07, "sphere");
  scene.add_capsule(0.03, 0.2, Eigen::Isometry3d(Eigen::Translation3d(-0.2, 0.1, 0.2)), "capsule");
  scene.add_cylinder(0.05, 0.1, Eigen::Isometry3d(Eigen::Translation3d(0.1, 0.2, 0.1)), "can");
  scene.add_mesh(medspheres::make_icosphere(0.1, 2),
                 Eigen::Isometry3d(Eigen::Translation3d(-0.1, -0.2, 0.25)), "ball");
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  std::vector<Eigen::Vector3d> points(3000), cells(500);
  for (Eigen::Vector3d& p : points) p = {u(rng), u(rng), 0.4 + 0.25 * u(rng)};
  for (Eigen::Vector3d& p : cells) p = {u(rng), u(rng), -0.2 + 0.25 * u(rng)};
  scene.add_points(points, "cloud");
  scene.add_cells(cells, 0.02, "octree");
  const SceneGrid one(scene, 0.04, 0.0, 200000, 1e-9, 1);
  const DistanceField field_one(one, 2, 1);
  const int* n = field_one.dims();
  const std::size_t cells_one = std::size_t(n[0]) * n[1] * n[2];
  REQUIRE(cells_one > 100000);
  for (const int threads : {2, 3}) {
    CAPTURE(threads);
    const SceneGrid grid(scene, 0.04, 0.0, 200000, 1e-9, threads);
    REQUIRE(grid.num_cells() == one.num_cells());
    CHECK(grid.num_entries() == one.num_entries());
    CHECK(std::equal(grid.lower_bounds(), grid.lower_bounds() + grid.num_cells() + 3,
                     one.lower_bounds()));
    const DistanceField field(grid, 2, threads);
    CHECK(std::equal(field.bounds(), field.bounds() + cells_one + 2, field_one.bounds()));
    // The lists: the same nearest distance and three-valued answer at random points.
    std::size_t differ = 0;
    for (int i = 0; i < 2000; ++i) {
      const double p[3] = {u(rng), u(rng), 0.3 + u(rng)};
      const double rq = 0.05 * (u(rng) + 0.4);
      if (grid.nearest(p, grid.reach()) != one.nearest(p, grid.reach()) ||
          grid.classify(p, rq, 1e-4) != one.classify(p, rq, 1e-4))
        ++differ;
    }
    CHECK(differ == 0);
  }
}
