#pragma once
/// \file
/// Covering sphere sets to a budget: at most K balls whose union contains the whole
/// surface of the solid, certified by certify_cover (medspheres/mesh/cover_certificate.h),
/// and as tight as the method below makes them.
///
/// Method (derivation and choices in cover.cpp):
/// 1. Constraint points. Every triangle is split by midpoint subdivision into elements no
///    longer than about L / (2 + 3 sqrt K) (at most 4^5 per triangle; coarser when that
///    would make more than max(2 triangles, 40000) elements); each element is
///    the three corners of a piece the certificate also tests. Points of a grid inside the
///    solid (winding number > 1/2) are added as one-point elements, so that the balls also
///    fill the interior and centres sit inside; their coverage is not certified.
/// 1b. Patches: the elements grouped by the cell of a grid (half the element size, coarser
///    until there are at most max(1500, 60 K) groups) that holds their centroid; each group
///    is one patch, a ball holding its points. Steps 2 to 4 run on the patches. A finer
///    grouping (at most max(4000, 60 K) groups) serves step 4c.
/// 2. Starts: the first is one ball (then refilled to K as in step 4, so that one ball is
///    kept where it is the tightest cover); the others are K centres by farthest-point
///    sampling of the patch centres from one drawn with `seed`. Steps 3 to 4b run from
///    each start.
/// 3. Lloyd-like rounds: each element goes to the centre whose distance to the element's
///    farthest point is least; each ball becomes the minimum enclosing ball of its
///    elements' points. The round of smallest exact union volume is kept. Then each
///    centre moves (pattern search) to where the ball holding its elements sticks out of
///    the solid least.
/// 4. Shrink: a ball drops the elements some other ball already holds, and is refitted to
///    the rest; repeated while it shrinks a ball. Coverage of every element is kept. When
///    balls were dropped, steps 3 and 4 run again from the survivors plus farthest-point
///    seeds up to K (once), kept when the union is smaller.
/// 4b. Each start's result is carried over to the elements (each element to its patch's
///    ball), each ball refitted as the minimum enclosing ball of its elements' points, and
///    the inward moves of step 3 and the shrink of step 4 run again on the elements.
/// 4c. Minimax start, on the largest protrusion. Candidate centres: points of a grid inside
///    the solid (about 2000) and the centres of every start's balls, each with its depth
///    D(c) (distance to the surface). A ball at c holds a fine patch with protrusion
///    (distance from c to the patch's farthest point) - D(c); a binary search finds the
///    least threshold t at which a greedy set cover picks at most K candidates holding
///    every fine patch with protrusion <= t. From those centres, minimax rounds on the
///    elements: each element goes to the ball whose protrusion grows least to hold it
///    (for fixed centres, the assignment of least largest protrusion), then the inward
///    moves of step 3; at most 8 rounds, while the largest protrusion falls; then the
///    shrink of step 4.
/// 4d. The winner, among every start's result and the minimax start's: the least product
///    of the volume outside the solid (U - V; U on an open mesh) and the largest
///    protrusion, so that neither is traded for a small gain in the other; a result whose
///    union is larger than that of start 0's single ball (moved inward) is not eligible.
/// 4e runs only for K <= 16, where each ball matters most and it costs least; 4f runs at
///    every K, with at most 3 rounds above 16.
/// 4e. Local search on the winner, at most 3 moves: the ball that protrudes most is split
///    in two (each half its minimum enclosing ball), filling the budget while balls are
///    missing, else in exchange for the ball whose elements the others take at the least
///    protrusion; then two minimax rounds (4c). A move is kept when it lowers the product
///    of 4d (and keeps the union within the single ball's); the first that does not ends
///    the search.
/// 4f. Union-volume descent on the winner: with each ball's elements fixed (its radius the
///    distance to its farthest point), each centre in turn moves against the gradient of
///    the union's volume (estimated on points of its sphere), by a step halved until the
///    exact union volume falls; then the shrink of step 4; at most 12 rounds (3 for
///    K > 16), while the union falls by 3e-4 of itself. One run where no ball may stick
///    out beyond the winner's largest protrusion and, for K <= 4, a free one; the one of
///    least product (4d) is kept when it is below the winner's.
/// 5. Radii get a slack of 1e-9 L plus rounding; the certificate runs; any piece it cannot
///    certify is repaired by growing the ball that needs the least growth to hold it,
///    until certified (at most `repair_rounds`). A set that still fails is reported
///    uncertified, never covered.
/// K = 1 is the minimum enclosing ball of the surface (the bounding sphere).
///
/// What is certified: the surface. The interior is covered at the sample points of step 1
/// only. excess_volume = (vol(union) - V) / V is the exact volume of the union outside the
/// solid, relative to V, when the union contains the solid, and a lower bound otherwise.
/// max_protrusion: the largest r_i - signed distance of c_i to the surface (fit_metrics.h),
/// the farthest a point of the union is from the solid.
///
/// Frames and units: those of the mesh. Determinism: the same spheres for the same input
/// and options, whatever the thread count.
/// Errors: budget 0 or options out of range throw std::invalid_argument naming the
/// option.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_set.h"

namespace medspheres {

struct CoverOptions {
  int starts = 2;          ///< steps 2 to 4b from this many first centres, >= 1 (then step 4c)
  std::uint64_t seed = 1;  ///< draws the first centre of every start but the first
  int rounds = 24;         ///< step 3 rounds at most (step 4c: min(8, rounds)), >= 1
  int interior_resolution = 12;         ///< step 1 interior grid: cells along L; 0: none
  int repair_rounds = 8;                ///< step 5 certify-and-grow rounds at most, >= 1
  CoverCertificateOptions certificate;  ///< max_depth must be >= 5 (the element depth)
  int threads = 0;                      ///< 0: all cores
  bool volume_descent = true;           ///< step 4f (K <= 16)
};

struct CoverStats {
  std::size_t budget = 0;
  std::size_t spheres = 0;
  std::size_t elements = 0;         ///< surface elements of step 1
  std::size_t interior_points = 0;  ///< interior grid points of step 1
  std::size_t patches = 0;          ///< surface patches of step 1b
  int rounds_run = 0;               ///< step 3
  int best_round = 0;
  std::size_t repaired = 0;  ///< balls grown by step 5, counted per growth
  int repair_rounds_run = 0;
  std::size_t start_spheres = 0;      ///< tighten_cover: the balls it started from; 0: bake_cover
  bool certified = false;             ///< the certificate's verdict on the result
  std::optional<double> mesh_volume;  ///< V, when the mesh is closed
  double union_volume = 0.0;          ///< exact
  double excess_volume = 0.0;         ///< (U - V) / V; NaN without V
  double max_protrusion = 0.0;        ///< a length
  double largest_side = 0.0;          ///< L
  double seconds = 0.0;               ///< the whole call
};

struct CoverResult {
  SphereSet spheres;
  CoverCertificate certificate;  ///< of the returned spheres
  CoverStats stats;
};

/// At most \p budget balls covering the surface of query.mesh() (file comment).
/// \throws std::invalid_argument for budget 0 or options out of range.
CoverResult bake_cover(const MeshQuery& query, std::size_t budget,
                       const CoverOptions& options = {});

/// A cover made from the caller's own balls (a planner's hand-made or fitted set, which
/// need not cover): every surface element of step 1 (no interior points) goes to the ball
/// that must grow least to hold it, each ball becomes just large enough for its elements
/// (so it grows where the set left the surface uncovered and shrinks where it was loose),
/// then the shrink of step 4 and the descent of step 4f (at most 40 rounds), no ball
/// sticking out beyond the largest protrusion the set had after the first step; then step
/// 5. At most start.size() balls; their order and layout follow \p start (empty balls are
/// dropped). Before step 5 the union is never larger than after the first step, and when
/// \p start already holds every element its union and largest protrusion do not grow (up
/// to step 5's slack). stats.budget and stats.start_spheres are start.size();
/// stats.interior_points is 0.
/// \throws std::invalid_argument for an empty \p start, a sphere with a non-finite centre
///   or a radius that is not >= 0 (naming its index), or options out of range.
CoverResult tighten_cover(const MeshQuery& query, const std::vector<Sphere>& start,
                          const CoverOptions& options = {});

/// What tighten_cover refuses in \p start ("no spheres", "sphere 3 has a non-finite centre
/// or a radius that is not >= 0"), or empty when it accepts it.
std::string cover_start_problem(const std::vector<Sphere>& start);

/// The repair step: for each piece of \p cert (its uncertified_pieces), the ball whose
/// radius must grow least to hold the piece's three corners (ties: lowest index) grows to
/// that reach plus \p slack and a rounding allowance of 64 eps of the reach. Returns the
/// growths.
std::size_t grow_to_hold(std::vector<Sphere>& balls, const CoverCertificate& cert, double slack);

/// The margin added to a covering ball's radius: 1e-9 \p L (the solid's largest side) plus
/// 64 eps of \p coordinates (the largest coordinate magnitude involved).
double cover_radius_slack(double L, double coordinates);

}  // namespace medspheres
