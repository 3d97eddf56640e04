#pragma once
// A percentile of timings, for the benchmarks' tables (without bench_util.h's FCL).

#include <algorithm>
#include <cstddef>
#include <vector>

namespace medspheres::bench {

// The element of rank round(q (n - 1)) of v sorted ascending (q = 0.5: the median).
// Precondition: v is not empty, 0 <= q <= 1.
inline double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5));
  return v[i];
}

}  // namespace medspheres::bench
