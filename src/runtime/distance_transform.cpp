#include "medspheres/distance_transform.h"

#include <algorithm>
#include <cstddef>

#include "medspheres/threads.h"

namespace medspheres::detail {

namespace {

// One 1D pass along \p count cells spaced \p stride apart from \p first: f[q] becomes
// min over p of (q - p)^2 + f[p] (the lower envelope of the parabolas rooted at the cells
// with f[p] < kNoSeed). \p v and \p z are scratch of count and count + 1 entries.
void envelope_pass(std::vector<std::int64_t>& f, std::int64_t first, std::int64_t stride,
                   std::int64_t count, std::vector<std::int64_t>& v, std::vector<double>& z,
                   std::vector<std::int64_t>& column) {
  for (std::int64_t q = 0; q < count; ++q)
    column[static_cast<std::size_t>(q)] = f[static_cast<std::size_t>(first + q * stride)];
  auto at = [&](std::int64_t q) { return column[static_cast<std::size_t>(q)]; };
  // The parabola of p meets the one of r (r < p) at s; both values are exact integers
  // below 2^62, so s is exact to well below one cell (only its order against q matters).
  auto meet = [&](std::int64_t r, std::int64_t p) {
    return static_cast<double>((at(p) + p * p) - (at(r) + r * r)) /
           static_cast<double>(2 * (p - r));
  };
  std::int64_t k = -1;
  for (std::int64_t p = 0; p < count; ++p) {
    if (at(p) >= kNoSeed) continue;
    double s = 0.0;
    while (k >= 0 &&
           (s = meet(v[static_cast<std::size_t>(k)], p)) <= z[static_cast<std::size_t>(k)])
      --k;
    ++k;
    v[static_cast<std::size_t>(k)] = p;
    z[static_cast<std::size_t>(k)] = k == 0 ? -1e300 : s;
    z[static_cast<std::size_t>(k) + 1] = 1e300;
  }
  if (k < 0) return;  // no seed on this line: every value stays kNoSeed
  std::int64_t j = 0;
  for (std::int64_t q = 0; q < count; ++q) {
    while (z[static_cast<std::size_t>(j) + 1] < static_cast<double>(q)) ++j;
    const std::int64_t p = v[static_cast<std::size_t>(j)];
    f[static_cast<std::size_t>(first + q * stride)] = (q - p) * (q - p) + at(p);
  }
}

}  // namespace

std::vector<std::int64_t> squared_distance_transform(const std::array<std::int64_t, 3>& n,
                                                     const std::vector<bool>& is_seed,
                                                     int threads) {
  std::vector<std::int64_t> f(is_seed.size());
  for (std::size_t c = 0; c < f.size(); ++c) f[c] = is_seed[c] ? 0 : kNoSeed;
  const std::array<std::int64_t, 3> stride = {1, n[0], n[0] * n[1]};
  const std::size_t longest = static_cast<std::size_t>(std::max(n[0], std::max(n[1], n[2])));
  const int team = thread_count(threads);
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, w = (a + 2) % 3;
    // The lines of a pass are independent: each thread its own scratch.
#pragma omp parallel num_threads(team)
    {
      std::vector<std::int64_t> v(longest), column(longest);
      std::vector<double> z(longest + 1);
#pragma omp for schedule(static)
      for (std::int64_t j = 0; j < n[w]; ++j)
        for (std::int64_t i = 0; i < n[u]; ++i)
          envelope_pass(f, i * stride[u] + j * stride[w], stride[a], n[a], v, z, column);
    }
  }
  return f;
}

}  // namespace medspheres::detail
