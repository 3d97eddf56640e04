#pragma once
// A folder of generated meshes for batch tests and benchmarks: boxes, icospheres, tori,
// capsules and cylinders (mesh_generators.h) of sizes spread log-uniformly over a range
// of triangle counts, written as OFF, binary STL and OBJ in nested folders.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace medspheres::test {

struct LibraryMesh {
  std::string relative;  ///< its path under the folder
  std::size_t triangles = 0;
};

/// Writes \p count meshes under \p dir (created), each of \p min_triangles to
/// \p max_triangles triangles (targets drawn log-uniformly in that range; icospheres take
/// the level 20 * 4^k in the range nearest the target); the same seed gives the same files.
/// \throws std::invalid_argument when the range is too narrow for some kind of mesh.
std::vector<LibraryMesh> write_mesh_library(const std::string& dir, std::size_t count,
                                            std::uint64_t seed = 1, std::size_t min_triangles = 100,
                                            std::size_t max_triangles = 20000);

}  // namespace medspheres::test
