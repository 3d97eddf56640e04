#pragma once
/// \file
/// Baking a whole robot: every link's solid (link_solid.h) through the bake pipeline
/// (bake_pipeline.h), to a budget per link, links in parallel, spheres in link frames.
///
/// Each link gets an inner set (RobotModel's LinkSpheres::inner): the request's bake of
/// its meshed parts, plus its sphere primitives exactly. The outer (covering) set has its
/// slot beside it and is left empty by the medial method.
///
/// What is baked. A link with one meshed part is baked in that part's frame G (its mesh
/// with the scale applied), and the spheres are then moved to the link frame by X_LG; so
/// links whose one part is the same geometry (same file bytes and scale, or the same
/// primitive), wherever their origins put it, with the same budget are baked once. A link
/// with several meshed parts is baked as their union placed in the link frame (the
/// concatenated meshes; the winding-number solid is the union). Moving a sphere by X_LG
/// rounds its centre: each radius is shrunk by 16 eps (3 |c| + |t| + r) (c the centre in
/// G, t the translation of X_LG), which covers that rounding and the non-orthogonality of
/// the rotation as computed, so a sphere inside the part in G is inside the placed part.
///
/// Budgets. The budget of a link counts its sphere primitives; what its bake may make is
/// the rest, at least 1. --budget N is shared out by surface area (RobotBudget::total).
///
/// Determinism. Every link's spheres are a pure function of its solid and its request,
/// and results are gathered in link order: the same robot and options give bit-identical
/// spheres for every `jobs` (only timings differ). With request.record_seconds false the
/// model's metadata holds no times either, so it is bit-identical too.

#include <cstddef>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/mesh/filled_solid.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_model.h"

namespace medspheres {

/// The budget per link `medspheres robot` uses when it is given no budget, error target or
/// resolution: a planner's size (cuRobo's own configuration of the Unitree G1 has 674
/// spheres for its 40 links), not the hundreds per link a default-resolution bake makes.
inline constexpr std::size_t kDefaultSpheresPerLink = 32;

/// How many spheres each link may have (its sphere primitives included).
struct RobotBudget {
  /// Every link with meshed parts gets this many.
  std::optional<std::size_t> per_link;
  /// The whole robot: N minus the links fixed by `links` and minus the sphere primitives
  /// of the other links is shared among the other links with meshed parts, each getting
  /// at least 1 and the rest in proportion to the surface area of its meshed parts
  /// (largest remainders; ties to the earlier link). Exclusive with per_link.
  std::optional<std::size_t> total;
  /// Per link overrides (link name -> K), on top of either.
  std::map<std::string, std::size_t> links;
};

/// What each link's bake may make: the budget minus the link's sphere primitives, at
/// least 1; std::nullopt where no budget applies (the request's own max_spheres then
/// holds) and for links without meshed parts.
/// \throws InputError naming \p source and the option: a --link name that is no link of
///   the robot or a link without meshed parts, a budget of 0, per_link with total, a total
///   smaller than what the fixed links take plus one sphere per other baked link.
std::vector<std::optional<std::size_t>> link_bake_budgets(const std::vector<LinkSolid>& solids,
                                                          const RobotBudget& budget,
                                                          const std::string& source);

/// One link's row of the progress lines and of the summary.
struct LinkBakeStats {
  std::string link;
  std::size_t parts = 0;              ///< meshed parts
  std::size_t primitive_spheres = 0;  ///< sphere primitives, kept exactly
  std::size_t triangles = 0;          ///< of the meshed parts
  std::optional<std::size_t> budget;  ///< what its bake was allowed (link_bake_budgets)
  std::size_t spheres = 0;            ///< of the inner set, primitives included
  std::size_t outer_spheres = 0;      ///< of the outer set, primitives included
  bool outer_certified = false;       ///< the outer set's surface coverage is certified
  double outer_protrusion = std::numeric_limits<double>::quiet_NaN();  ///< of the cover
  /// nerr of the baked part (NaN when not measured or not defined), and its kind.
  double nerr = std::numeric_limits<double>::quiet_NaN();
  std::string nerr_kind;
  double seconds = 0.0;         ///< its bake (0 for a reused one)
  double outer_seconds = 0.0;   ///< of seconds, the outer set's bake
  std::size_t outer_start = 0;  ///< the spheres its outer set started from (0: baked)
  std::string baked_as;         ///< the link whose bake it reuses; empty for its own
  std::string note;             ///< "no collision geometry" and the like
  /// Its inner set was baked on its filled solid (RobotBakeOptions::fill_thin_shells); the
  /// robot's metadata then records "inner_solid": "filled" for the link.
  bool inner_filled = false;
  /// Its outer set was baked on its filled solid (RobotBakeOptions::fill_thin_shell_covers);
  /// the robot's metadata then records "cover_solid": "filled" for the link.
  bool outer_filled = false;
};

/// Called once per link as its spheres are ready (in completion order, one call at a
/// time, from any thread).
using LinkProgressFn = std::function<void(const LinkBakeStats&)>;

struct RobotBakeOptions {
  /// Every link's request. Its max_spheres is replaced per link where a budget applies;
  /// medial.threads is split among the jobs; medial.progress is not used.
  BakeRequest request;
  RobotBudget budget;
  /// Bakes at once, 1 to kMaxThreads, or 0 for as many as thread_count(0).
  int jobs = 1;
  LinkProgressFn progress;
  /// Also bake each link's outer set: a certified cover (BakeMethod::kCover) to the same
  /// budget (kDefaultSpheresPerLink where none applies). Sphere primitives are in both sets.
  bool outer = true;
  /// Link name -> spheres in its frame (a planner's own set, which need not cover): that
  /// link's outer set is tighten_cover (cover.h) of them instead of a bake to its budget.
  /// Links of the robot without meshed parts, and names that are no link of the robot, are
  /// not used (RobotBakeResult::unused_outer_start). Needs `outer`.
  std::map<std::string, std::vector<Sphere>> outer_start;
  /// Link name -> where its outer set should stick out less (protrusion_weights.h), points
  /// in its link frame (contact_regions.h makes them). Links without meshed parts, links
  /// with an outer_start and names that are no link are not used.
  std::map<std::string, ProtrusionWeights> outer_weights;
  /// With request.solid kAuto: a link whose mesh is a thin shell (is_thin_shell,
  /// filled_solid.h) gets its inner set baked on its filled solid: the set lies inside the
  /// filled solid (its balls may sit in the cavity), records "inner_solid": "filled" (in
  /// its SphereSet's metadata and the link's entry of the robot's), and its nerr is of the
  /// filled solid. Its outer set is certified on the real surface as always. A
  /// BoundedGeometry built from the set with the link's mesh does not use its balls; the
  /// robot file keeps only the robot's metadata, which RobotBounds and RobotChecker do not
  /// read: their inner bounds of such a link are those of the filled solid. Off by
  /// default for that reason (`robot --fill`).
  bool fill_thin_shells = false;
  /// With request.solid kAuto and `outer`: a link whose mesh is a thin shell gets its
  /// covering set baked on its filled solid at fill_cover_resolution (make_filled_solid),
  /// certified on the link's real surface as every covering set is: its balls may sit in the
  /// cavity and hug the outside instead of sticking out on both sides of the thin material,
  /// and they fill the cavity's opening. Its outer set's metadata and the link's entry of
  /// the robot's record "cover_solid": "filled" (LinkBakeStats::outer_filled); the stats'
  /// outer_max_protrusion is then against the filled solid. docs/self-collision.md,
  /// "Covers of thin shells".
  bool fill_thin_shell_covers = false;
  /// The resolution of the filled solid the covers of fill_thin_shell_covers are baked on,
  /// in [8, 1024]: its excess over the link's convex parts is below
  /// (1 + sqrt(3)/2 + sqrt(3)) L / resolution (robust_solid.h).
  int fill_cover_resolution = kFillCoverResolution;
};

struct RobotBakeResult {
  RobotModel model;  ///< the robot's tree with every link's spheres and the provenance
  std::vector<LinkBakeStats> links;  ///< in link order
  /// Names of options.outer_start not used: no link of the robot, or one without meshed
  /// parts; in the map's order.
  std::vector<std::string> unused_outer_start;
  double seconds = 0.0;  ///< wall clock of the whole bake
};

/// Bakes every link of \p robot, whose solids are \p solids (load_link_solids).
/// \throws InputError (source: robot.path) naming the link and the problem for every
///   failure of a link's bake (the first in link order when several fail), and as
///   link_bake_budgets and validate(request).
/// \throws InputError (source: robot.path) for outer_start without outer or with spheres
///   that tighten_cover refuses (naming the link).
/// \throws std::invalid_argument for jobs outside [0, kMaxThreads] or solids that do not
///   match the robot's links, or a model whose links do not match them.
RobotBakeResult bake_robot(const UrdfRobot& robot, const std::vector<LinkSolid>& solids,
                           const RobotBakeOptions& options);

}  // namespace medspheres
