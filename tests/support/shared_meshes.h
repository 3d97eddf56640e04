#pragma once
// The optional real meshes of ../shared/meshes, described by their MANIFEST.tsv.
// Tests that use them are tagged [shared] and compiled only when the folder exists.

#include <cstddef>
#include <string>
#include <vector>

namespace medspheres::test {

struct SharedMesh {
  std::string file;  ///< path relative to the meshes folder, e.g. "cgal/knot1.off"
  std::string path;  ///< absolute path
  std::size_t triangles = 0;
  bool closed = false;
  std::size_t boundary_edges = 0;
  std::size_t nonmanifold_edges = 0;
  std::size_t components = 0;
  std::size_t degenerate_triangles = 0;
  std::size_t selfint_pairs = 0;  ///< the manifest's (heuristic) count of intersecting pairs
  std::string category;           ///< "classic", "classic:peanut", "awkward:open", ...
  bool classic() const { return category.rfind("classic", 0) == 0; }
};

/// Every row of DIR/MANIFEST.tsv, paths under DIR. Throws std::runtime_error naming
/// the file when it cannot be read.
std::vector<SharedMesh> read_manifest(const std::string& dir);

/// The rows of ../shared/meshes/MANIFEST.tsv; empty when the build has no shared meshes. In
/// the sanitizer builds (sanitizer_build.h), the rows of at most 50,000 triangles.
const std::vector<SharedMesh>& shared_meshes();

/// The folder of the shared meshes this build was configured with; empty if none.
std::string shared_meshes_dir();

/// True when this build was configured with ../shared/meshes present.
bool have_shared_meshes();

}  // namespace medspheres::test
