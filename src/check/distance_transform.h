#pragma once
// The exact Euclidean distance transform of a 3-D grid of cells (Felzenszwalb and
// Huttenlocher, "Distance transforms of sampled functions", 2012): for every cell, the
// squared distance, in cells, from its centre to the centre of the nearest marked cell.

#include <cstddef>
#include <vector>

namespace medspheres::check::detail {

/// \p marked: nx * ny * nz flags, x fastest. Returns the squared distances (a value of
/// at least 3 * (nx + ny + nz)^2 where nothing is marked).
std::vector<double> squared_distance_transform(const std::vector<char>& marked, int nx, int ny,
                                               int nz);

}  // namespace medspheres::check::detail
