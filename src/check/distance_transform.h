#pragma once
// The exact Euclidean distance transform of a 3-D grid of cells (Felzenszwalb and
// Huttenlocher, "Distance transforms of sampled functions", 2012): for every cell, the
// squared distance, in cells, from its centre to the centre of the nearest marked cell.

#include <cstddef>
#include <vector>

#include "scene_element.h"

namespace medspheres::check::detail {

/// \p marked: nx * ny * nz flags, x fastest. Returns the squared distances (a value of
/// at least 3 * (nx + ny + nz)^2 where nothing is marked).
std::vector<double> squared_distance_transform(const std::vector<char>& marked, int nx, int ny,
                                               int nz);

/// The transform of the cells that the boxes of \p elements, grown by \p pad, touch, on the
/// grid of n[0] * n[1] * n[2] cells of side \p h whose corner is \p origin (frame W).
std::vector<double> boxes_distance_transform(const std::vector<Element>& elements,
                                             const double* origin, double h, const int* n,
                                             double pad);

}  // namespace medspheres::check::detail
