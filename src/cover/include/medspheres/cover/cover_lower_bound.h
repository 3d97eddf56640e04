#pragma once
/// \file
/// A lower bound on how tight any K-ball cover of a surface can be: every set of at most K
/// balls whose union contains the surface of the solid has a ball protruding by at least
/// `bound` (protrusion of (c, r): r - D(c), D the signed distance to the surface, positive
/// inside; fit_metrics.h). So no covering method, bake_cover included, can reach a max
/// protrusion below it at that budget.
///
/// Method: the larger of two arguments. Pairs (derivation in cover_lower_bound.cpp): K + 1
/// surface points (the witnesses) are chosen so that every ball holding two of them
/// protrudes by at least `pair_bound`; K balls covering the surface hold all K + 1, so one
/// of them holds two. The protrusion of a ball holding two points is bounded below through
/// an upper bound on the depth D over a ball, taken from D on a grid of `resolution` cells
/// along L (the largest side of the box), and for the witnesses' worst pairs by branch and
/// bound on finer boxes. Counting (cover_count_bound.cpp): up to `count_witnesses` surface
/// points with integer weights; K covering balls hold the total weight, so one holds a
/// K-th of it, and every ball holding that much protrudes by at least `count_bound`
/// (branch and bound over the balls' centres). The weights are chosen where balls are dear,
/// and a last pass can weigh many evenly spread points alike (`count_even_witnesses`).
///
/// Assumptions: a closed mesh (solid_volume defined), its query built on the oriented mesh
/// (as FitEvaluator builds it); inside is the query's winding number > 1/2 and distances are
/// the query's, as for protrusions. The bound is a reported figure, rounding accounted for
/// by a slack of a few 1e-9 L, not a certificate. With winding_solid an open mesh is
/// accepted: the solid is then its winding solid, and the bound also assumes that the grid
/// resolves it (every inside point farther than cell_reach from the surface is within
/// cell_reach of an inside grid point or a neighbour of one) and, for the refinement, that
/// its boundary lies on the surface with holes capped; `closed` says which case ran. Frames
/// and units: those of the mesh. Determinism: the same result for every thread count. Errors:
/// budget 0 or options out of range throw std::invalid_argument naming them; an open mesh throws
/// InputError (kind kUnsupported, source "mesh").

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "medspheres/mesh/mesh_query.h"

namespace medspheres {

struct CoverLowerBoundOptions {
  /// Depth grid cells along L, in [4, 256]; finer: tighter, slower. Its inside points are
  /// also where the counting argument looks for cheap balls first. The defaults against
  /// resolution 48, 50,000 counting queries and 3 passes, on the G1's 33 links at cuRobo's
  /// counts: higher on 29 (the pelvis 5.26% of L against 4.00%, the elbows 4.2% against 3.5
  /// and 3.8%), lower by up to 1.1% on 2, for 6 times the CPU (653 s against 107 s in all);
  /// 256 was no tighter on the right elbow (its cheap balls sampled more sparsely).
  int resolution = 128;
  std::size_t candidates = 600;  ///< surface points the witnesses are chosen from, >= 2
  int starts = 4;              ///< greedy choices of witnesses, each from another first point, >= 1
  std::uint64_t seed = 1;      ///< the area-weighted surface samples behind the candidates
  int threads = 0;             ///< 0: all cores
  bool winding_solid = false;  ///< accept an open mesh (file comment); false: it throws
  /// Distance queries spent refining the witnesses' worst pairs beyond the grid (branch and
  /// bound); 0: none. More: tighter, slower, until the refinement's boxes reach 1e-4 L (on
  /// the G1's links 200,000 and 1,000,000 give the same bounds; 20,000 a lower one on 15 of
  /// 33, for 8% less CPU).
  std::size_t refine_queries = 200000;
  /// The counting argument (file comment): boxes of centres evaluated in each of its passes
  /// (branch and bound); 0: the pair argument alone. 50,000 stopped short on the G1's
  /// thick links (the right elbow at resolution 48: 3.48% of L, and 3.98% at 400,000 and
  /// at 2,000,000).
  std::size_t count_queries = 400000;
  /// Passes of the counting argument, >= 1: after each, the centres of its cheapest boxes
  /// join the balls its weights are chosen against, so every pass may prove more (a torus
  /// at K = 16: 0.037 after 3, 0.051 after 8).
  int count_passes = 8;
  /// Surface points the counting argument weighs, >= 2.
  std::size_t count_witnesses = 1024;
  /// Surface points (farthest-point spread) that weigh 1 each in the counting argument's last
  /// pass, 0 or >= 2; 0: no such pass. They measure the surface where chosen weights on
  /// fewer points leave cheap balls between them (a torus at K = 32).
  std::size_t count_even_witnesses = 0;
};

struct CoverLowerBound {
  double bound = 0.0;  ///< a length, >= 0: the least max protrusion of any K-ball cover is >= it
  /// K + 1 points on the surface (p_MoW_M): any ball holding two of them protrudes by >=
  /// pair_bound;
  /// empty (and bound 0) when the surface has fewer than K + 1 distinct sample points.
  std::vector<Eigen::Vector3d> witnesses;
  std::size_t grid_points = 0;    ///< depth grid points, and of them
  std::size_t inside_points = 0;  ///< those inside the solid
  double cell_reach = 0.0;        ///< the farthest any point of the box is from a grid point
  double pair_bound = 0.0;        ///< the pair argument's bound (witnesses above)
  double count_bound = 0.0;       ///< the counting argument's bound (0: not run or nothing)
  /// Its witnesses (points of the surface, p_MoW_M) and their weights (>= 1): every cover
  /// has a ball holding witnesses of total weight >= ceil(total / K), which protrudes by
  /// >= count_bound.
  std::vector<Eigen::Vector3d> count_points;
  std::vector<long> count_weights;
  bool closed = true;    ///< false: an open mesh's winding solid (winding_solid)
  double seconds = 0.0;  ///< the whole call
};

/// The bound of the file comment for \p budget balls on the solid of query.mesh().
/// \throws std::invalid_argument for budget 0 ("budget must be >= 1") or options out of range
///   (naming the option); InputError ("mesh: is not closed ...") for an open mesh unless
///   options.winding_solid.
CoverLowerBound cover_protrusion_lower_bound(const MeshQuery& query, std::size_t budget,
                                             const CoverLowerBoundOptions& options = {});

}  // namespace medspheres
