#pragma once
// The squared distance transform of the cells that a scene's elements touch: the grid's and
// the distance field's lower bounds both start from it.

#include <vector>

#include "scene_element.h"

namespace medspheres::check::detail {

/// The transform (medspheres/distance_transform.h) of the cells that the boxes of
/// \p elements, grown by \p pad, touch, on the grid of n[0] * n[1] * n[2] cells of side \p h
/// whose corner is \p origin (frame W): per cell (x fastest), the squared distance in cells
/// from its centre to the nearest touched cell's centre; a value of at least
/// 3 * (n[0] + n[1] + n[2])^2 where no cell is touched.
std::vector<double> boxes_distance_transform(const std::vector<Element>& elements,
                                             const double* origin, double h, const int* n,
                                             double pad);

}  // namespace medspheres::check::detail
