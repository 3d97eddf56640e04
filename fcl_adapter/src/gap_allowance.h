#pragma once
// Private to the fcl_adapter target: the one rounding rule for a gap between bounds
// computed in doubles. A gap is certainly greater than a margin when it exceeds it by 1e-12
// of the magnitudes involved (the coordinates, sizes and the margin), far above the few
// ulps of error of such a gap.

#include <cmath>

namespace medspheres::fcl::detail {

/// The allowance for a gap computed from values of magnitude up to \p scale (>= 0),
/// compared with \p margin.
inline double gap_allowance(double scale, double margin) {
  return 1e-12 * (scale + std::abs(margin));
}

/// Whether \p gap is certainly greater than \p margin (false for a NaN or infinite gap).
inline bool gap_beyond(double gap, double scale, double margin) {
  return std::isfinite(gap) && gap - gap_allowance(scale, margin) > margin;
}

/// gap_beyond for the gap sqrt(d2) - sub (a distance given by its square d2, less radii
/// \p sub), without the square root: sqrt(d2) must exceed margin + allowance + sub.
inline bool squared_gap_beyond(double d2, double sub, double scale, double margin) {
  const double reach = margin + gap_allowance(scale, margin) + sub;
  if (!std::isfinite(d2) || !std::isfinite(reach)) return false;
  return reach < 0.0 || d2 > reach * reach;
}

}  // namespace medspheres::fcl::detail
