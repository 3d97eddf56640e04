#pragma once
/// \file
/// Medial sphere baking (Stolpner, Kry and Siddiqi, "Medial Spheres for Shape
/// Approximation", section 3): spheres centred near the medial surface of the solid bounded
/// by a mesh, each tangent to the boundary and inside the solid.
///
/// Frame and units: the mesh's; L is the largest side of its bounding box. A grid of cubic
/// cells of size h = L / resolution samples the solid, and each cell keeps at most one
/// sphere (its candidate of largest radius; ties: lowest grid vertex).
/// Containment: radii are shrunk by s = 1e-12 L + 4 eps (X + L), X the largest |coordinate|
/// of the box, which exceeds the rounding of the distance: on a closed mesh every sphere
/// lies inside the solid. Open, non-manifold or self-intersecting meshes are baked against
/// the solid their winding number defines.
/// Determinism: the same input gives a bit-identical sphere list for every thread count.
/// The method, step by step, and the derivation of s are in bake.cpp.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/error.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_set.h"
#include "medspheres/threads.h"

namespace medspheres {

/// Progress of a long computation: stage name, units done, units in total.
using ProgressFn =
    std::function<void(const std::string& stage, std::size_t done, std::size_t total)>;

/// Limits of BakeOptions (validate_bake_options).
inline constexpr int kMinResolution = 2;
inline constexpr int kMaxResolution = 4096;
/// The smallest medial_tolerance accepted, as a fraction of L (why: bake.cpp).
inline constexpr double kMinMedialTolerance = 1e-9;
/// The default medial_tolerance, as a fraction of L; it is also kept below half a cell.
inline constexpr double kDefaultMedialTolerance = 1e-3;
/// Halvings of a search bracket at most: a cap that only guarantees termination.
inline constexpr int kMaxBisections = 128;
/// The resolution searches' default upper limit.
inline constexpr int kMaxSearchResolution = 512;
/// After its bisection, a resolution search also bakes this many resolutions beyond the
/// boundary it found (above it for a sphere budget, below it for an error target) and
/// moves to any that qualifies, repeating from there: sphere counts and errors are not
/// monotonic in the resolution.
inline constexpr int kResolutionSearchWindow = 4;

struct BakeOptions {
  /// h = L / resolution: resolution + 1 cells along the longest side; in [2, 4096].
  int resolution = 28;
  double object_angle = 0.6;  ///< rad, in (0, pi): keep medial points at least this open
  /// Length at which the medial search stops; 0 (the default) means min(1e-3 L, h / 2);
  /// otherwise in [1e-9 L, h) (medial_tolerance_range).
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

/// The first option that does not depend on the mesh that is out of range, as the
/// InputError (kOutOfRange, field named as in BakeOptions: "object_angle") that a caller
/// may throw, or none: resolution in [2, 4096], object_angle in (0, pi), medial_tolerance
/// finite and >= 0, threads in [0, kMaxThreads].
std::optional<InputError> bake_options_problem(const BakeOptions& options);

/// \throws std::invalid_argument "<field> <problem>" for bake_options_problem(options),
///   e.g. "resolution must be in [2, 4096], got 1".
void validate_bake_options(const BakeOptions& options);

/// An explicit medial_tolerance outside medial_tolerance_range(longest, resolution), for
/// a mesh whose box has largest side \p longest baked at resolutions up to \p resolution,
/// as an InputError (kOutOfRange, field "medial_tolerance"), or none. 0 always fits.
std::optional<InputError> medial_tolerance_problem(double tolerance, double longest,
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
/// \throws InputError (kNoInterior, file "mesh") when no grid vertex is inside the solid
///   (a flat sheet, parts thinner than a cell), or when fewer than 70% of the inside grid
///   vertices have a winding number of at least 0.75 (a triangle soup).
/// A bake may find no sphere (a coarse grid whose cells no medial sheet crosses twice):
/// the result is then empty, not an error.
BakeResult bake(const MeshQuery& query, const BakeOptions& options = {});

/// Convenience: builds the MeshQuery and bakes. Same errors.
BakeResult bake(const TriangleMesh& mesh, const BakeOptions& options = {});

/// A resolution in [2, max_resolution] whose bake has 1 to \p max_spheres spheres, as
/// large as the search finds (doubling or halving, bisection, then windows of
/// kResolutionSearchWindow resolutions above: counts are not monotonic, so this is the
/// largest seen, not a proof over all resolutions); the result is that bake, with
/// stats.search and stats.total_seconds describing the whole search. An explicit
/// medial_tolerance must lie below the cell of max_resolution.
/// \throws std::invalid_argument if max_spheres < 1, max_resolution is outside [2, 4096],
///   or for options as bake(); InputError (kUnreachable, field "max_spheres") when no
///   resolution tried gives 1 to max_spheres spheres (the message gives the fewest
///   found); InputError (kNoInterior, "mesh") as bake() when none has an inside vertex.
BakeResult bake_max_spheres(const MeshQuery& query, std::size_t max_spheres,
                            const BakeOptions& options = {},
                            int max_resolution = kMaxSearchResolution);

/// Normalized volumetric error of a sphere set against the solid: supplied by the
/// caller so that this header stays free of the volume machinery. It is called only on
/// non-empty sets, once per resolution; an empty set's error is 1 (it misses the whole
/// volume) and never meets a target.
using ErrorFn = std::function<double(const SphereSet&)>;

/// Smallest resolution in [2, max_resolution] whose bake has error(spheres) <= target,
/// by the search of bake_max_spheres mirrored (windows below); stats.search lists every
/// resolution baked with its error.
/// \throws std::invalid_argument if target <= 0 or no ErrorFn, or as bake_max_spheres;
///   InputError (kUnreachable, field "target_error") when no resolution tried meets the
///   target (the message gives the best error found); InputError (kNoInterior, "mesh") as
///   bake_max_spheres.
BakeResult bake_target_error(const MeshQuery& query, double target, const ErrorFn& error,
                             const BakeOptions& options = {},
                             int max_resolution = kMaxSearchResolution);

}  // namespace medspheres
