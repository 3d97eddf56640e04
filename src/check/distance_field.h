#pragma once
// DistanceField: per cell of a fine grid over a SceneGrid's extent, a lower and an upper
// bound of the distance from the cell's centre to the scene, one byte each in eighths of
// the side. At a point p of the cell, d(p) lies within |p - centre| of d(centre) (distance
// is 1-Lipschitz), so one look-up clears a ball far from everything or takes one deep in
// an element, and only balls near their threshold read the grid's lists.
// Bounds: exact distances (SceneGrid::nearest) where the scene is within reach of the
// centre; beyond it, reach or the Euclidean distance transform of the cells the elements'
// boxes touch, whichever is larger, and no upper bound. Every value is rounded outward by
// `pad` and by the bytes' step; 255 as an upper bound means none is known. Frame W, metres.
// Immutable after construction.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "scene_grid.h"

namespace medspheres::check::detail {

class DistanceField {
 public:
  /// Cells of side grid.cell_side() / \p split over the grid's extent, built by \p threads
  /// (threads.h; the field the same for any count). An empty grid gives an empty field.
  DistanceField(const SceneGrid& grid, int split, int threads = 1);

  bool empty() const noexcept { return bounds_.empty(); }
  const double* origin() const noexcept { return origin_; }
  const int* dims() const noexcept { return n_; }
  double cell_side() const noexcept { return h_; }
  /// Per cell (x fastest): lower | upper << 8, each times unit(); 2 entries follow the last
  /// cell, so that a 4-byte read at any cell stays inside.
  const std::uint16_t* bounds() const noexcept {
    return bounds_.empty() ? nullptr : bounds_.data();
  }
  double unit() const noexcept { return unit_; }

 private:
  double origin_[3] = {0, 0, 0};
  double h_ = 0.0, unit_ = 0.0;
  int n_[3] = {0, 0, 0};
  std::vector<std::uint16_t> bounds_;
};

}  // namespace medspheres::check::detail
