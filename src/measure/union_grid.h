#pragma once
// UnionGrid: a uniform grid over a set of closed balls that answers two point queries
// against their union U: which ball holds a point, and how far a point is from U.
//
// Cells are cubes of side h, laid from the minimum corner of the balls' bounding box: the
// median radius, raised so that there are at most 128 cells along the box's largest side
// and at most 64 cells per ball, and to at least 2^20 eps times the magnitude of the
// coordinates (and 2^-900): any finite radii > 0, subnormal ones included, give a grid of
// at most 129^3 cells with finite cell indices. A cell that lies inside one ball
// (with a margin, below) keeps only that ball, the one of smallest index: every point of
// the cell is in U, and that ball is at least as near to any point as the part of U in
// the cell. Every other cell keeps, in ascending order, the balls that meet it.
//
// Rounding. A point is mapped to a cell by rounding, so it may land in a cell it lies
// up to a few units in the last place outside. Cells are therefore compared with the
// balls with a margin `slack_` (64 eps times the magnitude of the coordinates plus h):
// "inside a ball" means within r - slack_ of its centre, "meets a ball" within
// r + slack_. The final test of a point against a ball, |p - c|^2 <= r^2, is the same
// double-precision comparison a brute-force loop makes.
//
// Thread safety: immutable after construction; const members may run concurrently.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/sphere_set.h"

namespace medspheres::detail {

class UnionGrid {
 public:
  /// Precondition: \p balls is not empty, every centre finite, every radius finite and > 0
  /// (validate_sphere_set), so that the balls' bounding box is finite.
  explicit UnionGrid(const std::vector<Sphere>& balls);

  /// A ball that contains p (closed balls), or -1 when none does: for a cell inside a
  /// ball that ball, otherwise the first of the cell's list.
  int containing(const Eigen::Vector3d& p) const;

  /// The distance from p to U (0 when p is in U) and a ball that realizes it: for p in
  /// U a ball containing p, otherwise the ball of least |p - c| - r found first in a
  /// fixed order that depends only on the balls and p.
  struct Nearest {
    double distance = 0.0;
    int ball = -1;
  };
  Nearest nearest(const Eigen::Vector3d& p) const;

 private:
  // The cell side, origin, counts and rounding slack for balls of bounding box \p box and
  // radii \p radii (reordered).
  void size_cells(const Eigen::AlignedBox3d& box, std::vector<double>& radii);
  // Calls fn(cell, near2, far2) for every cell of the ball's bounding box, with the squared
  // distances from the centre to the nearest and the farthest point of the cell.
  template <class Fn>
  void for_each_cell(const Eigen::Vector4d& b, Fn&& fn) const;
  // Each cell's list (start_, items_) and whether one ball holds it whole (full_).
  void build_lists();
  std::array<long long, 3> cell_of(const Eigen::Vector3d& p) const;
  std::size_t flat(long long x, long long y, long long z) const {
    return (static_cast<std::size_t>(x) * static_cast<std::size_t>(dims_[1]) +
            static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(dims_[2]) +
           static_cast<std::size_t>(z);
  }
  // Offers the balls of cell (x, y, z) to \p best, unless the cell is farther than the
  // best ball; returns true when p is inside one of them.
  bool visit(long long x, long long y, long long z, const Eigen::Vector3d& p, Nearest& best) const;
  // A lower bound on the distance from p to every cell at Chebyshev index distance >= k
  // from p's cell \p c.
  double beyond(const Eigen::Vector3d& p, const std::array<long long, 3>& c, long long k) const;

  std::vector<Eigen::Vector4d> balls_;  // centre, radius
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  double h_ = 1.0;
  double inv_h_ = 1.0;
  double slack_ = 0.0;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::size_t> start_;  // cell c holds items_[start_[c] .. start_[c + 1])
  std::vector<int> items_;
  std::vector<std::uint8_t> full_;  // 1: the cell lies inside its single listed ball
};

}  // namespace medspheres::detail
