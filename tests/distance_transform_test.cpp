// distance_transform.h against brute force: the squared distance from every cell's centre to
// the nearest seed's, on random grids of odd shapes (exact integers, so equal), on one
// thread and on three.
#include <random>

#include <catch2/catch.hpp>

#include "medspheres/distance_transform.h"

using medspheres::detail::kNoSeed;
using medspheres::detail::squared_distance_transform;

TEST_CASE("the squared distance transform equals brute force", "[distance_transform]") {
  std::mt19937 rng(5);
  for (const std::array<std::int64_t, 3> n :
       {std::array<std::int64_t, 3>{1, 1, 1}, {7, 1, 3}, {9, 6, 5}, {13, 11, 4}, {4, 17, 9}}) {
    for (double density : {0.0, 0.002, 0.05, 0.5}) {
      std::bernoulli_distribution seed(density);
      const std::size_t cells = static_cast<std::size_t>(n[0] * n[1] * n[2]);
      std::vector<bool> is_seed(cells);
      for (std::size_t c = 0; c < cells; ++c) is_seed[c] = seed(rng);
      const std::vector<std::int64_t> d = squared_distance_transform(n, is_seed, 1);
      REQUIRE(d.size() == cells);
      CHECK(squared_distance_transform(n, is_seed, 3) == d);
      for (std::int64_t k = 0; k < n[2]; ++k)
        for (std::int64_t j = 0; j < n[1]; ++j)
          for (std::int64_t i = 0; i < n[0]; ++i) {
            std::int64_t best = kNoSeed;
            for (std::int64_t c = 0; c < static_cast<std::int64_t>(cells); ++c) {
              if (!is_seed[static_cast<std::size_t>(c)]) continue;
              const std::int64_t x = c % n[0] - i, y = c / n[0] % n[1] - j,
                                 z = c / (n[0] * n[1]) - k;
              best = std::min(best, x * x + y * y + z * z);
            }
            INFO("grid " << n[0] << "x" << n[1] << "x" << n[2] << ", density " << density
                         << ", cell " << i << " " << j << " " << k);
            CHECK(d[static_cast<std::size_t>(i + n[0] * (j + n[1] * k))] == best);
          }
    }
  }
}
