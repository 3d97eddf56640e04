// Bottleneck set cover by binary search on the threshold (cover_threshold.h). At a fixed
// threshold each candidate's covered items are a bitset, built from the cost matrix in
// one pass; the greedy cover then costs budget x candidates x items / 64 word operations.
#include "cover_threshold.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace medspheres {

namespace {

using Words = std::vector<std::uint64_t>;

int popcount(std::uint64_t x) {  // SWAR: no call, whatever the target's instruction set
  x -= (x >> 1) & 0x5555555555555555ULL;
  x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
  x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
  return static_cast<int>((x * 0x0101010101010101ULL) >> 56);
}

// The greedy cover at threshold t: the picks, or empty when budget picks leave items
// uncovered. Lazy: a candidate's gain only falls as items get covered, so the gains of
// the previous picks are upper bounds, and a candidate whose fresh gain is at least every
// other bound (ties: the lower index) is the greedy pick. \p covers is scratch space.
std::vector<std::size_t> greedy_at(const float* cost, std::size_t candidates, std::size_t items,
                                   std::size_t budget, double t, int threads,
                                   std::vector<Words>& covers) {
  const std::size_t words = (items + 63) / 64;
  covers.resize(candidates);
  const long long n = static_cast<long long>(candidates);
  std::vector<int> bound(candidates, 0);
  // A float c has c <= t exactly when c <= the largest float not above t: the rows are
  // compared in float, without a branch, a word at a time.
  float tf = static_cast<float>(t);
  if (static_cast<double>(tf) > t) tf = std::nextafter(tf, -std::numeric_limits<float>::infinity());
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long long mm = 0; mm < n; ++mm) {
    const std::size_t m = static_cast<std::size_t>(mm);
    Words& cover = covers[m];
    cover.assign(words, 0);
    const float* row = cost + m * items;
    for (std::size_t w = 0; w < words; ++w) {
      const std::size_t first = 64 * w, count = std::min<std::size_t>(64, items - first);
      std::uint64_t bits = 0;
      for (std::size_t b = 0; b < count; ++b)
        bits |= static_cast<std::uint64_t>(row[first + b] <= tf) << b;
      cover[w] = bits;
      bound[m] += popcount(bits);
    }
  }
  // Max-heap on (bound, -index).
  auto before = [&](std::size_t a, std::size_t b) {
    return bound[a] < bound[b] || (bound[a] == bound[b] && a > b);
  };
  std::vector<std::size_t> heap(candidates);
  for (std::size_t m = 0; m < candidates; ++m) heap[m] = m;
  std::make_heap(heap.begin(), heap.end(), before);
  Words open(words, ~std::uint64_t{0});
  if (items % 64) open.back() = (std::uint64_t{1} << (items % 64)) - 1;
  std::size_t left = items;
  std::vector<std::size_t> picks;
  while (left > 0 && picks.size() < budget && !heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), before);
    const std::size_t m = heap.back();
    int gain = 0;
    for (std::size_t w = 0; w < words; ++w) gain += popcount(covers[m][w] & open[w]);
    bound[m] = gain;
    if (gain == 0) {
      heap.pop_back();
      continue;
    }
    if (!heap.empty() && before(m, heap.front())) {  // stale: back with its fresh gain
      std::push_heap(heap.begin(), heap.end(), before);
      continue;
    }
    heap.pop_back();
    picks.push_back(m);
    for (std::size_t w = 0; w < words; ++w) open[w] &= ~covers[m][w];
    left -= static_cast<std::size_t>(gain);
  }
  if (left > 0) picks.clear();
  return picks;
}

}  // namespace

std::vector<std::size_t> greedy_cover_at(const float* cost, std::size_t candidates,
                                         std::size_t items, std::size_t budget, double t,
                                         int threads) {
  std::vector<Words> covers;
  return greedy_at(cost, candidates, items, budget, t, threads, covers);
}

ThresholdCover least_threshold_cover(const float* cost, std::size_t candidates, std::size_t items,
                                     std::size_t budget, double hi, int iterations, int threads) {
  ThresholdCover out;
  if (candidates == 0 || items == 0 || budget == 0) return out;
  // Each item's cheapest cost and the largest cost, row by row (the matrix is stored so).
  std::vector<float> cheapest(items, std::numeric_limits<float>::infinity());
  float top_cost = -std::numeric_limits<float>::infinity();
  for (std::size_t m = 0; m < candidates; ++m) {
    const float* row = cost + m * items;
    for (std::size_t q = 0; q < items; ++q) {
      cheapest[q] = std::min(cheapest[q], row[q]);
      top_cost = std::max(top_cost, row[q]);
    }
  }
  double lo = static_cast<double>(*std::max_element(cheapest.begin(), cheapest.end()));
  // At the largest cost any one candidate covers every item.
  const double top = static_cast<double>(top_cost);
  hi = std::min(std::max(hi, lo), top);
  std::vector<Words> covers;
  std::vector<std::size_t> picks = greedy_at(cost, candidates, items, budget, hi, threads, covers);
  if (picks.empty()) picks = greedy_at(cost, candidates, items, budget, hi = top, threads, covers);
  if (picks.empty()) return out;
  out = {hi, picks};
  for (int i = 0; i < iterations; ++i) {
    const double mid = 0.5 * (lo + out.threshold);
    std::vector<std::size_t> p = greedy_at(cost, candidates, items, budget, mid, threads, covers);
    if (p.empty())
      lo = mid;
    else
      out = {mid, std::move(p)};
  }
  return out;
}

}  // namespace medspheres
