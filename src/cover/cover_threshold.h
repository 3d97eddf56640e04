#pragma once
// The least threshold at which a budget of candidates covers every item: the bottleneck
// set cover behind the covering bake's minimax start (cover.cpp, step 4c).

#include <cstddef>
#include <vector>

namespace medspheres {

// cost[m * items + q] (candidates x items values): what candidate m must pay to cover item q (for
// the cover: the protrusion a ball centred at candidate m needs to hold patch q). A candidate
// covers at threshold t the items of cost <= t.
struct ThresholdCover {
  double threshold = 0.0;          // the least t found at which `picks` cover every item
  std::vector<std::size_t> picks;  // at most the budget, in the order chosen
};

// Binary search (\p iterations halvings of [lo, hi]; lo the largest over items of their
// cheapest cost, below which no set covers) for the least t at which the greedy cover
// (each pick the candidate covering most uncovered items, ties the lowest index) needs at
// most \p budget candidates. The greedy cover is a ln(items)-approximation of the least
// set cover, so the threshold is an upper bound on the best achievable at that budget by
// these candidates, not the optimum. When the greedy cover at hi needs more than the
// budget (or is not finite), the search starts from the largest cost instead (one candidate
// covers all there).
// Deterministic: the answer does not depend on \p threads.
ThresholdCover least_threshold_cover(const float* cost, std::size_t candidates, std::size_t items,
                                     std::size_t budget, double hi, int iterations, int threads);

std::vector<std::size_t> greedy_cover_at(const float* cost, std::size_t candidates,
                                         std::size_t items, std::size_t budget, double t,
                                         int threads);

}  // namespace medspheres
