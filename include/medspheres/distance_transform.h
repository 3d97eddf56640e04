#pragma once
// The exact squared Euclidean distance transform of a 3D grid of cells (Felzenszwalb and
// Huttenlocher, "Distance transforms of sampled functions", Theory of Computing 8, 2012):
// for every cell, the squared distance between its centre and the nearest seed cell's
// centre, in cells (an integer: the distance between lattice points), computed exactly in
// three 1D passes of lower envelopes of parabolas, O(cells). The robust solid (mesh) and the
// checker's scene grid and distance field (check) start from it.

#include <array>
#include <cstdint>
#include <vector>

namespace medspheres::detail {

/// Squared distances are at most this; a grid without seeds gives kNoSeed everywhere.
inline constexpr std::int64_t kNoSeed = std::int64_t{1} << 60;

/// For the grid of \p n cells (x fastest: index i + n0 (j + n1 k)) whose seeds are the cells
/// with is_seed[index] true: the squared distance in cells from each cell to the nearest
/// seed (0 on seeds), or kNoSeed when there is none. Each pass's lines run on \p threads
/// (medspheres/threads.h: 0 for every core); the result is the same for any count.
std::vector<std::int64_t> squared_distance_transform(const std::array<std::int64_t, 3>& n,
                                                     const std::vector<bool>& is_seed,
                                                     int threads = 1);

}  // namespace medspheres::detail
