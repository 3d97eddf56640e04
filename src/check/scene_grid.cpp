#include "scene_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "boxes_distance_transform.h"
#include "medspheres/threads.h"

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
// Cells are indexed by 32-bit integers in the kernel's look-ups.
constexpr std::size_t kMaxCells = std::size_t(1) << 30;

}  // namespace

SceneGrid::SceneGrid(const Scene& scene, double reach, double cell, std::size_t max_cells,
                     double pad, int threads)
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
    if (cells <= static_cast<double>(std::clamp<std::size_t>(max_cells, 1, kMaxCells))) break;
    h_ *= std::max(
        1.01,
        std::cbrt(cells / static_cast<double>(std::clamp<std::size_t>(max_cells, 1, kMaxCells))));
  }
  origin_ = bounds_.min().array() - (reach + h_);
  inverse_h_ = 1.0 / h_;
  unit_ = h_ / kLowerSteps;
  build_lists(pad, threads);
  build_lower(pad, threads);
}

long SceneGrid::cell_of(const double* p, long* xyz) const {
  long index = 0, stride = 1;
  for (int k = 0; k < 3; ++k) {
    const double u = (p[k] - origin_[k]) * inverse_h_;  // a rounding off: within the pad
    if (!(u >= 0.0) || u >= n_[k]) return -1;
    const auto i = static_cast<long>(u);
    if (xyz) xyz[k] = i;
    index += i * stride;
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

// The cells [lo, hi] (inclusive, per axis) that element i's box, grown by reach + pad,
// touches; returns their count.
std::size_t SceneGrid::reach_cells(std::size_t i, double pad, int* lo, int* hi) const {
  const Element& e = elements_[i];
  std::size_t count = 1;
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::max(0, int(std::floor((e.box.min()[k] - reach_ - pad - origin_[k]) / h_)));
    hi[k] = std::min(n_[k] - 1, int(std::floor((e.box.max()[k] + reach_ + pad - origin_[k]) / h_)));
    count *= std::size_t(std::max(hi[k] - lo[k] + 1, 0));
  }
  return count;
}

// Element i's entries (the cells within reach of it) appended to `hits`, cells in order.
void SceneGrid::list_element(std::size_t i, double pad, std::vector<Hit>& hits) const {
  const Element& e = elements_[i];
  int lo[3], hi[3];
  reach_cells(i, pad, lo, hi);
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

// The elements in chunks of consecutive indices, each chunk's hits apart, then gathered
// per cell in the chunks' order and sorted: the lists are the same for any thread count.
// A chunk reserves a hit for every cell of its elements' boxes, up to kReserve (a chunk of
// a point cloud's points grows no vector; one of long diagonal triangles, whose boxes hold
// far more cells than they reach, reserves no more than that).
void SceneGrid::build_lists(double pad, int threads) {
  const std::size_t cells = std::size_t(n_[0]) * n_[1] * n_[2];
  constexpr std::size_t kChunk = 256, kReserve = std::size_t(1) << 16;
  const std::size_t count = elements_.size(), chunks = (count + kChunk - 1) / kChunk;
  std::vector<std::vector<Hit>> hits(chunks);
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count(threads))
  for (long j = 0; j < long(chunks); ++j) {
    const std::size_t first = std::size_t(j) * kChunk, last = std::min(count, first + kChunk);
    std::size_t most = 0;
    for (std::size_t i = first; i < last; ++i) {
      int lo[3], hi[3];
      most += reach_cells(i, pad, lo, hi);
    }
    hits[std::size_t(j)].reserve(std::min(most, kReserve));
    for (std::size_t i = first; i < last; ++i) list_element(i, pad, hits[std::size_t(j)]);
  }
  begin_.assign(cells + 1, 0);
  for (const std::vector<Hit>& chunk : hits)
    for (const Hit& h : chunk) ++begin_[h.cell + 1];
  for (std::size_t c = 0; c < cells; ++c) begin_[c + 1] += begin_[c];
  entries_.resize(begin_[cells]);
  std::vector<std::uint32_t> next(begin_.begin(), begin_.end() - 1);
  for (std::vector<Hit>& chunk : hits) {
    for (const Hit& h : chunk) entries_[next[h.cell]++] = {h.element, h.lower, h.upper};
    std::vector<Hit>().swap(chunk);
  }
#pragma omp parallel for schedule(dynamic, 4096) num_threads(thread_count(threads))
  for (long c = 0; c < long(cells); ++c)
    std::sort(entries_.begin() + begin_[std::size_t(c)],
              entries_.begin() + begin_[std::size_t(c) + 1], [](const Entry& a, const Entry& b) {
                return a.lower < b.lower || (a.lower == b.lower && a.element < b.element);
              });
}

// Per cell: a lower bound of the distance from its centre to the scene, the larger of the
// lists' (the first entry, or reach when none is listed: every element
// not listed is farther than that from the centre) and the distance transform's.
void SceneGrid::build_lower(double pad, int threads) {
  const std::size_t cells = begin_.size() - 1;
  const std::vector<std::int64_t> d2 =
      boxes_distance_transform(elements_, origin_.data(), h_, n_, pad, threads);
  lower_.assign(cells + 3, 0);  // 3 bytes beyond the last cell for 4-byte reads
  // Every element not listed is farther than reach from the cell, so from its centre.
  const double unlisted = reach_;
  for (std::size_t c = 0; c < cells; ++c) {
    // A cube of side h whose centre is D h from this centre is at least (D - sqrt 3 / 2) h
    // from it.
    const double transform = h_ * (std::sqrt(double(d2[c])) - kHalfDiagonal) - pad;
    const double listed =
        begin_[c] < begin_[c + 1] ? double(entries_[begin_[c]].lower) - pad : unlisted;
    const double value = std::max({std::min(listed, unlisted), transform, 0.0});
    double q = std::min(std::floor(value / unit_), 255.0);
    if (q * unit_ > value) q -= 1.0;  // the division rounded up
    lower_[c] = static_cast<std::uint8_t>(std::max(q, 0.0));
  }
}

// The cell's bound at p: its centre's, less |p - centre| (distance is 1-Lipschitz), less
// the pad for the rounding of that.
double SceneGrid::cell_lower(std::size_t c, const Eigen::Vector3d& centre,
                             const Eigen::Vector3d& p) const {
  return lower_[c] * unit_ - (p - centre).norm() - pad_;
}

bool SceneGrid::clear(const double* p, double rq) const {
  if (elements_.empty()) return true;
  long xyz[3];
  const long c = cell_of(p, xyz);
  if (c < 0) return outside_lower(p) > rq;
  return cell_lower(std::size_t(c), centre(xyz[0], xyz[1], xyz[2]),
                    Eigen::Vector3d(p[0], p[1], p[2])) > rq;
}

Eigen::Vector3d SceneGrid::centre(long x, long y, long z) const {
  return origin_ + h_ * Eigen::Vector3d(double(x) + 0.5, double(y) + 0.5, double(z) + 0.5);
}

// The list of cell c (centred at `centre`): the elements within rq_out of p, to
// found(element, certain) until it returns true (then true), certain when the element is
// within rq_in <= rq_out. An element farther than rq + delta from the centre (delta =
// |p - centre|, padded) is farther than rq from p; one nearer than rq - delta is within;
// then the same with the element's ball (its centre's distance d from p, its radius b:
// beyond when d - b > rq, within when d + b <= rq); the others are tested exactly. The
// pads keep the shortcuts on the side the exact test would take.
template <class Found>
bool SceneGrid::scan_list(std::size_t c, const Eigen::Vector3d& centre, const Eigen::Vector3d& p,
                          double rq_in, double rq_out, Found&& found) const {
  const double delta = (p - centre).norm() + pad_;
  for (std::uint32_t k = begin_[c]; k < begin_[c + 1]; ++k) {
    const Entry& entry = entries_[k];
    if (double(entry.lower) - delta > rq_out) break;
    const double* ball = &balls_[4 * std::size_t(entry.element)];
    const double dx = p.x() - ball[0], dy = p.y() - ball[1], dz = p.z() - ball[2];
    const double d2 = dx * dx + dy * dy + dz * dz;
    const double beyond = rq_out + ball[3] + pad_;
    if (d2 > beyond * beyond) continue;
    const double inside = rq_in - ball[3] - pad_;
    const Element& e = elements_[entry.element];
    bool certain =
        double(entry.upper) + delta + pad_ <= rq_in || (inside >= 0.0 && d2 <= inside * inside);
    if (!certain) {
      const double in = rq_in + e.radius, out = rq_out + e.radius;
      if (out < 0.0) continue;
      const double core = core_distance_sq(e, p);
      if (core > out * out) continue;
      certain = in >= 0.0 && core <= in * in;
    }
    if (found(e, certain)) return true;
  }
  return false;
}

// Every element within rq_out of p to found(element, certain) until it returns true (then
// true), certain when within rq_in <= rq_out.
template <class Found>
bool SceneGrid::scan(const double* p, double rq_in, double rq_out, Found&& found) const {
  if (elements_.empty() || rq_out < 0.0) return false;
  const Eigen::Vector3d P(p[0], p[1], p[2]);
  long xyz[3];
  const long c = cell_of(p, xyz);
  if (c < 0) {
    if (outside_lower(p) > rq_out) return false;
    for (const Element& e : elements_) {
      const double in = rq_in + e.radius, out = rq_out + e.radius;
      if (out < 0.0) continue;
      const double core = core_distance_sq(e, P);
      if (core <= out * out && found(e, in >= 0.0 && core <= in * in)) return true;
    }
    return false;
  }
  const Eigen::Vector3d mid = centre(xyz[0], xyz[1], xyz[2]);
  if (cell_lower(std::size_t(c), mid, P) > rq_out) return false;
  if (rq_out <= reach_) return scan_list(std::size_t(c), mid, P, rq_in, rq_out, found);
  // A larger ball: every element within rq of p is within reach of a point x at most
  // rq - reach from p, so in the list of x's cell; read every cell that such x can be in.
  const double out = rq_out - reach_ + pad_;
  int lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::max(0, int(std::floor((p[k] - out - origin_[k]) / h_)));
    hi[k] = std::min(n_[k] - 1, int(std::floor((p[k] + out - origin_[k]) / h_)));
  }
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        const std::size_t cell = std::size_t(x) + n_[0] * (std::size_t(y) + std::size_t(n_[1]) * z);
        const Eigen::Vector3d m = centre(x, y, z);
        double d2 = 0.0;  // from p to the cell's box
        for (int k = 0; k < 3; ++k) {
          const double d = std::max(std::abs(P[k] - m[k]) - h_ / 2, 0.0);
          d2 += d * d;
        }
        if (std::sqrt(d2) <= out && scan_list(cell, m, P, rq_in, rq_out, found)) return true;
      }
  return false;
}

bool SceneGrid::within(const double* p, double rq) const {
  return scan(p, rq, rq, [](const Element&, bool) { return true; });
}

int SceneGrid::classify(const double* p, double rq, double slack) const {
  bool maybe = false;
  const bool hit = scan(p, rq - slack, rq + slack, [&maybe](const Element&, bool certain) {
    maybe = true;
    return certain;
  });
  return hit ? 1 : maybe ? 2 : 0;
}

double SceneGrid::nearest(const double* p, double limit) const {
  const double inf = std::numeric_limits<double>::infinity();
  long xyz[3];
  const long c = cell_of(p, xyz);
  if (c < 0 || limit > reach_) return inf;
  const Eigen::Vector3d P(p[0], p[1], p[2]);
  const double delta = (P - centre(xyz[0], xyz[1], xyz[2])).norm() + pad_;
  double best = inf;
  for (std::uint32_t k = begin_[std::size_t(c)]; k < begin_[std::size_t(c) + 1]; ++k) {
    const Entry& entry = entries_[k];
    if (double(entry.lower) - delta > std::min(best, limit)) break;
    best = std::min(best, element_distance(elements_[entry.element], P));
  }
  return best;
}

void SceneGrid::objects_within(const double* p, double rq, std::vector<std::uint32_t>& out) const {
  scan(p, rq, rq, [&out](const Element& e, bool) {
    out.push_back(e.object);
    return false;
  });
}

}  // namespace medspheres::check::detail
