#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "../src/cover/cover_threshold.h"

using namespace medspheres;

namespace {

// Whether the candidates of \p picks cover every item at threshold t.
bool covers(const std::vector<float>& cost, std::size_t items,
            const std::vector<std::size_t>& picks, double t) {
  for (std::size_t q = 0; q < items; ++q) {
    bool held = false;
    for (std::size_t m : picks) held = held || cost[m * items + q] <= t;
    if (!held) return false;
  }
  return true;
}

// The least threshold at which some set of at most \p budget candidates covers every item,
// by trying every subset (the oracle: the bottleneck of the optimal set cover).
double optimum(const std::vector<float>& cost, std::size_t candidates, std::size_t items,
               std::size_t budget) {
  double best = std::numeric_limits<double>::infinity();
  for (std::uint32_t mask = 1; mask < (1u << candidates); ++mask) {
    std::vector<std::size_t> picks;
    for (std::size_t m = 0; m < candidates; ++m)
      if (mask >> m & 1u) picks.push_back(m);
    if (picks.size() > budget) continue;
    double t = 0.0;  // the set's own bottleneck: max over items of the cheapest pick
    for (std::size_t q = 0; q < items; ++q) {
      double c = std::numeric_limits<double>::infinity();
      for (std::size_t m : picks) c = std::min(c, static_cast<double>(cost[m * items + q]));
      t = std::max(t, c);
    }
    best = std::min(best, t);
  }
  return best;
}

}  // namespace

TEST_CASE("least_threshold_cover: covers at its threshold, never below the optimum",
          "[cover][threshold]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int exact = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const std::size_t candidates = 3 + trial % 8, items = 5 + trial % 37, budget = 1 + trial % 4;
    std::vector<float> cost(candidates * items);
    for (float& c : cost) c = u(rng);
    const ThresholdCover a = least_threshold_cover(cost.data(), candidates, items, budget,
                                                   std::numeric_limits<double>::infinity(), 30, 1);
    const double best = optimum(cost, candidates, items, budget);
    INFO("trial " << trial);
    REQUIRE(!a.picks.empty());
    CHECK(a.picks.size() <= budget);
    CHECK(covers(cost, items, a.picks, a.threshold));
    CHECK(a.threshold >= best);
    exact += a.threshold <= best + 1e-6;
    // The same answer for every thread count and from a finite start.
    const ThresholdCover b =
        least_threshold_cover(cost.data(), candidates, items, budget, 0.5, 30, 2);
    CHECK(covers(cost, items, b.picks, b.threshold));
    CHECK(b.picks.size() <= budget);
    const ThresholdCover c = least_threshold_cover(cost.data(), candidates, items, budget,
                                                   std::numeric_limits<double>::infinity(), 30, 2);
    CHECK(c.picks == a.picks);
    CHECK(c.threshold == a.threshold);
  }
  // Greedy is not exact, but on these small instances it mostly finds the optimum.
  CHECK(exact >= 30);
}

TEST_CASE("least_threshold_cover: one candidate that holds everything cheaply wins at budget 1",
          "[cover][threshold]") {
  // Candidate 1 covers all at 0.25; candidates 0 and 2 cover halves at 0.1.
  const std::size_t items = 4;
  const std::vector<float> cost = {0.1f,  0.1f,  0.9f,  0.9f,   //
                                   0.25f, 0.25f, 0.25f, 0.25f,  //
                                   0.9f,  0.9f,  0.1f,  0.1f};
  const ThresholdCover one = least_threshold_cover(cost.data(), 3, items, 1, 1.0, 40, 1);
  REQUIRE(one.picks == std::vector<std::size_t>{1});
  CHECK(one.threshold == Approx(0.25).margin(1e-6));
  const ThresholdCover two = least_threshold_cover(cost.data(), 3, items, 2, 1.0, 40, 1);
  CHECK(two.picks.size() == 2);
  CHECK(two.threshold == Approx(0.1).margin(1e-6));
  CHECK(least_threshold_cover(nullptr, 0, 0, 2, 1.0, 10, 1).picks.empty());
}
