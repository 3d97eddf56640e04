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
/// 2. wall cells: those whose centre lies within r = (1 + sqrt(3)/2) h + t of some
///    triangle, so that every point within h of the surface lies in a wall cell, and gaps
///    narrower than about 2 r are closed;
/// 3. a 6-connected flood fill from the grid's corner over non-wall cells: what it
///    reaches is outside, everything else (walls and the cells they enclose) is the solid;
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

struct RobustSolidOptions {
  int resolution = 0;      ///< n: cells along the largest side, in [8, 1024]; 0: chosen
  double thickness = 0.0;  ///< t >= 0, mesh units: extra wall thickness
};

struct RobustSolid {
  TriangleMesh mesh;         ///< the boundary of the solid (closed, outward)
  int resolution = 0;        ///< n, as given or chosen
  double cell = 0.0;         ///< h
  double wall_radius = 0.0;  ///< r = (1 + sqrt(3)/2) h + t
  std::size_t wall_cells = 0;
  std::size_t enclosed_cells = 0;  ///< not wall, not reached by the flood fill
  std::size_t solid_cells = 0;     ///< after step 4
};

/// The robust solid of \p mesh (see the file comment); \p name names the mesh in errors.
/// \throws InputError (kOutOfRange, field "robust_resolution" or "robust_thickness") for
///   options out of range, (kNoInterior, file \p name) when the walls enclose no cell (at
///   any probe's resolution, when chosen): the surface bounds no volume (a flat sheet),
///   has holes wider than the walls close, or parts thinner than the walls, which then fill
///   them.
/// \throws std::invalid_argument for a mesh without triangles or with indices out of range.
RobustSolid make_robust_solid(const TriangleMesh& mesh, const RobustSolidOptions& options,
                              const std::string& name);

/// One sentence for the user: what make_robust_solid did (resolution, cell, walls).
std::string describe(const RobustSolid& solid);

}  // namespace medspheres
