#pragma once
/// \file
/// Conservative dilation (Stolpner, Kry and Siddiqi, section 5.1): grow and add spheres
/// so that a set of internal medial spheres S_D hugs the surface of the solid, giving
/// S+. Distance queries between objects need S+: the union of internal spheres lies
/// inside the object, so distances between such unions are too large.
///
/// The steps, on the union's dual complex (union_volume.h):
/// 1. v-points. For each triangle (i, j, k) of the dual complex, the points where
///    spheres i, j and k meet on the boundary of the union. For each v-point v, with m
///    the nearest mesh point to v, every sphere of its triangle grows until it covers m.
///    Beyond the paper, `max_protrusion` caps this: a sphere grows for m only if, grown,
///    it would stick out of the solid by at most that much (its radius minus the exact
///    distance from its centre to the mesh); a point m that no sphere of its triangle
///    may cover joins the vertices of step 3, which gets a small sphere added there.
/// 2. Lone edges. For each edge (i, j) of the dual complex in no triangle, two points
///    drawn at random (seeded) on the circle where spheres i and j meet are treated
///    like v-points of spheres i and j.
/// 3. Vertex spheres. Each mesh vertex u (and each point m left by the cap of step 1)
///    whose nearest point t on the union is farther than `vertex_tolerance` gets a new
///    sphere with r = |t - u| / 2 centred at
///    u + r (t - u) / |t - u|, which touches both. Vertices are visited in order of
///    decreasing distance (ties: lower index), each against the union as it stands, so
///    a new sphere that covers later vertices spares them theirs. (Candidates are made
///    64 vertices at a time, in parallel, with t taken on the spheres present before
///    this step; each is added only if its vertex is still uncovered when its turn
///    comes, so the result does not depend on the thread count.)
/// 4. Optional, beyond the paper (`cover_tolerance` >= 0): rounds of fresh surface
///    samples (area-weighted, plus every vertex), each sample farther than the tolerance
///    outside the union getting a sphere as in step 3, cap included, that comes within
///    half the tolerance of it (so that the samples around it are covered too), until a
///    round finds none or the caps are hit. The largest uncovered distance of the last
///    round is reported. It bounds the samples of that round only: a denser sampling
///    finds somewhat larger gaps (bench_dilate measures 10^5 fresh samples).
///
/// Spheres only grow or are added: S_D is contained in S+, so every distance between
/// two sphere sets built this way is at most the distance between their S_D. The order
/// of S+ is: the spheres of S_D (grown) in their order, then the added spheres in the
/// order they were added. Deterministic for given input and options, whatever the
/// thread count.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_set.h"

namespace medspheres {

struct DilateOptions {
  /// Step 3 threshold, a length; 0 means 0.5% of the bounding box's largest side.
  double vertex_tolerance = 0.0;
  /// Step 1 cap on how far a grown sphere may stick out of the solid, a length; infinite
  /// (the default) is the paper's rule, where every sphere of a v-point's triangle grows.
  double max_protrusion = std::numeric_limits<double>::infinity();
  /// Seed of the random points on lone-edge circles and of the cover samples.
  std::uint64_t seed = 1;
  /// Step 4: < 0 off; otherwise the coverage to reach, a length.
  double cover_tolerance = -1.0;
  /// Step 4: area-weighted samples per round (every vertex is sampled too).
  std::size_t cover_samples = 20000;
  /// Step 4 caps: rounds, and spheres added by step 4 as a multiple of |S_D|. Once few
  /// samples are left uncovered a round costs little; 32 rounds leave a handful of
  /// samples per 20000 uncovered on the meshes with the sharpest features.
  int cover_max_rounds = 32;
  double cover_max_added = 4.0;
  int threads = 0;  ///< 0: all cores
};

struct DilateStats {
  std::size_t input_spheres = 0;
  std::size_t v_points = 0;       ///< step 1 points used
  std::size_t edge_points = 0;    ///< step 2 points used
  std::size_t grown = 0;          ///< spheres of S_D whose radius grew
  std::size_t capped_points = 0;  ///< step 1 points no sphere could cover within the cap
  double max_growth = 0.0;        ///< largest radius increase, a length
  std::size_t added_vertex = 0;   ///< spheres added by step 3
  std::size_t added_cover = 0;    ///< spheres added by step 4
  int cover_rounds = 0;           ///< step 4 rounds run
  bool cover_reached = false;     ///< step 4: the last round found nothing to cover
  double vertex_tolerance = 0.0;  ///< the value used
  double uncovered_max = 0.0;     ///< step 4: largest sample distance outside S+, last round
  double seconds = 0.0;
};

struct DilateResult {
  SphereSet spheres;  ///< S+
  DilateStats stats;
};

/// Dilates the internal sphere set \p internal of the solid bounded by query.mesh().
/// \throws std::invalid_argument for options out of range (the message names the
///   option); InputError (source "sphere set") for an invalid or empty sphere set.
DilateResult dilate(const MeshQuery& query, const SphereSet& internal,
                    const DilateOptions& options = {});

}  // namespace medspheres
