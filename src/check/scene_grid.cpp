#include "scene_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "distance_transform.h"

namespace medspheres::check::detail {
namespace {

// The largest float <= x (x >= 0 finite, or +inf).
float float_below(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

const double kHalfDiagonal = std::sqrt(3.0) / 2.0;
// A cell's lower bound is kept in steps of side / kLowerSteps, in one byte: the grid of
// bounds stays in the processor's cache (a bound is at most 255 / kLowerSteps sides).
constexpr double kLowerSteps = 8.0;

}  // namespace

SceneGrid::SceneGrid(const Scene& scene, double reach, double cell, std::size_t max_cells,
                     double pad)
    : elements_(scene_elements(scene)), reach_(reach), pad_(pad) {
  if (!(reach > 0.0) || !std::isfinite(reach))
    throw std::invalid_argument("scene grid: the reach must be finite and > 0");
  if (!(cell >= 0.0) || !std::isfinite(cell))
    throw std::invalid_argument("scene grid: the cell side must be finite and >= 0");
  if (elements_.empty()) return;
  for (const Element& e : elements_) {
    bounds_.extend(e.box);
    balls_.insert(balls_.end(),
                  {e.ball_centre.x(), e.ball_centre.y(), e.ball_centre.z(), e.ball_radius});
  }
  h_ = cell > 0.0 ? cell : reach / 2;
  // The grid holds every point within reach of an element, and a cell more.
  const Eigen::Vector3d extent = bounds_.max() - bounds_.min();
  while (true) {
    double cells = 1.0;
    for (int k = 0; k < 3; ++k) {
      n_[k] = static_cast<int>(std::ceil((extent[k] + 2 * (reach + h_)) / h_));
      cells *= n_[k];
    }
    if (cells <= static_cast<double>(std::max<std::size_t>(max_cells, 1))) break;
    h_ *= std::max(1.01, std::cbrt(cells / static_cast<double>(max_cells)));
  }
  origin_ = bounds_.min().array() - (reach + h_);
  inverse_h_ = 1.0 / h_;
  unit_ = h_ / kLowerSteps;
  build_lists(pad);
  build_lower(pad);
}

long SceneGrid::cell_of(const double* p) const {
  long index = 0, stride = 1;
  for (int k = 0; k < 3; ++k) {
    const double u = (p[k] - origin_[k]) * inverse_h_;  // a rounding off: within the pad
    if (!(u >= 0.0) || u >= n_[k]) return -1;
    index += static_cast<long>(u) * stride;
    stride *= n_[k];
  }
  return index;
}

// Outside the grid: the distance to the elements' bounds, less the pad.
double SceneGrid::outside_lower(const double* p) const {
  double s = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = std::max({bounds_.min()[k] - p[k], p[k] - bounds_.max()[k], 0.0});
    s += d * d;
  }
  return std::sqrt(s) - pad_;
}

void SceneGrid::build_lists(double pad) {
  const std::size_t cells = std::size_t(n_[0]) * n_[1] * n_[2];
  struct Hit {
    std::uint32_t cell, element;
    float lower, upper;
  };
  std::vector<Hit> hits;
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    const Element& e = elements_[i];
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::max(0, int(std::floor((e.box.min()[k] - reach_ - pad - origin_[k]) / h_)));
      hi[k] =
          std::min(n_[k] - 1, int(std::floor((e.box.max()[k] + reach_ + pad - origin_[k]) / h_)));
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) {
          const Eigen::Vector3d c = origin_ + h_ * Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5);
          const double d = element_distance(e, c);
          if (d - kHalfDiagonal * h_ - pad > reach_) continue;  // beyond reach of the cell
          const auto cell = static_cast<std::uint32_t>(x + n_[0] * (y + std::size_t(n_[1]) * z));
          hits.push_back({cell, static_cast<std::uint32_t>(i), float_below(std::max(d - pad, 0.0)),
                          -float_below(-(d + pad))});
        }
  }
  begin_.assign(cells + 1, 0);
  for (const Hit& h : hits) ++begin_[h.cell + 1];
  for (std::size_t c = 0; c < cells; ++c) begin_[c + 1] += begin_[c];
  entries_.resize(hits.size());
  std::vector<std::uint32_t> next(begin_.begin(), begin_.end() - 1);
  for (const Hit& h : hits) entries_[next[h.cell]++] = {h.element, h.lower, h.upper};
  for (std::size_t c = 0; c < cells; ++c)
    std::sort(entries_.begin() + begin_[c], entries_.begin() + begin_[c + 1],
              [](const Entry& a, const Entry& b) {
                return a.lower < b.lower || (a.lower == b.lower && a.element < b.element);
              });
}

// Per cell: the lists' bound (the first entry, or reach when none is listed: every element
// not listed is farther than reach), raised to the distance transform's where larger.
void SceneGrid::build_lower(double pad) {
  const std::size_t cells = begin_.size() - 1;
  std::vector<char> touched(cells, 0);
  for (const Element& e : elements_) {
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::max(0, int(std::floor((e.box.min()[k] - pad - origin_[k]) / h_)));
      hi[k] = std::min(n_[k] - 1, int(std::floor((e.box.max()[k] + pad - origin_[k]) / h_)));
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x)
          touched[std::size_t(x) + n_[0] * (std::size_t(y) + std::size_t(n_[1]) * z)] = 1;
  }
  const std::vector<double> d2 = squared_distance_transform(touched, n_[0], n_[1], n_[2]);
  lower_.resize(cells);
  for (std::size_t c = 0; c < cells; ++c) {
    // Two cubes of side h whose centres are D h apart are at least (D - sqrt 3) h apart.
    const double transform = h_ * (std::sqrt(d2[c]) - 2 * kHalfDiagonal) - pad;
    const double listed = begin_[c] < begin_[c + 1]
                              ? double(entries_[begin_[c]].lower) - kHalfDiagonal * h_ - pad
                              : reach_;
    const double value = std::max({std::min(listed, reach_), transform, 0.0});
    double q = std::min(std::floor(value / unit_), 255.0);
    if (q * unit_ > value) q -= 1.0;  // the division rounded up
    lower_[c] = static_cast<std::uint8_t>(std::max(q, 0.0));
  }
}

bool SceneGrid::clear(const double* p, double rq) const {
  if (elements_.empty()) return true;
  const long c = cell_of(p);
  if (c < 0) return outside_lower(p) > rq;
  return lower_[std::size_t(c)] * unit_ > rq;
}

Eigen::Vector3d SceneGrid::centre(std::size_t c) const {
  const std::size_t x = c % std::size_t(n_[0]), y = c / std::size_t(n_[0]) % std::size_t(n_[1]),
                    z = c / (std::size_t(n_[0]) * std::size_t(n_[1]));
  return origin_ + h_ * Eigen::Vector3d(double(x) + 0.5, double(y) + 0.5, double(z) + 0.5);
}

// The list of cell c: the elements within rq of p, to `found` until it returns true
// (then true). An element farther than rq + delta from the centre (delta = |p - centre|,
// padded) is farther than rq from p; one nearer than rq - delta is within; then the same
// with the element's ball (its centre's distance d from p, its radius b: beyond when
// d - b > rq, within when d + b <= rq); the others are tested exactly. The pads keep the
// shortcuts on the side the exact test would take.
template <class Found>
bool SceneGrid::scan_list(std::size_t c, const Eigen::Vector3d& p, double rq, Found&& found) const {
  const double delta = (p - centre(c)).norm() + pad_;
  for (std::uint32_t k = begin_[c]; k < begin_[c + 1]; ++k) {
    const Entry& entry = entries_[k];
    if (double(entry.lower) - delta > rq) break;
    const double* ball = &balls_[4 * std::size_t(entry.element)];
    const double dx = p.x() - ball[0], dy = p.y() - ball[1], dz = p.z() - ball[2];
    const double beyond = rq + ball[3] + pad_;
    if (dx * dx + dy * dy + dz * dz > beyond * beyond) continue;
    const double inside = rq - ball[3] - pad_;
    const bool near = double(entry.upper) + delta + pad_ <= rq ||
                      (inside >= 0.0 && dx * dx + dy * dy + dz * dz <= inside * inside);
    if ((near || element_within(elements_[entry.element], p, rq)) &&
        found(elements_[entry.element]))
      return true;
  }
  return false;
}

// Every element within rq of p to `found` until it returns true (then true).
template <class Found>
bool SceneGrid::scan(const double* p, double rq, Found&& found) const {
  if (elements_.empty() || rq < 0.0) return false;
  const Eigen::Vector3d P(p[0], p[1], p[2]);
  const long c = cell_of(p);
  if (c < 0) {
    if (outside_lower(p) > rq) return false;
    for (const Element& e : elements_)
      if (element_within(e, P, rq) && found(e)) return true;
    return false;
  }
  if (lower_[std::size_t(c)] * unit_ > rq) return false;
  if (rq <= reach_) return scan_list(std::size_t(c), P, rq, found);
  // A larger ball: every element within rq of p is within reach of a point x at most
  // rq - reach from p, so in the list of x's cell; read every cell that such x can be in.
  const double out = rq - reach_ + pad_;
  int lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::max(0, int(std::floor((p[k] - out - origin_[k]) / h_)));
    hi[k] = std::min(n_[k] - 1, int(std::floor((p[k] + out - origin_[k]) / h_)));
  }
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        const std::size_t cell = std::size_t(x) + n_[0] * (std::size_t(y) + std::size_t(n_[1]) * z);
        const Eigen::Vector3d m = centre(cell);
        double d2 = 0.0;  // from p to the cell's box
        for (int k = 0; k < 3; ++k) {
          const double d = std::max(std::abs(P[k] - m[k]) - h_ / 2, 0.0);
          d2 += d * d;
        }
        if (std::sqrt(d2) <= out && scan_list(cell, P, rq, found)) return true;
      }
  return false;
}

bool SceneGrid::within(const double* p, double rq) const {
  return scan(p, rq, [](const Element&) { return true; });
}

void SceneGrid::objects_within(const double* p, double rq, std::vector<std::uint32_t>& out) const {
  scan(p, rq, [&out](const Element& e) {
    out.push_back(e.object);
    return false;
  });
}

}  // namespace medspheres::check::detail
