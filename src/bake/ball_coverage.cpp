#include "ball_coverage.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "medspheres/threads.h"

namespace medspheres {

namespace {

constexpr int kBlock = 8;  // cells per block side
constexpr int kBlockCells = kBlock * kBlock * kBlock;
// At most this many blocks in the box (5 bytes each while sampling): the cell is coarsened
// until they fit, which only a solid filling a tiny part of its box needs.
constexpr double kMaxBlocks = 1 << 22;

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// How a ball meets an axis-aligned box.
enum class Meets { kNot, kPart, kWhole };

Meets meets(const Sphere& b, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const double r2 = b.radius * b.radius;
  const Eigen::Vector3d near = (lo - b.center).cwiseMax(b.center - hi).cwiseMax(0.0);
  if (near.squaredNorm() > r2) return Meets::kNot;
  const Eigen::Vector3d far = (lo - b.center).cwiseAbs().cwiseMax((hi - b.center).cwiseAbs());
  return far.squaredNorm() <= r2 ? Meets::kWhole : Meets::kPart;
}

// The grid: cells of side s from origin, grouped in blocks of 8^3 cells; a point per cell,
// at a position in the cell drawn from a hash of its index (stratified, so that the faces
// of an axis-aligned solid do not line up with rows of points).
class Grid {
 public:
  Grid(const Eigen::AlignedBox3d& box, double s) : s_(s) {
    origin_ = box.min() - Eigen::Vector3d::Constant(s);
    for (int a = 0; a < 3; ++a) {
      cells_[a] = static_cast<long long>(std::ceil(box.sizes()[a] / s)) + 2;
      blocks_[a] = (cells_[a] + kBlock - 1) / kBlock;
    }
  }
  static double blocks_for(const Eigen::AlignedBox3d& box, double s) {
    double n = 1.0;
    for (int a = 0; a < 3; ++a) n *= std::ceil((std::ceil(box.sizes()[a] / s) + 2.0) / kBlock);
    return n;
  }
  const std::array<long long, 3>& blocks() const { return blocks_; }
  std::size_t num_blocks() const {
    return static_cast<std::size_t>(blocks_[0] * blocks_[1] * blocks_[2]);
  }
  std::size_t block_index(const std::array<long long, 3>& b) const {
    return static_cast<std::size_t>(b[0] + blocks_[0] * (b[1] + blocks_[1] * b[2]));
  }
  Eigen::Vector3d block_min(const std::array<long long, 3>& b) const {
    return origin_ + kBlock * s_ * Eigen::Vector3d(b[0], b[1], b[2]);
  }
  Eigen::Vector3d block_max(const std::array<long long, 3>& b) const {
    return block_min(b) + Eigen::Vector3d::Constant(kBlock * s_);
  }
  // The blocks that the ball's bounding box meets: calls f(block coordinates, index).
  template <typename F>
  void for_blocks(const Sphere& b, F f) const {
    std::array<long long, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      const double side = kBlock * s_;
      const auto at = [&](double x) {
        return std::clamp(static_cast<long long>(std::floor((x - origin_[a]) / side)), 0LL,
                          blocks_[a] - 1);
      };
      lo[a] = at(b.center[a] - b.radius);
      hi[a] = at(b.center[a] + b.radius);
    }
    std::array<long long, 3> c{};
    for (c[2] = lo[2]; c[2] <= hi[2]; ++c[2])
      for (c[1] = lo[1]; c[1] <= hi[1]; ++c[1])
        for (c[0] = lo[0]; c[0] <= hi[0]; ++c[0]) f(c, block_index(c));
  }
  // The cell `local` (0..511, x fastest) of block b: its hash, or 0 if it lies beyond the
  // grid (no point there).
  std::uint64_t cell_hash(const std::array<long long, 3>& b, int local) const {
    const long long x = b[0] * kBlock + local % kBlock;
    const long long y = b[1] * kBlock + (local / kBlock) % kBlock;
    const long long z = b[2] * kBlock + local / (kBlock * kBlock);
    if (x >= cells_[0] || y >= cells_[1] || z >= cells_[2]) return 0;
    return splitmix64(static_cast<std::uint64_t>(x + cells_[0] * (y + cells_[1] * z))) | 1;
  }
  Eigen::Vector3d point(const std::array<long long, 3>& b, int local) const {
    const std::uint64_t h = cell_hash(b, local);
    const Eigen::Vector3d u(static_cast<double>(h & 0x1fffff), (h >> 21) & 0x1fffff,
                            (h >> 42) & 0x1fffff);
    const Eigen::Vector3d cell(b[0] * kBlock + local % kBlock,
                               b[1] * kBlock + (local / kBlock) % kBlock,
                               b[2] * kBlock + local / (kBlock * kBlock));
    return origin_ + s_ * (cell + u / static_cast<double>(1 << 21));
  }

 private:
  double s_;
  Eigen::Vector3d origin_;
  std::array<long long, 3> cells_{}, blocks_{};
};

// The blocks the balls meet, numbered in block order, with the points each keeps.
struct Blocks {
  std::vector<int> slot;                     // per block of the grid: -1 or its number
  std::vector<std::array<long long, 3>> at;  // per slot: block coordinates
  std::vector<std::uint32_t> weight;         // per slot
  std::vector<std::size_t> first;            // per slot: its first point (one more at the end)
  std::vector<Eigen::Vector3f> offset;       // per point: its position - the block's minimum
};

Blocks keep_points(const Grid& grid, const std::vector<Sphere>& balls, std::uint32_t depth) {
  std::vector<std::uint32_t> centre(grid.num_blocks(), 0);  // balls holding the block's centre
  std::vector<char> met(grid.num_blocks(), 0);
  for (const Sphere& b : balls)
    grid.for_blocks(b, [&](const std::array<long long, 3>& c, std::size_t i) {
      const Eigen::Vector3d lo = grid.block_min(c), hi = grid.block_max(c);
      if (meets(b, lo, hi) == Meets::kNot) return;
      met[i] = 1;
      if ((0.5 * (lo + hi) - b.center).squaredNorm() <= b.radius * b.radius) ++centre[i];
    });
  Blocks out;
  out.slot.assign(grid.num_blocks(), -1);
  out.first.push_back(0);
  const auto n = grid.blocks();
  std::array<long long, 3> c{};
  for (c[2] = 0; c[2] < n[2]; ++c[2])
    for (c[1] = 0; c[1] < n[1]; ++c[1])
      for (c[0] = 0; c[0] < n[0]; ++c[0]) {
        const std::size_t i = grid.block_index(c);
        if (!met[i]) continue;
        out.slot[i] = static_cast<int>(out.at.size());
        out.at.push_back(c);
        const std::uint32_t w = std::max<std::uint32_t>(1, centre[i] / depth);
        out.weight.push_back(w);
        const Eigen::Vector3d lo = grid.block_min(c);
        for (int l = 0; l < kBlockCells; ++l) {
          const std::uint64_t h = grid.cell_hash(c, l);
          if (h != 0 && (w == 1 || splitmix64(h) % w == 0))
            out.offset.push_back((grid.point(c, l) - lo).cast<float>());
        }
        out.first.push_back(out.offset.size());
      }
  return out;
}

// The kept points in ball b, ascending (blocks in index order, points in block order).
std::vector<std::uint32_t> points_in(const Grid& grid, const Blocks& blocks, const Sphere& b) {
  std::vector<std::uint32_t> out;
  grid.for_blocks(b, [&](const std::array<long long, 3>& c, std::size_t i) {
    const int slot = blocks.slot[i];
    if (slot < 0) return;
    const Eigen::Vector3d lo = grid.block_min(c);
    const Meets m = meets(b, lo, grid.block_max(c));
    if (m == Meets::kNot) return;
    const std::size_t begin = blocks.first[slot], end = blocks.first[slot + 1];
    if (m == Meets::kWhole) {
      for (std::size_t p = begin; p < end; ++p) out.push_back(static_cast<std::uint32_t>(p));
      return;
    }
    // In the block's frame, in single precision: a proxy needs no more.
    const Eigen::Vector3f centre = (b.center - lo).cast<float>();
    const float r2 = static_cast<float>(b.radius * b.radius);
    for (std::size_t p = begin; p < end; ++p)
      if ((blocks.offset[p] - centre).squaredNorm() <= r2)
        out.push_back(static_cast<std::uint32_t>(p));
  });
  return out;
}

}  // namespace

BallCoverage sample_ball_coverage(const std::vector<Sphere>& balls, const Eigen::AlignedBox3d& box,
                                  double volume, std::size_t samples, std::uint32_t depth,
                                  int threads) {
  double s = std::cbrt(volume / static_cast<double>(samples));
  while (Grid::blocks_for(box, s) > kMaxBlocks) s *= 1.25;
  const Grid grid(box, s);
  const Blocks blocks = keep_points(grid, balls, depth);
  BallCoverage c;
  c.cell = s;
  c.points.resize(balls.size());
  const long long n = static_cast<long long>(balls.size());
#pragma omp parallel for num_threads(thread_count(threads)) schedule(dynamic, 4)
  for (long long i = 0; i < n; ++i) c.points[i] = points_in(grid, blocks, balls[i]);
  // Renumber the covered points only, in order; then the owners of each.
  std::vector<std::uint32_t> count(blocks.offset.size(), 0);
  for (const auto& list : c.points)
    for (std::uint32_t p : list) ++count[p];
  std::vector<std::uint32_t> renumber(blocks.offset.size(), 0);
  c.offsets.assign(1, 0);
  for (std::size_t slot = 0; slot + 1 < blocks.first.size(); ++slot)
    for (std::size_t p = blocks.first[slot]; p < blocks.first[slot + 1]; ++p) {
      if (count[p] == 0) continue;
      renumber[p] = static_cast<std::uint32_t>(c.weight.size());
      c.weight.push_back(blocks.weight[slot]);
      c.offsets.push_back(c.offsets.back() + count[p]);
    }
  c.owners.resize(c.offsets.back());
  std::vector<std::size_t> fill(c.offsets.begin(), c.offsets.end() - 1);
  for (std::size_t j = 0; j < c.points.size(); ++j)
    for (std::uint32_t& p : c.points[j]) {
      p = renumber[p];
      c.owners[fill[p]++] = static_cast<std::uint32_t>(j);
    }
  return c;
}

}  // namespace medspheres
