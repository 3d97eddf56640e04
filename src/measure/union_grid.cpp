#include "union_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace medspheres::detail {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// Cells per axis at most (plus one for rounding): bounds the grid at about 2 million cells.
constexpr double kMaxCellsPerAxis = 128.0;
// Cells per ball at most: a sparse set of small balls gets cells larger than its balls,
// so that a search from a point outside them crosses few empty cells.
constexpr double kMaxCellsPerBall = 64.0;

// The smallest cell side for balls whose coordinates reach \p magnitude: 2^20 eps of it
// (a cell is then a million double spacings wide, so points still map to cells
// meaningfully), and at least 2^-900 (about 1e-271), so that 1 / h and the cell indices
// of points in the grid stay finite. Below it are only sets of tiny balls (subnormal
// radii, say), for which a coarser grid costs nothing.
double min_cell(double magnitude) {
  return std::max(0x1p20 * kEps * magnitude, 0x1p-900);
}

}  // namespace

UnionGrid::UnionGrid(const std::vector<Sphere>& balls) {
  Eigen::AlignedBox3d box;
  std::vector<double> radii;
  balls_.reserve(balls.size());
  radii.reserve(balls.size());
  for (const Sphere& b : balls) {
    box.extend(b.center - Eigen::Vector3d::Constant(b.radius));
    box.extend(b.center + Eigen::Vector3d::Constant(b.radius));
    balls_.emplace_back(b.center.x(), b.center.y(), b.center.z(), b.radius);
    radii.push_back(b.radius);
  }
  size_cells(box, radii);
  build_lists();
}

void UnionGrid::size_cells(const Eigen::AlignedBox3d& box, std::vector<double>& radii) {
  const auto middle = radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2);
  std::nth_element(radii.begin(), middle, radii.end());
  const Eigen::Vector3d size = box.sizes();
  const double magnitude = box.min().cwiseAbs().cwiseMax(box.max().cwiseAbs()).maxCoeff();
  // cbrt(volume / (64 n)); as a product of cube roots when the volume overflows.
  const double n = kMaxCellsPerBall * static_cast<double>(radii.size());
  const double per_ball = std::isfinite(box.volume()) ? std::cbrt(box.volume() / n)
                                                      : std::cbrt(size[0]) * std::cbrt(size[1]) *
                                                            std::cbrt(size[2]) / std::cbrt(n);
  h_ = std::max({*middle, size.maxCoeff() / kMaxCellsPerAxis, per_ball, min_cell(magnitude)});
  inv_h_ = 1.0 / h_;
  origin_ = box.min();
  // h >= the largest side / 128, so each count is at most 128 plus rounding; the cap
  // only guards that bound.
  for (int k = 0; k < 3; ++k)
    dims_[k] =
        static_cast<int>(std::clamp(std::ceil(size[k] * inv_h_), 1.0, kMaxCellsPerAxis + 1.0));
  slack_ = 64.0 * kEps * (magnitude + h_);
}

template <class Fn>
void UnionGrid::for_each_cell(const Eigen::Vector4d& b, Fn&& fn) const {
  std::array<int, 3> lo{}, hi{};
  for (int k = 0; k < 3; ++k) {
    const double reach = b[3] + slack_;
    const double a = std::floor((b[k] - reach - origin_[k]) * inv_h_);
    const double z = std::floor((b[k] + reach - origin_[k]) * inv_h_);
    lo[k] = static_cast<int>(std::clamp(a, 0.0, dims_[k] - 1.0));
    hi[k] = static_cast<int>(std::clamp(z, 0.0, dims_[k] - 1.0));
  }
  for (int x = lo[0]; x <= hi[0]; ++x)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int z = lo[2]; z <= hi[2]; ++z) {
        const int index[3] = {x, y, z};
        double near2 = 0.0, far2 = 0.0;
        for (int k = 0; k < 3; ++k) {
          const double c0 = origin_[k] + index[k] * h_, c1 = c0 + h_;
          const double gap = std::max({c0 - b[k], 0.0, b[k] - c1});
          const double reach = std::max(std::abs(b[k] - c0), std::abs(b[k] - c1));
          near2 += gap * gap;
          far2 += reach * reach;
        }
        fn(flat(x, y, z), near2, far2);
      }
}

void UnionGrid::build_lists() {
  const std::size_t cells = static_cast<std::size_t>(dims_[0]) *
                            static_cast<std::size_t>(dims_[1]) * static_cast<std::size_t>(dims_[2]);
  // Pass 1: the first ball that contains each cell.
  std::vector<int> owner(cells, -1);
  for (int i = 0; i < static_cast<int>(balls_.size()); ++i) {
    const double inner = balls_[i][3] - slack_;
    if (inner <= 0.0) continue;
    for_each_cell(balls_[i], [&](std::size_t c, double, double far2) {
      if (owner[c] < 0 && far2 <= inner * inner) owner[c] = i;
    });
  }
  // Pass 2: list sizes; pass 3: the lists, in ascending ball order.
  std::vector<std::size_t> count(cells, 0);
  for (std::size_t c = 0; c < cells; ++c) count[c] = owner[c] >= 0 ? 1 : 0;
  for (const Eigen::Vector4d& b : balls_) {
    const double outer = b[3] + slack_;
    for_each_cell(b, [&](std::size_t c, double near2, double) {
      if (owner[c] < 0 && near2 <= outer * outer) ++count[c];
    });
  }
  start_.assign(cells + 1, 0);
  for (std::size_t c = 0; c < cells; ++c) start_[c + 1] = start_[c] + count[c];
  items_.assign(start_[cells], -1);
  full_.assign(cells, 0);
  std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t c = 0; c < cells; ++c)
    if (owner[c] >= 0) {
      items_[fill[c]++] = owner[c];
      full_[c] = 1;
    }
  for (int i = 0; i < static_cast<int>(balls_.size()); ++i) {
    const double outer = balls_[i][3] + slack_;
    for_each_cell(balls_[i], [&](std::size_t c, double near2, double) {
      if (owner[c] < 0 && near2 <= outer * outer) items_[fill[c]++] = i;
    });
  }
}

std::array<long long, 3> UnionGrid::cell_of(const Eigen::Vector3d& p) const {
  // Far points are clamped to 2^40 cells away: still outside, and no integer overflow.
  constexpr double kFar = 1099511627776.0;
  std::array<long long, 3> c{};
  for (int k = 0; k < 3; ++k)
    c[k] =
        static_cast<long long>(std::clamp(std::floor((p[k] - origin_[k]) * inv_h_), -kFar, kFar));
  return c;
}

int UnionGrid::containing(const Eigen::Vector3d& p) const {
  const std::array<long long, 3> c = cell_of(p);
  for (int k = 0; k < 3; ++k)
    if (c[k] < 0 || c[k] >= dims_[k]) return -1;
  const std::size_t cell = flat(c[0], c[1], c[2]);
  if (full_[cell]) return items_[start_[cell]];
  for (std::size_t j = start_[cell]; j < start_[cell + 1]; ++j) {
    const Eigen::Vector4d& b = balls_[static_cast<std::size_t>(items_[j])];
    if ((p - b.head<3>()).squaredNorm() <= b[3] * b[3]) return items_[j];
  }
  return -1;
}

bool UnionGrid::visit(long long x, long long y, long long z, const Eigen::Vector3d& p,
                      Nearest& best) const {
  // A cell farther than the best ball holds no nearer one.
  const long long index[3] = {x, y, z};
  double gap2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double a = origin_[k] + static_cast<double>(index[k]) * h_;
    const double gap = std::max({a - p[k], 0.0, p[k] - (a + h_)});
    gap2 += gap * gap;
  }
  if (std::sqrt(gap2) - slack_ > best.distance) return false;
  const std::size_t cell = flat(x, y, z);
  for (std::size_t j = start_[cell]; j < start_[cell + 1]; ++j) {
    const int i = items_[j];
    const Eigen::Vector4d& b = balls_[static_cast<std::size_t>(i)];
    const double d2 = (p - b.head<3>()).squaredNorm();
    if (d2 <= b[3] * b[3]) {
      best = {0.0, i};
      return true;
    }
    const double d = std::max(0.0, std::sqrt(d2) - b[3]);
    if (d < best.distance) best = {d, i};
  }
  return false;
}

double UnionGrid::beyond(const Eigen::Vector3d& p, const std::array<long long, 3>& c,
                         long long k) const {
  // The cells at Chebyshev index distance >= k from c form six slabs of the grid: those
  // with index <= c - k or >= c + k along one axis. The bound is the distance to the
  // nearest non-empty slab, each slab a box.
  double bound = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis)
    for (const bool upper : {false, true}) {
      const long long top = dims_[axis] - 1;
      const long long lo = upper ? std::max(c[axis] + k, 0LL) : 0;
      const long long hi = upper ? top : std::min(c[axis] - k, top);
      if (lo > hi) continue;
      double d2 = 0.0;
      for (int j = 0; j < 3; ++j) {
        const double a = origin_[j] + (j == axis ? static_cast<double>(lo) * h_ : 0.0);
        const double b = origin_[j] + (j == axis ? static_cast<double>(hi + 1) : dims_[j]) * h_;
        const double gap = std::max({a - p[j], 0.0, p[j] - b});
        d2 += gap * gap;
      }
      bound = std::min(bound, std::sqrt(d2));
    }
  return bound - slack_;
}

UnionGrid::Nearest UnionGrid::nearest(const Eigen::Vector3d& p) const {
  const std::array<long long, 3> c = cell_of(p);
  // Shells of cells at Chebyshev index distance k from p's cell, from the first that
  // meets the grid to the last, until the cells left are all farther than the best ball.
  long long k_first = 0, k_last = 0;
  for (int k = 0; k < 3; ++k) {
    const long long top = dims_[k] - 1;
    k_first = std::max({k_first, -c[k], c[k] - top});
    k_last = std::max({k_last, std::abs(c[k]), std::abs(c[k] - top)});
  }
  if (k_first == 0 && full_[flat(c[0], c[1], c[2])])
    return {0.0, items_[start_[flat(c[0], c[1], c[2])]]};
  Nearest best{std::numeric_limits<double>::infinity(), -1};
  auto clip = [&](int axis, long long k) {
    return std::array<long long, 2>{std::max(c[axis] - k, 0LL),
                                    std::min(c[axis] + k, static_cast<long long>(dims_[axis]) - 1)};
  };
  for (long long k = k_first; k <= k_last; ++k) {
    if (k > k_first && best.distance <= beyond(p, c, k)) break;
    const auto xs = clip(0, k), ys = clip(1, k), zs = clip(2, k);
    for (long long x = xs[0]; x <= xs[1]; ++x)
      for (long long y = ys[0]; y <= ys[1]; ++y) {
        if (std::abs(x - c[0]) == k || std::abs(y - c[1]) == k) {
          for (long long z = zs[0]; z <= zs[1]; ++z)
            if (visit(x, y, z, p, best)) return best;
        } else {
          // Inside the shell's x-y extent only the two z faces belong to the shell.
          for (const long long z : {c[2] - k, c[2] + k})
            if (z >= 0 && z < dims_[2] && visit(x, y, z, p, best)) return best;
        }
      }
  }
  return best;
}

}  // namespace medspheres::detail
