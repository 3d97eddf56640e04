#pragma once
/// \file
/// Which solid a triangle mesh bounds, and the robust solid for meshes whose winding
/// number does not say (open, non-manifold, self-intersecting surfaces, triangle soups).
///
/// The robust solid of a mesh, at resolution n and thickness t (mesh units):
/// 0. n given, or (resolution 0, the default) chosen: the finest n in [16, 96] whose
///    boundary has at most kRobustTriangleBudget triangles, searched from a probe at n = 32
///    (48, then 96, when its walls enclose nothing) with guesses from triangles growing as
///    n^2, 5 more grids at most (or the coarsest built, when none fits); every query and
///    bake on the solid costs in proportion to its triangles;
/// 1. a grid of cubic cells of side h = L / n (L the largest side of the mesh's box),
///    padded so that its outer layer of cells touches no wall;
/// 2. wall cells: those whose centre lies within (1 + sqrt(3)/2) h of some triangle, so
///    that every point within h of the surface lies in a wall cell; for t > 0, also every
///    cell whose centre lies within t of a wall cell's centre (exact Euclidean distance
///    transform), so that the walls reach r = (1 + sqrt(3)/2) h + t from the surface at
///    most and gaps narrower than about 2 r are closed;
/// 3. a 6-connected flood fill from the grid's corner over non-wall cells: what it
///    reaches is outside; for t > 0 then a closing: the cells added by t whose centre lies
///    within t of an outside cell's become outside again (those the outside reaches through
///    them), so that the thickness plugs holes without fattening the rest. Everything else
///    is the solid. The walls *enclose a volume* when some cell of the solid is neither a
///    wall cell of step 2's first kind nor within sqrt(3) h of one: free cells the fill did
///    not reach, or cells a plug or a closing holds. A sheet encloses nothing, however thick
///    its walls (what its closing leaves lies within sqrt(3) h of its first walls);
/// 4. cells are added where only two diagonal cells around a grid edge are solid, until
///    none is left, so that the boundary is an edge-manifold surface;
/// 5. the boundary: the faces between solid and non-solid cells, two triangles each,
///    wound outward, on the grid's lattice points (welded by lattice index);
/// 6. the staircase smoothed: 8 Laplacian steps, each vertex kept within h/2 per axis of
///    its lattice point (so it moves less than h, and the surface stays inside the solid).
/// The result is a closed, consistently outward-wound mesh: its winding number is 1 inside
/// and 0 outside, so every exact query (inside test, nearest distance) and every guarantee
/// of a bake hold for this solid. It contains the input's surface and the volume the
/// surface encloses, and lies within r + sqrt(3) h of the surface.
/// Escalation (RobustSolidOptions::escalate): when the walls enclose nothing at t (every
/// probe, when n is chosen), t takes the steps of kRobustThicknessSteps above it in turn
/// (probed at n = 32 and 48 only: thickened walls are no thinner on a finer grid), and the
/// first solid whose walls enclose a volume is kept, its t in RobustSolid::thickness. An
/// open surface whose openings are as wide as its parts (a tube, a cup) encloses a volume
/// once its walls close its crevices or openings; the figures are in docs/reliability.md.
/// Deterministic; does not depend on the order of triangles or vertices.

#include <cstddef>
#include <string>

#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// The solid a bake or an evaluation uses.
/// - kAuto: the winding-number solid when it is well defined (the mesh is closed and
///   consistently wound, or its winding number is confident almost everywhere inside),
///   otherwise the robust solid, with a warning;
/// - kWinding: the winding-number solid, whatever it is (an ambiguous one is an error);
/// - kRobust: the robust solid, always.
enum class SolidKind { kAuto, kWinding, kRobust };

/// "auto", "winding", "robust" (read back by medspheres/options/option_text.h).
const char* to_string(SolidKind kind);

/// The boundary triangles the chosen resolution (resolution 0) allows.
inline constexpr std::size_t kRobustTriangleBudget = 24000;

/// The thicknesses, as fractions of L, that an escalating make_robust_solid tries in turn
/// (those above the given one) when the walls enclose nothing.
inline constexpr double kRobustThicknessSteps[] = {0.02, 0.05, 0.1, 0.2, 0.5};

struct RobustSolidOptions {
  int resolution = 0;      ///< n: cells along the largest side, in [8, 1024]; 0: chosen
  double thickness = 0.0;  ///< t >= 0, mesh units: extra wall thickness
  /// When the walls enclose nothing at \p thickness: try kRobustThicknessSteps (times L)
  /// above it, keeping the first solid whose walls enclose a cell (RobustSolid::thickness).
  bool escalate = false;
};

struct RobustSolid {
  TriangleMesh mesh;         ///< the boundary of the solid (closed, outward)
  int resolution = 0;        ///< n, as given or chosen
  double cell = 0.0;         ///< h
  double wall_radius = 0.0;  ///< r = (1 + sqrt(3)/2) h + t
  double thickness = 0.0;    ///< t, as given or escalated to
  std::size_t wall_cells = 0;
  std::size_t enclosed_cells = 0;  ///< the volume the walls enclose, in cells (step 3)
  std::size_t solid_cells = 0;     ///< after step 4
};

/// \throws InputError (kOutOfRange, field "robust_resolution" or "robust_thickness") for
///   options out of range. Callers that may not build the solid (a bake whose solid is
///   chosen later) call it first, so that a bad option fails whether or not it is used.
void validate(const RobustSolidOptions& options);

/// The robust solid of \p mesh (see the file comment); \p name names the mesh in errors.
/// \throws InputError (kOutOfRange, field "robust_resolution" or "robust_thickness") for
///   options out of range (a thickness above the mesh's largest side too), (kNoInterior,
///   file \p name) when the walls enclose no volume (at any probe's resolution, when
///   chosen; at any thickness tried, when escalating): the surface bounds no volume (a flat
///   sheet), has holes wider than the walls close, or parts thinner than the walls, which
///   then fill them.
/// \throws std::invalid_argument for a mesh without triangles or with indices out of range.
RobustSolid make_robust_solid(const TriangleMesh& mesh, const RobustSolidOptions& options,
                              const std::string& name);

/// One sentence for the user: what make_robust_solid did (resolution, cell, walls).
std::string describe(const RobustSolid& solid);

}  // namespace medspheres
