#pragma once
// The squared distance transform of the cells that a scene's elements touch: the grid's and
// the distance field's lower bounds both start from it.

#include <cstdint>
#include <vector>

#include "scene_element.h"

namespace medspheres::check::detail {

/// The transform (medspheres/distance_transform.h) of the cells that the boxes of
/// \p elements, grown by \p pad, touch, on the grid of n[0] * n[1] * n[2] cells of side \p h
/// whose corner is \p origin (frame W): per cell (x fastest), the squared distance in cells
/// from its centre to the nearest touched cell's centre; kNoSeed (2^60, far beyond the
/// grid) where no cell is touched. On \p threads (threads.h), the same for any count.
std::vector<std::int64_t> boxes_distance_transform(const std::vector<Element>& elements,
                                                   const double* origin, double h, const int* n,
                                                   double pad, int threads);

}  // namespace medspheres::check::detail
