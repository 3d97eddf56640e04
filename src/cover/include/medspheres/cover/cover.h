#pragma once
/// \file
/// Covering sphere sets to a budget: at most K balls whose union contains the whole
/// surface of the solid, certified by certify_cover (medspheres/mesh/cover_certificate.h),
/// and as tight as the method below makes them.
///
/// Method (derivation and choices in cover.cpp and the files it names):
/// 1. Elements. Every triangle is split by midpoint subdivision into elements no longer
///    than about L / (2 + 3 sqrt K) (at most 4^5 per triangle; coarser when that would make
///    more than max(2 triangles, 40000) elements: above K = 64 the finest size that fits,
///    which never grows with K); each element is the three corners of a
///    piece the certificate also tests. Points of a grid inside the solid (winding number >
///    1/2, interior_resolution cells along L) are added as one-point elements, so that the
///    balls also fill the interior and centres sit inside; their coverage is not certified.
/// 2. Protrusion stage: lowers the largest protrusion P. Start: candidate centres on a grid
///    inside the solid (about 2000), each with its depth D(c); a ball at c holds a patch
///    (the elements grouped, at most max(4000, 60 K) patches) at protrusion (distance from
///    c to the patch's farthest point) - D(c); a binary search finds the least threshold t
///    at which a greedy set cover picks at most K candidates holding every patch at
///    protrusion <= t. Then minimax rounds on the elements (at most `rounds`): each element
///    goes to the ball whose protrusion grows least to hold it, then each centre moves
///    (pattern search) to where its ball sticks out least. While fewer than K balls are left
///    (the candidates too coarse for a thin solid), the fill: the balls that protrude most,
///    as many as are missing, are split at once, then minimax rounds, kept while P does not
///    rise (else half as many splits; at most 6 tries; above K = 64, 6 + ceil(log2 K),
///    stopping at a kept try that neither lowers P nor adds a ball); above K = 64, the balls
///    still missing are then split in place (each part's ball started at its parent's centre and
///    moved only to stick out less, so P never rises). For K <= 64, split and exchange
///    moves follow: the ball that protrudes most is split in two (filling the budget, or in
///    exchange for the ball whose elements the others take at the least protrusion), then
///    two minimax rounds; each move kept while P falls (at most 6; 3 above K = 16). For
///    K <= 16 the same rounds and moves also run from K farthest-point centres on the
///    surface, and the result of lower P is kept. With protrusion_restarts, then that many
///    perturbed restarts from the best so far (its centres jittered, a ball exchanged for a
///    split of the worst, or the spread start from a random patch), each kept when P falls.
///    With balance_rounds, each run of minimax rounds ends with balancing rounds.
/// 3. Volume stage (volume_descent): all balls move and resize at once, by gradient steps,
///    down the union's volume plus penalties that keep the patches of step 2 held and each
///    protrusion within a cap; each element then goes to the ball that must grow least to
///    hold it, and balls shrink to what no other ball holds; when that leaves some ball at
///    most 10% beyond the cap, one minimax round of step 2 follows from those centres. The
///    penalties aim at the cap without certainty: while some ball protrudes beyond it, the
///    stage runs at most twice more from the same start, its aim lowered by the first
///    overshoot (aim = cap (cap / overshoot)^n). For K <= 8 it runs at three caps,
///    (1 + a/4) P, (1 + a/2) P and (1 + a) P (a = protrusion_allowance, P step 2's largest
///    protrusion), from each of step 2's two starts; above, once at (1 + a) P from step 2's
///    result. Each result whose balls all keep to its cap is a candidate.
/// 4. Of the candidates (steps 2 and 3, and the single ball: the minimum enclosing ball of
///    the surface, moved inward to stick out least) whose union is no larger than the
///    single ball's, or whose largest protrusion is at most half the single ball's, the one
///    of least product of the volume outside the solid (U - V; on an open mesh V is the
///    interior points' cells) and the largest protrusion is kept (ties: in that order). In
///    it, the elements that bind a ball's radius are split (at most 3 times, and no deeper
///    than the certificate's max_depth) and handed to the balls that hold their pieces.
///    For K <= 32, then the volume polish (volume_polish, with volume_descent): one ball at
///    a time, its centre moves by a pattern search (steps along the axes and diagonals,
///    halved down to 1e-3 of its radius), its radius what its elements need there, while the
///    exact volume of the union falls and the ball protrudes no farther than the largest
///    protrusion before the polish; then balls shrink to what no other ball holds; at most
///    3 sweeps. It is kept when neither the largest protrusion nor the union rose.
///    For K <= 8 (volume_choice, with volume_polish): the polish runs before the choice, on
///    the candidate of least (U - V) P and on the three of least (U - V) P^0.75, each
///    refined first; of those whose (U - V) P after it is still at most the least before
///    it and whose union is at most that of the first polished, the one of least
///    (U - V) P^0.75 is kept (the volume counts more than the
///    protrusion: the largest protrusion may be higher than the choice above would keep).
/// 5. Radii get a slack of 1e-9 L plus rounding; the certificate runs; any piece it cannot
///    certify is repaired by growing the ball that needs the least growth to hold it,
///    until certified (at most `repair_rounds`). A set that still fails is reported
///    uncertified, never covered.
/// K = 1 is the single ball of step 4 (for a symmetric solid, the bounding sphere).
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

#include "medspheres/cover/protrusion_weights.h"
#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_set.h"

namespace medspheres {

/// What a caller trades and spends in the cover's search (CoverOptions): the protrusion
/// given up for volume, and time for a lower protrusion. The defaults are the bake's; a bake
/// run once for a planner may spend more (docs/covers.md, "Tighter covers for a longer
/// bake": balance_rounds 40, protrusion_allowance 0 and protrusion_restarts 48 take P to a
/// median 0.85 of the default's on the G1's links, at 11 to 14 times the CPU).
struct CoverSearch {
  /// Step 3 may raise the largest protrusion by this fraction of step 2's to lower the
  /// union's volume (finite, >= 0; 0: step 3 never protrudes beyond step 2). Step 4 keeps
  /// a result that uses it only when the product of its volume outside the solid and its
  /// protrusion is least.
  double protrusion_allowance = 0.25;
  /// Step 2's perturbed restarts (>= 0; 0: none), a search for lower P at the cost of
  /// time: each costs about one more run of step 2's rounds and moves (0.007 to 0.21 CPU s
  /// on the G1's links at K = 2 to 30). Deterministic (a fixed seed). Step 3's caps follow
  /// step 2's P, so with the allowance the cover's P need not fall with it.
  int protrusion_restarts = 0;
  /// Step 2's balancing rounds at most after each run of minimax rounds (>= 0; 0: none).
  /// A round gives each element to the ball whose protrusion, less an offset per ball, is
  /// least to hold it; the offsets grow for balls below the mean protrusion and shrink for
  /// those above, so the ball that sticks out most cedes elements to its neighbours. They
  /// stop after 4 rounds in a row that lower P by less than 0.5%. At 40 (docs/covers.md,
  /// "Balancing rounds"): P a median 0.95 times that without on the G1's links and 0.94 on
  /// the classic meshes at K = 16 and 32, at 1.2 to 1.3 times the CPU.
  int balance_rounds = 0;
};

/// An out-of-range field of a CoverSearch: its name, its value as text, and what it must be
/// ("must be >= 0, got -1"); message() joins name and problem.
struct CoverSearchProblem {
  std::string field, value, problem;
  std::string message() const { return field + " " + problem; }
};
/// The first out-of-range field of \p search; none when every field is in range.
std::optional<CoverSearchProblem> cover_search_problem(const CoverSearch& search);

struct CoverOptions : CoverSearch {
  int rounds = 8;                       ///< step 2 minimax rounds at most, >= 1
  int interior_resolution = 12;         ///< step 1 interior grid: cells along L; 0: none
  int repair_rounds = 8;                ///< step 5 certify-and-grow rounds at most, >= 1
  CoverCertificateOptions certificate;  ///< max_depth must be >= 5 (the element depth)
  int threads = 0;                      ///< 0: all cores
  bool volume_descent = true;           ///< step 3, the volume stage
  bool volume_polish = true;            ///< step 4's polish (bake_cover, with volume_descent)
  /// Step 4's choice among polished candidates (bake_cover, K <= 8, with volume_polish)
  bool volume_choice = true;
  /// bake_cover only: where the balls should stick out less (protrusion_weights.h). When
  /// active, step 2 lowers the largest weighted protrusion and its result is the candidate
  /// kept (step 3 and step 4's choice, which weigh every ball alike, are skipped); step 4's
  /// refinement and 5 run as always. tighten_cover ignores it.
  ProtrusionWeights weights;
};

struct CoverStats {
  std::size_t budget = 0;
  std::size_t spheres = 0;
  std::size_t elements = 0;         ///< surface elements of step 1
  std::size_t interior_points = 0;  ///< interior grid points of step 1
  std::size_t patches = 0;          ///< surface patches of step 2
  int rounds_run = 0;               ///< minimax rounds of step 2
  std::size_t stage_spheres = 0;    ///< balls after step 2 (steps 3 and 4 may drop some)
  std::size_t repaired = 0;         ///< balls grown by step 5, counted per growth
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
  CoverSearch search;  ///< the settings the search ran with (CoverOptions)
};

/// At most \p budget balls covering the surface of query.mesh() (file comment).
/// \throws std::invalid_argument for budget 0 or options out of range.
CoverResult bake_cover(const MeshQuery& query, std::size_t budget,
                       const CoverOptions& options = {});

/// A cover made from the caller's own balls (a planner's hand-made or fitted set, which
/// need not cover): every surface element of step 1 (no interior points) goes to the ball
/// that must grow least to hold it, each ball becomes just large enough for its elements
/// (so it grows where the set left the surface uncovered and shrinks where it was loose),
/// then balls shrink to what no other ball holds; then the volume stage of step 3 with the
/// largest protrusion the set had after the first step as its cap, kept only when the
/// union falls and no ball sticks out beyond that cap; then the split of binding elements
/// of step 4 and step 5. At most start.size() balls; their order and layout follow \p start
/// (empty balls are dropped). Before step 5 the union is never larger than after the first
/// step, and when \p start already holds every element its union and largest protrusion do
/// not grow (up to step 5's slack). stats.budget and stats.start_spheres are start.size();
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
