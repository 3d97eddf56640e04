#pragma once
// spheretree (Bradshaw's sphere-tree construction toolkit, github.com/mlund/spheretree), run
// as a peer in bench_budget: its medial method (makeTreeMedial) with the settings foam
// (github.com/CoMMALab/foam, foam/external/__init__.py) uses: depth 1, branch K,
// testerLevels 2, numCover 5000, minCover 5, initSpheres 1000, minSpheres 200, erFact 2,
// maxOptLevel 1, expand, merge and burst, optimise balance with balExcess 0.05.
//
// The benchmark only runs a program the user built; nothing here builds it. The mesh goes
// to makeTreeMedial as OBJ (its loader needs "f a//a b//b c//c" faces), centred on its box
// as foam's loader expects, and its level-1 spheres come back in the mesh's frame.

#include <cstddef>
#include <string>
#include <vector>

#include "medspheres/sphere_set.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres::bench {

struct SpheretreeRun {
  std::vector<Sphere> spheres;  ///< level 1 of the tree, in the mesh's frame
  double seconds = 0.0;         ///< wall clock of makeTreeMedial
  double cpu = 0.0;             ///< its user + system CPU seconds
  bool cached = false;          ///< read back from the cache folder, not run now
  bool skipped = false;         ///< \p cached_only and not in the cache: neither run nor read
  std::string error;            ///< empty, or why there are no spheres (a crash, no file)
};

/// makeTreeMedial of \p bin_dir on \p mesh with branch \p k. With a \p cache_dir, the
/// spheres and seconds of a run are kept there under the hash of the OBJ text and the
/// options, and read back instead of running again (spheretree takes tens of seconds per
/// mesh). \p work_dir holds the OBJ, the log and the .sph while it runs. With
/// \p cached_only, a run the cache does not hold is skipped (SpheretreeRun::skipped).
SpheretreeRun run_spheretree(const std::string& bin_dir, const TriangleMesh& mesh, std::size_t k,
                             const std::string& cache_dir, const std::string& work_dir,
                             bool cached_only = false);

}  // namespace medspheres::bench
