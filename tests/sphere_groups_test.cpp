// SphereGroups (src/check/sphere_groups.h): the groups partition the set, and each ball
// holds every sphere of its group with the stated room, checked sphere by sphere.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "../src/check/sphere_groups.h"

using medspheres::check::detail::group_spheres;
using medspheres::check::detail::kMaxGroups;
using medspheres::check::detail::SphereGroups;

TEST_CASE("sphere groups: a partition, each ball holding its spheres with room", "[check]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-0.3, 0.3), radius(0.0, 0.08);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + trial % 34, groups = 1 + trial % kMaxGroups;
    std::vector<double> x(n), y(n), z(n), r(n);
    double extent = 0.0;
    for (int i = 0; i < n; ++i) {
      x[i] = coord(rng), y[i] = coord(rng) * 0.2, z[i] = coord(rng) * 0.5, r[i] = radius(rng);
      extent =
          std::max({extent, std::abs(x[i]) + r[i], std::abs(y[i]) + r[i], std::abs(z[i]) + r[i]});
    }
    const SphereGroups g = group_spheres(x.data(), y.data(), z.data(), r.data(), n, groups, extent);
    if (n < 2 * groups || n > 32) {
      CHECK(g.count == 0);
      continue;
    }
    REQUIRE(g.count == groups);
    std::uint32_t all = 0;
    for (int k = 0; k < g.count; ++k) {
      CHECK((all & g.mask[k]) == 0u);
      all |= g.mask[k];
      CHECK(g.mask[k] != 0u);
      for (int i = 0; i < n; ++i) {
        if (!(g.mask[k] >> i & 1u)) continue;
        const double d = std::sqrt((x[i] - g.ball[k][0]) * (x[i] - g.ball[k][0]) +
                                   (y[i] - g.ball[k][1]) * (y[i] - g.ball[k][1]) +
                                   (z[i] - g.ball[k][2]) * (z[i] - g.ball[k][2]));
        CHECK(d + r[i] + 0.9e-9 * (1.0 + extent) <= g.ball[k][3]);
      }
    }
    CHECK(all == (n == 32 ? 0xFFFFFFFFu : (1u << n) - 1u));
  }
}
