#pragma once
// Private to the cover lower bound (cover_lower_bound.cpp): the counting argument, a bound
// on the least max protrusion of any K-ball cover from many weighted surface witnesses (far
// more than the pair argument's K + 1). Derivation in cover_count_bound.cpp.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "medspheres/mesh/mesh_query.h"

namespace medspheres::detail {

// The hierarchical winding number \p w at p, or the direct sum when w is more than 0.1 from
// an integer (the inside test of cover_lower_bound.cpp, step 6).
double settled_winding(const MeshQuery& query, const Eigen::Vector3d& p, double w);

struct CountBound {
  double bound = 0.0;                   // a length >= 0 (0 when nothing was proven)
  std::vector<Eigen::Vector3d> points;  // the witnesses of the bound, of positive weight
  std::vector<long> weights;            // their weights; some ball holds ceil(Y / K) of Y
  std::size_t queries = 0;              // boxes evaluated
};

// Where the weights first look for cheap balls: centres c with their depth D(c) (the depth
// grid's counted centres).
struct DepthSamples {
  const std::vector<Eigen::Vector3d>* points = nullptr;
  const std::vector<double>* depth = nullptr;
};

// The counting bound for \p budget balls: weights on the points of \p pool (points of the
// surface, spread first: farthest-point order) are chosen starting from \p cheap
// (heuristic: no part of the proof), then inf_c (d_y(c) - D(c)) is bounded from below by
// branch and bound over the mesh's box with at most \p queries boxes in each of \p passes
// passes; the largest bound of the passes, lowered by \p slack, is returned with its weights. \p
// pairs (points of the surface, may be empty: the pair argument's witnesses) join the best weights
// in one more pass. \p even (points of the surface, may be empty) weigh 1 each in a last pass.
// \p closed: the mesh is closed (else its winding solid, with the assumption of
// cover_lower_bound.h). Deterministic for every thread count.
CountBound count_lower_bound(const MeshQuery& query, bool closed, std::size_t budget,
                             const std::vector<Eigen::Vector3d>& pool, const DepthSamples& cheap,
                             const std::vector<Eigen::Vector3d>& pairs,
                             const std::vector<Eigen::Vector3d>& even, double slack,
                             std::size_t queries, int passes, int threads);

}  // namespace medspheres::detail
