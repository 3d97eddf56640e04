#include "test_order.h"

#include <algorithm>
#include <numeric>

namespace medspheres::check::detail {

std::vector<std::uint32_t> order_by_hits(const std::vector<std::uint32_t>& hits) {
  std::vector<std::uint32_t> order(hits.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&hits](std::uint32_t a, std::uint32_t b) { return hits[a] > hits[b]; });
  return order;
}

}  // namespace medspheres::check::detail
