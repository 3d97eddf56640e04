#pragma once
// Weighted sample points of a union of balls, and which balls cover each: the volume proxy
// that bake_inner_budget maximises over subsets of the balls.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "medspheres/sphere_set.h"

namespace medspheres {

// For subsets T of the balls, the sum of the weights of the points that some ball of T
// covers estimates vol(union of T) / s^3 without bias, s^3 the volume of a cell.
struct BallCoverage {
  double cell = 0.0;                               // s
  std::vector<std::uint32_t> weight;               // per point, >= 1
  std::vector<std::vector<std::uint32_t>> points;  // per ball, ascending point indices
  std::vector<std::size_t> offsets;                // per point: its range in owners
  std::vector<std::uint32_t> owners;               // ball indices, ascending per point
  std::size_t num_points() const { return weight.size(); }
};

// Sample points (ball_coverage.cpp): one per cell of a grid of side s = cbrt(volume /
// samples) over \p box, at a position in the cell drawn from a hash of its index; in a
// block of 8^3 cells whose centre lies in n > \p depth balls, about one point in
// w = floor(n / depth) is kept (by a hash of the cell), with weight w: the points deep in
// the union, which any choice covers, are thinned. Only points in some ball are kept.
// Bit-identical for every thread count. Precondition: every ball lies in \p box;
// volume > 0, samples >= 1, depth >= 1.
BallCoverage sample_ball_coverage(const std::vector<Sphere>& balls, const Eigen::AlignedBox3d& box,
                                  double volume, std::size_t samples, std::uint32_t depth,
                                  int threads);

}  // namespace medspheres
