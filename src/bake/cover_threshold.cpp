// Bottleneck set cover by binary search on the threshold (cover_threshold.h). At a fixed
// threshold each candidate's covered items are a bitset, built from the cost matrix in
// one pass; the greedy cover then costs budget x candidates x items / 64 word operations.
#include "cover_threshold.h"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <cstdint>
#include <limits>

namespace medspheres {

namespace {

using Words = std::vector<std::uint64_t>;

int popcount(std::uint64_t x) {
  return static_cast<int>(std::bitset<64>(x).count());
}

// The greedy cover at threshold t: the picks, or empty when budget picks leave items
// uncovered.
std::vector<std::size_t> greedy_at(const std::vector<float>& cost, std::size_t candidates,
                                   std::size_t items, std::size_t budget, double t, int threads) {
  const std::size_t words = (items + 63) / 64;
  std::vector<Words> covers(candidates, Words(words, 0));
  const long long n = static_cast<long long>(candidates);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long long mm = 0; mm < n; ++mm) {
    const std::size_t m = static_cast<std::size_t>(mm);
    const float* row = cost.data() + m * items;
    for (std::size_t q = 0; q < items; ++q)
      if (row[q] <= t) covers[m][q / 64] |= std::uint64_t{1} << (q % 64);
  }
  Words open(words, ~std::uint64_t{0});
  if (items % 64) open.back() = (std::uint64_t{1} << (items % 64)) - 1;
  std::size_t left = items;
  std::vector<std::size_t> picks;
  while (left > 0 && picks.size() < budget) {
    std::size_t arg = 0;
    int gain = 0;
    for (std::size_t m = 0; m < candidates; ++m) {
      int g = 0;
      for (std::size_t w = 0; w < words; ++w) g += popcount(covers[m][w] & open[w]);
      if (g > gain) gain = g, arg = m;
    }
    if (gain == 0) break;
    picks.push_back(arg);
    for (std::size_t w = 0; w < words; ++w) open[w] &= ~covers[arg][w];
    left -= static_cast<std::size_t>(gain);
  }
  if (left > 0) picks.clear();
  return picks;
}

}  // namespace

ThresholdCover least_threshold_cover(const std::vector<float>& cost, std::size_t candidates,
                                     std::size_t items, std::size_t budget, double hi,
                                     int iterations, int threads) {
  ThresholdCover out;
  if (candidates == 0 || items == 0 || budget == 0) return out;
  double lo = -std::numeric_limits<double>::infinity();
  for (std::size_t q = 0; q < items; ++q) {
    double cheapest = std::numeric_limits<double>::infinity();
    for (std::size_t m = 0; m < candidates; ++m)
      cheapest = std::min(cheapest, static_cast<double>(cost[m * items + q]));
    lo = std::max(lo, cheapest);
  }
  // At the largest cost any one candidate covers every item.
  const double top = static_cast<double>(*std::max_element(cost.begin(), cost.end()));
  hi = std::min(std::max(hi, lo), top);
  std::vector<std::size_t> picks = greedy_at(cost, candidates, items, budget, hi, threads);
  if (picks.empty()) picks = greedy_at(cost, candidates, items, budget, hi = top, threads);
  if (picks.empty()) return out;
  out = {hi, picks};
  for (int i = 0; i < iterations; ++i) {
    const double mid = 0.5 * (lo + out.threshold);
    std::vector<std::size_t> p = greedy_at(cost, candidates, items, budget, mid, threads);
    if (p.empty())
      lo = mid;
    else
      out = {mid, std::move(p)};
  }
  return out;
}

}  // namespace medspheres
