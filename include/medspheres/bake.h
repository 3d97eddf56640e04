#pragma once
/// \file
/// Medial sphere baking (Stolpner, Kry and Siddiqi, "Medial Spheres for Shape
/// Approximation", section 3): spheres centred near the medial surface of a solid,
/// each tangent to the boundary and inside the solid.
///
/// The method, with every choice the paper leaves open made explicit:
///
/// 1. Grid. A regular grid of cubic cells covers the mesh's bounding box, with
///    `resolution` cells along its longest side (cell size h), centred on the box.
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
///    `medial_tolerance`, and the candidate m is the bracket's near end, whose nearest
///    point A is exact and still on p's side of the sheet. The segment
///    length is gamma = sqrt(3) h / sin(object_angle / 2): a sheet of object angle at
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
/// 5. Radius. r = D(m) - 1e-12 L, where D(m) is the exact distance from m to the mesh
///    and L the largest side of the bounding box. The shrink exceeds the rounding
///    error of D (a few ulps of the coordinates), so |m - x| > r for every mesh point
///    x: on a closed mesh every sphere lies inside the solid.
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
#include <string>
#include <vector>

#include "medspheres/mesh_query.h"
#include "medspheres/sphere_set.h"

namespace medspheres {

/// Progress of a long computation: stage name, units done, units in total.
using ProgressFn =
    std::function<void(const std::string& stage, std::size_t done, std::size_t total)>;

struct BakeOptions {
  int resolution = 28;            ///< cells along the longest side of the bounding box (>= 2);
                                  ///< 28 gives 240-460 spheres on most of the test meshes
  double object_angle = 0.6;      ///< rad, in (0, pi): keep medial points at least this open
  double medial_tolerance = 0.0;  ///< length; 0 means 1e-3 of the box's largest side
  int threads = 0;                ///< 0: all cores
  ProgressFn progress;            ///< optional; called from the calling thread only
};

/// What one medial sphere was made from (kept beside each sphere).
struct MedialSample {
  Eigen::Vector3d near_point;  ///< A: the exact nearest mesh point of the centre
  Eigen::Vector3d far_point;   ///< B: the approximate second tangency point
  double object_angle = 0.0;   ///< angle AmB, rad
  int cell = -1;               ///< linear index of the grid cell that kept it
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
  std::uint64_t closest_point_queries = 0;
  std::uint64_t winding_queries = 0;
  double min_radius = 0.0;
  double max_radius = 0.0;
  double seconds = 0.0;
};

struct BakeResult {
  SphereSet spheres;                  ///< the medial spheres, ordered by cell index
  std::vector<MedialSample> samples;  ///< one per sphere, same order
  BakeStats stats;
};

/// Bakes medial spheres of the solid bounded by query.mesh(). Reusing one MeshQuery
/// across bakes (as the resolution searches do) saves rebuilding the hierarchy.
/// \throws std::invalid_argument for options out of range (message names the option).
/// \throws InputError (source "mesh") when no grid vertex is inside the solid (a flat
///   sheet, or parts thinner than a cell), or when fewer than 70% of the grid vertices
///   inside have a winding number of at least 0.75: the winding number of a closed or
///   nearly closed surface is close to 1 inside, that of a triangle soup wanders.
BakeResult bake(const MeshQuery& query, const BakeOptions& options = {});

/// Convenience: builds the MeshQuery and bakes. Same errors.
BakeResult bake(const TriangleMesh& mesh, const BakeOptions& options = {});

/// Largest resolution in [2, max_resolution] whose bake has at most \p max_spheres
/// spheres, found by doubling and then bisection. Sphere counts grow with resolution
/// but not strictly monotonically, so the answer is the largest resolution the search
/// saw within the limit; the result returned is that bake. Doubling stops early when it
/// adds no sphere: the medial surface is then resolved (a ball's single centre, say) and
/// higher resolutions would only cost time.
/// \throws std::invalid_argument if max_spheres < 1; InputError as bake().
BakeResult bake_max_spheres(const MeshQuery& query, std::size_t max_spheres,
                            const BakeOptions& options = {}, int max_resolution = 512);

/// Normalized volumetric error of a sphere set against the solid: supplied by the
/// caller so that this header stays free of the volume machinery.
using ErrorFn = std::function<double(const SphereSet&)>;

/// Smallest resolution in [2, max_resolution] whose bake has error(spheres) <= target,
/// found by doubling and then bisection (error falls with resolution, not strictly).
/// Doubling stops early when it does not reduce the error.
/// \throws std::invalid_argument if target <= 0 or no ErrorFn; InputError as bake();
///   Error if even max_resolution misses the target (the message gives the best error).
BakeResult bake_target_error(const MeshQuery& query, double target, const ErrorFn& error,
                             const BakeOptions& options = {}, int max_resolution = 512);

}  // namespace medspheres
