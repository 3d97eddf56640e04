#include "boxes_distance_transform.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "medspheres/distance_transform.h"

namespace medspheres::check::detail {

std::vector<std::int64_t> boxes_distance_transform(const std::vector<Element>& elements,
                                                   const double* origin, double h, const int* n,
                                                   double pad, int threads) {
  const std::size_t count = static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]) *
                            static_cast<std::size_t>(n[2]);
  std::vector<bool> touched(count, false);
  for (const Element& e : elements) {
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::max(0, int(std::floor((e.box.min()[k] - pad - origin[k]) / h)));
      hi[k] = std::min(n[k] - 1, int(std::floor((e.box.max()[k] + pad - origin[k]) / h)));
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x)
          touched[std::size_t(x) + n[0] * (std::size_t(y) + std::size_t(n[1]) * z)] = true;
  }
  return medspheres::detail::squared_distance_transform({n[0], n[1], n[2]}, touched, threads);
}

}  // namespace medspheres::check::detail
