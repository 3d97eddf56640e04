#pragma once
// PairTables: for the self pairs whose relative pose hangs on at most three joint
// positions (each link's frame reached from their common ancestor frame through steps
// driven by those positions alone), a grid over those positions' limits whose cells are
// marked free when the pair's spheres-mode sets are proven farther apart than a threshold
// (the margin plus the rounding allowance) at every configuration inside the cell. The
// spheres mode then skips the pair in a lane whose positions fall in a free cell: the
// pair's test would find no collision there, so no verdict changes.
//
// The proof of a cell (pair_table.cpp): at the cell's centre c the two sets' least gap
// d(c) = min |x_i - y_j| - r_i - r_j (centres posed in the common ancestor frame, doubles,
// the robot's own steps), and D = sum over the path's steps s of w_s h_s, h_s the cell's
// half-width in the step's position and w_s a bound of how fast the step moves the
// centres of its side per unit of that position (for a revolute step the largest speed of
// R(theta) = P + cos theta C + sin theta S on a vector, times the farthest centre from the
// step's frame origin, times |multiplier|, times the norms of the rotations above it on
// the path; for a prismatic one |v| |multiplier| likewise). Over the cell a centre of
// either side moves at most its own side's share of D (the triangle inequality over one
// position at a time), so the gap anywhere in the cell is at least d(c) - D, and the
// kernel's test, whose rounding stays within the allowance, finds no collision there.
// Cells per position are powers of two, at most kFineCells.
// Free when d(c) - D > threshold + pad (pad:
// the bake's own rounding, 1e-9 m and 1e-9 relative). A lane's position is found in a cell
// by (q - lower) * inverse rounded down in doubles: a rounding away from the cell, so the
// half-widths are taken 1e-6 relative larger. Positions outside the limits are never in a
// cell. Frame: the layout's; units: metres and the joints' units.

#include <cstdint>
#include <vector>

#include "medspheres/robot_model.h"
#include "robot_layout.h"

namespace medspheres::check::detail {

/// The kernel finds a lane's cell from the position's index on a grid of kFineCells cells
/// over the position's limits (one per position the tables use, a "slot"), shared by every
/// table: a table of 2^k cells along it takes the index shifted right by 16 - k.
inline constexpr double kFineCells = 65536.0;
inline constexpr int kMaxTableSlots = 64;
inline constexpr std::uint32_t kOutsideLimits = 0xFFFFFFFFu;

/// One self pair's table, as the kernel reads it (block.h): no table when bits is null.
struct PairTableView {
  int sources = 0;                      // joint positions the pair's pose hangs on
  int slot[3] = {0, 0, 0};              // of each position, into PairTables::slots()
  int shift[3] = {0, 0, 0};             // its cells: kFineCells >> shift
  std::uint32_t stride[3] = {0, 0, 0};  // of the cell's index, x fastest
  const std::uint64_t* bits = nullptr;  // one per cell: 1 free
  bool all_free = false;                // every cell
};

/// A position the tables use: its index into q, and its fine index (q - lower) * inverse
/// rounded down, in [0, kFineCells) within the limits.
struct TableSlot {
  int source = 0;
  double lower = 0.0, inverse = 0.0;
};

class PairTables {
 public:
  /// Tables of up to \p max_cells cells each (0: none) for the pairs of \p layout whose
  /// relative pose hangs on at most three positions with finite limits in \p model (the
  /// planner's robot), free beyond \p threshold metres.
  PairTables(const RobotModel& model, const RobotLayout& layout, double threshold,
             std::size_t max_cells);

  /// Per self pair of the layout.
  const std::vector<PairTableView>& views() const noexcept { return views_; }
  const std::vector<TableSlot>& slots() const noexcept { return slots_; }
  /// How many pairs have a table, and the share of their cells that is free.
  std::size_t tables() const noexcept { return tables_; }
  double free_share() const noexcept { return free_share_; }

 private:
  std::vector<std::vector<std::uint64_t>> bits_;
  std::vector<PairTableView> views_;
  std::vector<TableSlot> slots_;
  std::size_t tables_ = 0;
  double free_share_ = 0.0;
};

}  // namespace medspheres::check::detail
