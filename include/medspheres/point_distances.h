#pragma once
/// \file
/// Many points against one sphere tree: the tree-and-point distance of sphere_tree.h for
/// each point of an array, the call that vectorised callers (the Python module, a grid
/// of query points) make.
///
/// Frames: A's pose X_WA; the points p_WQ in W, row-major n x 3. Results as
/// distance(a, X_WA, p_WQ): the signed distance to the union of A's balls (see there),
/// and the index of the ball that realises it. Threads: one call runs on the calling
/// thread; many calls may run at once on the same tree.
/// Errors: std::invalid_argument for a non-finite pose or point (naming the point's row).

#include <cstddef>
#include <cstdint>

#include <Eigen/Geometry>

#include "medspheres/sphere_tree.h"

namespace medspheres {

/// For i < n: out[i] = distance(a, X_WA, (xyz[3i], xyz[3i+1], xyz[3i+2])).distance and,
/// when \p sphere is given, sphere[i] its sphere_a (-1 for an empty tree, whose
/// distances are +infinity).
void point_distances(const SphereTree& a, const Eigen::Isometry3d& X_WA, const double* xyz,
                     std::size_t n, double* out, std::intptr_t* sphere = nullptr);

}  // namespace medspheres
