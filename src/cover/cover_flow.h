#pragma once
// Private to the covering bake (cover.cpp): the volume flow, its volume stage. Derivation
// and choices in cover_flow.cpp.

#include <limits>
#include <vector>

#include <Eigen/Core>

#include "cover_elements.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_set.h"

namespace medspheres::detail {

struct FlowOptions {
  double cap = std::numeric_limits<double>::infinity();  // protrusion aimed at, a length
  int iterations = 240;
  int threads = 1;
};

// The balls moved and resized, all at once, down the union's volume plus two penalties: an
// element of \p e outside every ball (by the distance its farthest point lies beyond the
// nearest ball), and a ball protruding beyond options.cap. The penalties sharpen as the flow
// runs; the result is close to holding every element, not certain to: the caller makes it
// hold them. Deterministic: the same balls for every thread count.
std::vector<Sphere> volume_flow(const MeshQuery& query, const Elements& e,
                                std::vector<Sphere> balls, const FlowOptions& options);

// n directions spread evenly over the unit sphere (a Fibonacci lattice).
std::vector<Eigen::Vector3d> fibonacci_directions(int n);

}  // namespace medspheres::detail
