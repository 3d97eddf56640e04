#pragma once
/// \file
/// Where a cover should stick out less: a weight on the protrusion of the balls that hold
/// given regions of the surface (CoverOptions::weights, bake_cover only).
///
/// A ball (c, r) reaches the region when some of `points` is within r + `reach` of c. The
/// bake's protrusion stage lowers the largest weighted protrusion, weight x (r - D(c)) for a
/// ball that reaches the region and r - D(c) for the others: the balls that reach the region
/// stick out about 1 / weight as far as the others, or stay out of it. For a planner, the
/// points are where other links come (contact_regions.h): a ball that sticks out far there
/// reports collisions the meshes do not have. The covering certificate is the same as without
/// weights (the surface is covered, proven); only where the budget's balls go changes.
///
/// Frames and units: those of the mesh baked. Empty points or a weight of 1: the bake is
/// the unweighted one, bit for bit.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace medspheres {

struct ProtrusionWeights {
  std::vector<Eigen::Vector3d> points;  ///< the region's seeds, in the mesh's frame
  double reach = 0.0;                   ///< a length, finite and >= 0
  double weight = 1.0;                  ///< finite and >= 1
  bool active() const { return !points.empty() && weight != 1.0; }
};

/// What bake_cover refuses in \p w ("weights.reach must be finite and >= 0, got -1"), or
/// empty when it accepts it.
std::string protrusion_weights_problem(const ProtrusionWeights& w);

}  // namespace medspheres
