#pragma once
// SceneGrid: a check::Scene made for sphere queries (a uniform grid over the scene, in the
// manner of VAMP's collision-affording point tree, for every kind of element):
// - per cell, a certified lower bound (one byte, in eighths of the side) of the distance
//   from its centre to the nearest element: the larger of the listed elements' bound (below)
//   and an exact Euclidean distance transform of the cells that elements' boxes touch; at a
//   point p of the cell, that less |p - centre| bounds the distance from p (distance is
//   1-Lipschitz), so that a query ball far from everything is cleared with one look-up,
//   however large;
// - per cell, the elements within `reach` of the cell, with their distance from the cell's
//   centre (rounded down and up) and ordered by it: a ball of radius up to reach centred at
//   p in the cell, delta from the centre, is decided by the elements listed, skipping those
//   farther than radius + delta, taking as touching those nearer than radius - delta, then
//   the same with a ball around each element, and testing the others exactly; a larger ball goes
//   through the cells within its radius less reach (every element within its radius is within reach
//   of one of them).
// Frame W, metres. Every bound is rounded down by `pad` (a few orders of magnitude above
// the rounding of the doubles involved), so that "clear" is certain and never disagrees
// with the exact test. Immutable after construction: const queries are thread-safe.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "medspheres/check/scene.h"
#include "scene_element.h"

namespace medspheres::check::detail {

class SceneGrid {
 public:
  /// \p reach: the query radius answered from one cell's list (larger ones read the cells
  /// around); \p cell: the cell side (0: reach / 2); at most \p max_cells cells (the side
  /// grows to fit); \p pad: the rounding allowance of bounds; \p threads: the build's
  /// threads (threads.h), the grid the same for any count.
  SceneGrid(const Scene& scene, double reach, double cell, std::size_t max_cells, double pad,
            int threads = 1);

  bool empty() const noexcept { return elements_.empty(); }
  double reach() const noexcept { return reach_; }
  double cell_side() const noexcept { return h_; }
  std::size_t num_cells() const noexcept { return begin_.empty() ? 0 : begin_.size() - 1; }
  std::size_t num_entries() const noexcept { return entries_.size(); }
  std::size_t num_elements() const noexcept { return elements_.size(); }

  /// The grid's frame and lower bounds (null when empty), cells x fastest.
  const double* origin() const noexcept { return origin_.data(); }
  const int* dims() const noexcept { return n_; }
  /// Cell c's centre is at least lower_bounds()[c] * lower_unit() from every element, less
  /// the pad; 3 bytes follow the last cell, so that a 4-byte read at any cell stays inside.
  const std::uint8_t* lower_bounds() const noexcept {
    return lower_.empty() ? nullptr : lower_.data();
  }
  double lower_unit() const noexcept { return unit_; }
  /// The elements' bounding box (empty when there is none).
  const Eigen::AlignedBox3d& bounds() const noexcept { return bounds_; }
  double pad() const noexcept { return pad_; }

  /// True when certainly no element lies within \p rq of \p p.
  bool clear(const double* p, double rq) const;
  /// True when some element lies within \p rq of \p p (closed, exact as element_within).
  bool within(const double* p, double rq) const;
  /// Three-valued within for a point known to \p slack (>= 0): 1 when some element lies
  /// within rq - slack of p (exact as element_within), 0 when none lies within rq + slack,
  /// else 2. With slack 0, within() as 0 or 1.
  int classify(const double* p, double rq, double slack) const;
  /// The exact distance from \p p to the nearest element when it is at most \p limit
  /// (<= reach()), else some value above \p limit; as element_distance computes it.
  double nearest(const double* p, double limit) const;
  const std::vector<Element>& elements() const noexcept { return elements_; }
  /// The objects with an element within \p rq of \p p, appended to \p out (repeats too).
  void objects_within(const double* p, double rq, std::vector<std::uint32_t>& out) const;

 private:
  struct Entry {
    std::uint32_t element;
    float lower, upper;  // <= and >= the distance from the cell's centre to the element
  };
  long cell_of(const double* p, long* xyz = nullptr) const;
  template <class Found>
  bool scan(const double* p, double rq_in, double rq_out, Found&& found) const;
  template <class Found>
  bool scan_list(std::size_t c, const Eigen::Vector3d& centre, const Eigen::Vector3d& p,
                 double rq_in, double rq_out, Found&& found) const;
  Eigen::Vector3d centre(long x, long y, long z) const;
  double outside_lower(const double* p) const;
  double cell_lower(std::size_t c, const Eigen::Vector3d& centre, const Eigen::Vector3d& p) const;
  struct Hit {
    std::uint32_t cell, element;
    float lower, upper;
  };
  std::size_t reach_cells(std::size_t i, double pad, int* lo, int* hi) const;
  void list_element(std::size_t i, double pad, std::vector<Hit>& hits) const;
  void build_lists(double pad, int threads);
  void build_lower(double pad, int threads);

  std::vector<Element> elements_;
  std::vector<double> balls_;   // per element: its ball's centre and radius (x, y, z, r)
  Eigen::AlignedBox3d bounds_;  // of the elements
  double reach_ = 0.0, h_ = 0.0, inverse_h_ = 0.0, unit_ = 0.0, pad_ = 0.0;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  int n_[3] = {0, 0, 0};
  std::vector<std::uint8_t> lower_;   // per cell, in units of unit_ (rounded down); 3 more
  std::vector<std::uint32_t> begin_;  // per cell + 1: its entries
  std::vector<Entry> entries_;
};

}  // namespace medspheres::check::detail
