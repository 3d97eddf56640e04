#pragma once
/// \file
/// Medial sphere baking (Stolpner, Kry and Siddiqi, "Medial Spheres for Shape
/// Approximation", section 3): spheres centred near the medial surface of a solid,
/// each tangent to the boundary and inside the solid.
///
/// The method, with every choice the paper leaves open made explicit:
///
/// 1. Grid. A regular grid of cubic cells of size h = L / `resolution` (L the largest
///    side of the mesh's bounding box) covers the box, centred on it, with one cell
///    more than the box needs along each axis: `resolution` + 1 cells along the longest
///    side, so that grid vertices sit off the box's faces and mid-planes.
///    The sample points are the grid vertices. Each vertex is classified with the
///    generalized winding number (inside when > 0.5), and each inside vertex v gets its
///    exact nearest mesh point c(v) and the unit direction u(v) = (c(v) - v)/|c(v) - v|
///    toward it (the paper's gradient field, nabla D). A vertex exactly on the surface
///    has no direction and counts as outside.
/// 2. Cells where the medial surface likely passes. A cell is flagged when at least
///    two of its corners are inside and two inside corners have directions at least
///    `object_angle` apart. Points on the two sides of a medial sheet whose object
///    angle is alpha have directions alpha apart, so this finds the sheets the filter
///    in step 4 keeps, and skips the sheets of tiny object angle that every convex edge
///    of a polyhedron grows.
/// 3. Search. From every inside corner p of a flagged cell, along the segment
///    (p, p - gamma u(p)), i.e. away from p's nearest boundary point, binary search for
///    the first point whose direction differs from u(p) by at least `object_angle`.
///    Along that segment the nearest point stays put until the segment meets the
///    medial surface (the property of section 3, from Stolpner and Whitesides 2009),
///    so the search brackets a medial point; it stops when the bracket is shorter than
///    `medial_tolerance` (or after kMaxBisections halvings, which only a tolerance near
///    the rounding of the coordinates could need), and the candidate m is the bracket's
///    near end, whose nearest point A is exact and still on p's side of the sheet. The
///    segment length is gamma = sqrt(3) h / sin(object_angle / 2): a sheet of object angle at
///    least `object_angle` that passes through a cell is met within that distance by
///    the segment from any of the cell's corners.
///    A candidate is dropped unless (a) the distance grew along the segment as it must
///    before the first medial crossing, D(m) >= D(p) + t cos(object_angle) - tolerance,
///    (b) m is inside (winding number), and (c) its object angle, the angle at m between
///    its exact nearest point A and the far-side point B (the nearest point of the
///    bracket's far end), is at least `object_angle`.
/// 4. One point per cell. Each surviving candidate belongs to the cell that contains
///    it; a cell keeps its candidate of largest radius (ties: lowest grid vertex
///    index). This is what spreads the spheres evenly (paper, Fig. 1).
/// 5. Radius. r = D(m) - s, where D(m) is the distance from m to the mesh as computed
///    (the exact nearest point, rounded to doubles) and s = 1e-12 L + 4 eps (X + L),
///    with eps the double epsilon and X the largest |coordinate| of the bounding box.
///    s exceeds the rounding error of D, so |m - x| > r for every mesh point x: on a
///    closed mesh every sphere lies inside the solid. The derivation: the computed
///    nearest point is a + (v ab + w ac) for a triangle corner a; forming the offset
///    and the distance from the local vectors p - a, ab, ac, all shorter than about 2 L,
///    costs a few eps L (more on slivers, which the 1e-12 L = 4500 eps L term covers),
///    and adding a, whose coordinates reach X, then rounds each coordinate of the point
///    by up to eps X / 2, i.e. moves it by up to (sqrt(3) / 2) eps X and changes D by as
///    much. The 4 eps (X + L) term covers that more than four times over (X + L also
///    bounds the coordinates of the centres, which lie within a cell or two of the
///    box). For a mesh near the origin it is below 1e-15 L and changes nothing; for one
///    far from it (X = 1e6 L, say) the 1e-12 L term alone would not cover the rounding,
///    which is about 2e-10 L there.
///
/// Determinism: every step is a pure function of the mesh, the options and the grid
/// vertex or cell it works on, and results are gathered in index order, so the same
/// input gives a bit-identical sphere list whatever the thread count.
///
/// Open, non-manifold or self-intersecting meshes are baked against the solid their
/// winding number defines: every centre is inside that solid, and every sphere is
/// tangent to its nearest triangle and contains no point of any triangle.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_set.h"
#include "medspheres/mesh/threads.h"

namespace medspheres {

/// Progress of a long computation: stage name, units done, units in total.
using ProgressFn =
    std::function<void(const std::string& stage, std::size_t done, std::size_t total)>;

/// Limits of BakeOptions (validate_bake_options).
inline constexpr int kMinResolution = 2;
inline constexpr int kMaxResolution = 4096;
/// The smallest medial_tolerance accepted, as a fraction of L (the box's largest side).
/// Below a few eps L (about 1e-15 L) halving the bracket no longer moves the probe point
/// of a mesh near the origin (farther out, sooner): a smaller tolerance could never be
/// reached, and every search would run to kMaxBisections. 1e-9 L keeps well clear of
/// that up to coordinates of about 1e6 L, and is a million times finer than the default.
inline constexpr double kMinMedialTolerance = 1e-9;
/// The default medial_tolerance, as a fraction of L; it is also kept below half a cell.
inline constexpr double kDefaultMedialTolerance = 1e-3;
/// Halvings of a search bracket at most (step 3). With the tolerance at least
/// kMinMedialTolerance L the bracket is short enough after about 60; the cap only
/// guarantees termination.
inline constexpr int kMaxBisections = 128;
/// The resolution searches' default upper limit.
inline constexpr int kMaxSearchResolution = 512;
/// After its bisection, a resolution search also bakes this many resolutions beyond the
/// boundary it found (above it for a sphere budget, below it for an error target) and
/// moves to any that qualifies, repeating from there: sphere counts and errors are not
/// monotonic in the resolution.
inline constexpr int kResolutionSearchWindow = 4;

struct BakeOptions {
  /// h = L / resolution: resolution + 1 cells along the longest side; in [2, 4096]. 28
  /// gives a median of 428 spheres on the 23 closed classic test meshes (half of
  /// them 243 to 461), from 1 for a sphere and 88 for a torus to 838 for the bunny and
  /// 1129 for fandisk (flat faces grow many sheets).
  int resolution = 28;
  double object_angle = 0.6;  ///< rad, in (0, pi): keep medial points at least this open
  /// Length at which the medial search stops; 0 (the default) means
  /// min(1e-3 L, h / 2). Otherwise it must lie in [1e-9 L, h): a bracket as long as a
  /// cell no longer says which cell the medial point is in, and a tolerance that large
  /// also loosens checks (a) of step 3 by as much.
  double medial_tolerance = 0.0;
  int threads = 0;      ///< 0: all cores; at most kMaxThreads (threads.h)
  ProgressFn progress;  ///< optional; called from the calling thread only
};

/// The range [lo, hi) an explicit medial_tolerance must lie in for a mesh whose bounding
/// box has largest side \p longest, baked at \p resolution: lo = 1e-9 L, hi = L /
/// resolution, the cell size.
struct ToleranceRange {
  double lo = 0.0;
  double hi = 0.0;
};
ToleranceRange medial_tolerance_range(double longest, int resolution);

/// An option out of range: the BakeOptions field, by its name in the struct
/// ("object_angle"), and what is wrong with it ("must be in (0, pi) radians, got 4").
struct OptionProblem {
  std::string option;
  std::string problem;
};

/// The first of the options that do not depend on the mesh that is out of range, or none:
/// resolution in [2, 4096], object_angle in (0, pi), medial_tolerance finite and >= 0,
/// threads in [0, kMaxThreads]. The one source of these ranges (the CLI names its flags
/// after the fields).
std::optional<OptionProblem> bake_options_problem(const BakeOptions& options);

/// \throws std::invalid_argument "<option> <problem>" for bake_options_problem(options),
///   e.g. "resolution must be in [2, 4096], got 1".
void validate_bake_options(const BakeOptions& options);

/// What is wrong with an explicit medial_tolerance for a mesh whose bounding box has
/// largest side \p longest, baked at resolutions up to \p resolution (outside
/// medial_tolerance_range(longest, resolution): the range, L and the value), or none.
/// 0, the default, always fits.
std::optional<std::string> medial_tolerance_problem(double tolerance, double longest,
                                                    int resolution);

/// What one medial sphere was made from (kept beside each sphere).
struct MedialSample {
  Eigen::Vector3d near_point;  ///< A: the exact nearest mesh point of the centre
  Eigen::Vector3d far_point;   ///< B: the approximate second tangency point
  double object_angle = 0.0;   ///< angle AmB, rad
  int cell = -1;               ///< linear index of the grid cell that kept it
};

/// One resolution a search baked.
struct SearchStep {
  int resolution = 0;
  std::size_t spheres = 0;
  /// bake_target_error: the error of the set (1 for an empty set, which is not
  /// measured); NaN for bake_max_spheres.
  double error = 0.0;
};

struct BakeStats {
  int resolution = 0;
  double cell_size = 0.0;
  double medial_tolerance = 0.0;        ///< the value used (after the default is resolved)
  std::array<int, 3> grid = {0, 0, 0};  ///< cells per axis
  std::size_t inside_vertices = 0;
  std::size_t flagged_cells = 0;
  std::size_t searches = 0;          ///< segments searched
  std::size_t candidates = 0;        ///< searches that bracketed a medial point
  std::size_t rejected_angle = 0;    ///< candidates below the object angle
  std::size_t rejected_invalid = 0;  ///< candidates failing check (a) or (b)
  std::size_t spheres = 0;
  std::uint64_t closest_point_queries = 0;  ///< of this bake (the searches: the chosen one)
  std::uint64_t winding_queries = 0;
  double min_radius = 0.0;
  double max_radius = 0.0;
  double seconds = 0.0;  ///< this bake (the searches: the chosen resolution's bake alone)
  /// Wall-clock seconds of the whole call: equal to `seconds` for bake(); for the
  /// searches every bake and every error evaluation they ran.
  double total_seconds = 0.0;
  /// The resolution searches: every resolution baked, in the order baked (empty for bake()).
  std::vector<SearchStep> search;
};

struct BakeResult {
  SphereSet spheres;                  ///< the medial spheres, ordered by cell index
  std::vector<MedialSample> samples;  ///< one per sphere, same order
  BakeStats stats;
};

/// Bakes medial spheres of the solid bounded by query.mesh(). Reusing one MeshQuery
/// across bakes (as the resolution searches do) saves rebuilding the hierarchy. For an
/// open mesh build the query with MeshQueryOptions::cap_holes (FitEvaluator::query() and
/// bake(mesh) do): radii are distances as the query gives them, and without the caps a
/// ball near a hole reaches out through it.
/// \throws std::invalid_argument for options out of range (message names the option
///   and the allowed range), including an explicit medial_tolerance outside
///   medial_tolerance_range(L, resolution).
/// \throws InputError (source "mesh") when no grid vertex is inside the solid (a flat
///   sheet, or parts thinner than a cell), or when fewer than 70% of the grid vertices
///   inside have a winding number of at least 0.75: the winding number of a closed or
///   nearly closed surface is close to 1 inside, that of a triangle soup wanders.
/// A bake may find no sphere (a coarse grid whose cells no medial sheet crosses twice):
/// the result is then empty, not an error.
BakeResult bake(const MeshQuery& query, const BakeOptions& options = {});

/// Convenience: builds the MeshQuery and bakes. Same errors.
BakeResult bake(const TriangleMesh& mesh, const BakeOptions& options = {});

/// A resolution in [2, max_resolution] whose bake has 1 to \p max_spheres spheres, as
/// large as the search finds; the result returned is that bake, with stats.search and
/// stats.total_seconds describing the whole search.
///
/// The search: from options.resolution, doubling (while the count is within the budget)
/// or halving (while it is above) until the other side is reached, then bisection to two
/// adjacent resolutions r (count <= N) and r + 1 (count > N). A bake with no sphere (or no
/// grid vertex inside) counts as too coarse, i.e. on the side of r. Sphere counts grow
/// with resolution, but not monotonically (knot1: 84 spheres at 13, 112 at 14, 100 at
/// 15), so the search then bakes r + 1 .. r + kResolutionSearchWindow and moves up to the
/// largest of them with 1 to N spheres, repeating from there until a window has none. The
/// result is the largest resolution with 1 to N spheres seen this way: no resolution in
/// the window above it has 1 to N spheres, but this is not a proof over all resolutions.
/// Doubling stops early when it adds no sphere: the medial surface is then resolved (a
/// ball's single centre, say) and higher resolutions would only cost time. Every
/// explicit medial_tolerance must lie below the cell of max_resolution (L /
/// max_resolution), the finest the search may bake.
/// \throws std::invalid_argument if max_spheres < 1 or max_resolution is outside
///   [2, 4096], or for options as bake();
///   InputError (source "--max-spheres") when no resolution tried gives 1 to max_spheres
///   spheres (the message gives the fewest found, and where); InputError (source "mesh")
///   as bake() when no resolution tried has a grid vertex inside the solid, or when the
///   winding number is ambiguous.
BakeResult bake_max_spheres(const MeshQuery& query, std::size_t max_spheres,
                            const BakeOptions& options = {},
                            int max_resolution = kMaxSearchResolution);

/// Normalized volumetric error of a sphere set against the solid: supplied by the
/// caller so that this header stays free of the volume machinery. It is called only on
/// non-empty sets, once per resolution; an empty set's error is 1 (it misses the whole
/// volume) and never meets a target.
using ErrorFn = std::function<double(const SphereSet&)>;

/// Smallest resolution in [2, max_resolution] whose bake has error(spheres) <= target,
/// as found by a search mirroring bake_max_spheres: doubling or halving, bisection to
/// adjacent resolutions r - 1 (error > target) and r (error <= target), then the
/// kResolutionSearchWindow resolutions below r, moving down to the smallest of them that
/// meets the target and repeating (error falls with resolution, not strictly). The
/// result meets the target and no resolution in the window below it does.
/// Doubling stops early when it does not reduce the error. stats.search lists every
/// resolution baked with its error.
/// \throws std::invalid_argument if target <= 0 or no ErrorFn, or as bake_max_spheres;
///   InputError (source "--target-error") when no resolution tried up to max_resolution
///   meets the target (the message gives the best error found); InputError (source
///   "mesh") as bake_max_spheres.
BakeResult bake_target_error(const MeshQuery& query, double target, const ErrorFn& error,
                             const BakeOptions& options = {},
                             int max_resolution = kMaxSearchResolution);

}  // namespace medspheres
