#pragma once
// Private to the covering bake (cover.cpp): its protrusion stage, which lowers the largest
// protrusion of the balls. Derivation in cover_protrusion.cpp.

#include <cstddef>
#include <optional>
#include <vector>

#include "cover_elements.h"
#include "cover_weights.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_set.h"

namespace medspheres::detail {

struct ProtrusionStage {
  Clustering clustering;  // over the elements
  int rounds = 0;         // minimax rounds run, over all moves
  // The other start's result, of no smaller P (for budgets up to kSpreadBudget; else none):
  // another local optimum, from which the volume stage may reach a smaller union.
  std::vector<Clustering> others;
};

// At most \p budget balls holding every element of \p e: the threshold start over the
// patches \p fine, then minimax rounds (at most \p rounds), then for budgets up to
// kMoveBudget split and exchange moves, each kept while the largest protrusion falls; for
// budgets up to kSpreadBudget the same from the spread start too, the lower P kept.
// \p volume: solid_volume(query.mesh()), computed once by the caller (on a mesh of 100k
// triangles each call costs about a tenth of the bake). With \p weights, every measure of
// the largest protrusion is weighted (cover_weights.h): the threshold start's costs, the
// rounds' and the moves' choices.
ProtrusionStage protrusion_stage(const MeshQuery& query, const Elements& e, const Elements& fine,
                                 std::size_t budget, int rounds,
                                 const std::optional<double>& volume, int threads,
                                 const BallWeights& weights = {}, int restarts = 0,
                                 int balance = 0);

// One ball: the minimum enclosing ball of the surface elements of \p e, moved inward.
Clustering one_ball(const MeshQuery& query, const Elements& e, int threads);

// Minimax rounds (at most \p rounds) from \p c: the protrusion stage's local step.
Clustering minimax_rounds(const MeshQuery& query, const Elements& e, Clustering c, int rounds,
                          int threads);

// The largest protrusion of the balls of radius > 0 (0 for none).
double largest_protrusion(const MeshQuery& query, const std::vector<Sphere>& balls, int threads);

}  // namespace medspheres::detail
