#include "distance_field.h"

#include <algorithm>
#include <cmath>

#include "boxes_distance_transform.h"
#include "medspheres/threads.h"

namespace medspheres::check::detail {
namespace {

const double kHalfDiagonal = std::sqrt(3.0) / 2.0;
constexpr double kSteps = 8.0;  // a byte counts eighths of the side

// x rounded down (up) to a whole number of units, in [0, 255] (255 when above).
std::uint16_t bytes_below(double x, double unit) {
  double q = std::min(std::floor(x / unit), 255.0);
  if (q * unit > x) q -= 1.0;  // the division rounded up
  return static_cast<std::uint16_t>(std::max(q, 0.0));
}
std::uint16_t bytes_above(double x, double unit) {
  double q = std::ceil(x / unit);
  if (q * unit < x) q += 1.0;  // the division rounded down
  return static_cast<std::uint16_t>(std::clamp(q, 0.0, 255.0));
}

}  // namespace

DistanceField::DistanceField(const SceneGrid& grid, int split, int threads) {
  if (grid.empty()) return;
  h_ = grid.cell_side() / split;
  unit_ = h_ / kSteps;
  for (int k = 0; k < 3; ++k) {
    origin_[k] = grid.origin()[k];
    n_[k] = grid.dims()[k] * split;
  }
  const std::size_t cells = std::size_t(n_[0]) * n_[1] * n_[2];
  const double pad = grid.pad(), reach = grid.reach();
  const std::vector<std::int64_t> d2 =
      boxes_distance_transform(grid.elements(), origin_, h_, n_, pad, threads);
  bounds_.assign(cells + 2, 0);
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count(threads))
  for (int z = 0; z < n_[2]; ++z)
    for (int y = 0; y < n_[1]; ++y)
      for (int x = 0; x < n_[0]; ++x) {
        const std::size_t c =
            std::size_t(x) + std::size_t(n_[0]) * (std::size_t(y) + std::size_t(n_[1]) * z);
        const double p[3] = {origin_[0] + h_ * (x + 0.5), origin_[1] + h_ * (y + 0.5),
                             origin_[2] + h_ * (z + 0.5)};
        // A cube of side h whose centre is D h away is at least (D - sqrt 3 / 2) h away.
        const double transform = h_ * (std::sqrt(double(d2[c])) - kHalfDiagonal) - pad;
        const double d = grid.nearest(p, reach);
        const bool near = d <= reach;
        const double lower = near ? d - pad : std::max(reach, transform);
        const std::uint16_t upper = near ? bytes_above(d + pad, unit_) : 255;
        bounds_[c] = static_cast<std::uint16_t>(bytes_below(lower, unit_) | upper << 8);
      }
}

}  // namespace medspheres::check::detail
