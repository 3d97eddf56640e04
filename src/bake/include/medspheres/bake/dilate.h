#pragma once
/// \file
/// Conservative dilation (Stolpner, Kry and Siddiqi, section 5.1): grow and add spheres so
/// that a set of internal medial spheres S_D hugs the surface of the solid, giving S+
/// (distances between unions of internal spheres are too large).
///
/// Spheres only grow or are added: S_D is contained in S+, so every distance between two
/// sets built this way is at most the distance between their S_D. S+ lists the spheres of
/// S_D (grown) in their order, then the added spheres in the order added. Spheres are added
/// at mesh vertices farther than vertex_tolerance from the union; max_protrusion caps how far
/// a grown or added sphere sticks out of the solid; cover_tolerance >= 0 adds rounds of
/// surface samples until one finds none farther than it (or a cap is hit).
/// Frame and units: the mesh's. Deterministic for given input and options, whatever the
/// thread count. The steps are described in dilate.cpp.

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
