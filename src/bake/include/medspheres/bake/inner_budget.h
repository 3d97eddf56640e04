#pragma once
/// \file
/// The inner set to a sphere budget: K medial spheres, each inside the solid, chosen to
/// cover as much of its volume as the candidates allow.
///
/// Method. Medial spheres are baked (bake.h) at growing resolutions until the bakes together
/// have found about `candidate_factor` times K spheres: the candidates, every one inside the
/// solid as bake() guarantees. K of them are then chosen to maximise the volume of their
/// union, measured on weighted sample points: one jittered point per cell of a grid fine
/// enough for about `samples` points in the solid, kept where some candidate covers it, and
/// thinned (with weights that keep the estimate unbiased) deep inside many candidates.
/// Greedy selection by the weight of the points a sphere adds (ties: the lower candidate
/// index), then passes of single swaps (drop one chosen sphere, add the unchosen one that
/// gains the most, when that covers strictly more) until a pass changes nothing or
/// `swap_passes` passes ran. When no candidate adds a point, the remaining picks go by
/// radius, largest first (ties: lower index).
///
/// Contract. The result has exactly min(K, candidates) spheres, a subset of the candidates,
/// so every sphere lies inside the solid exactly as bake()'s do. The spheres are in
/// candidate order (by bake, then by cell), each with its MedialSample, whose `cell` is in
/// the grid of the bake that found it. Every step is a pure function of the mesh and the
/// options and runs in index order (the parallel loops gather their results by index), so
/// the output is bit-identical for every thread count. The volume maximised is a proxy; the
/// exact nerr of the result is FitEvaluator::volume_error (fit_metrics.h).
///
/// Stats. stats describes the last (finest) candidate bake (resolution, grid, queries),
/// except stats.spheres and the radii, which describe the chosen set; stats.search lists
/// every candidate bake in order (spheres: what it found) and stats.total_seconds the call.

#include <cstddef>

#include "medspheres/bake/bake.h"
#include "medspheres/mesh/mesh_query.h"

namespace medspheres {

struct InnerBudgetOptions {
  /// Bake candidates until there are at least this many times the budget (>= 1); more
  /// gives the selection more choice and costs finer bakes.
  double candidate_factor = 3.0;
  /// Sample points in the solid for the volume proxy: 0 (the default) for 512 K, at least
  /// 2^15 and at most 2^18; otherwise at least 1000.
  std::size_t samples = 0;
  int swap_passes = 8;  ///< passes of the swap improvement (0: greedy only)
  /// The finest resolution baked for candidates, in [2, 4096].
  int max_resolution = kMaxSearchResolution;
};

/// K = \p max_spheres medial spheres of the solid bounded by query.mesh(), chosen as the
/// file comment says. The candidate bakes start at options.resolution and grow the
/// resolution, each step aimed at the candidates still missing (1.1 times the square root of
/// missing / last bake's count, as sphere counts grow with the area of the medial surface;
/// between 1.25 and 2 times; doubling after a bake that finds none), until there are
/// enough, a step of at least 1.5 times finds some spheres but no more than the bake before
/// it (the medial surface is resolved: a ball's centre), or budget.max_resolution is
/// reached. A start resolution with no grid vertex inside the solid is doubled, at most 3
/// times. For an open mesh build the query with MeshQueryOptions::cap_holes, as for bake().
/// \throws std::invalid_argument if max_spheres < 1, for options as bake() (an explicit
///   medial_tolerance must lie below the cell of budget.max_resolution), or for budget
///   fields out of range (the message names the field);
///   InputError (source "mesh") as bake(); InputError (source "--max-spheres") when no
///   candidate bake finds a sphere.
BakeResult bake_inner_budget(const MeshQuery& query, std::size_t max_spheres,
                             const BakeOptions& options = {},
                             const InnerBudgetOptions& budget = {});

}  // namespace medspheres
