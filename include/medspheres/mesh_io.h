#pragma once
/// \file
/// Loading triangle meshes through assimp: STL (binary and ASCII), OBJ, PLY, OFF,
/// COLLADA (.dae), glTF 2 (.gltf, .glb), and the other formats assimp reads.
///
/// What the loader does, in order:
/// 1. reads every mesh of the scene and applies each node's accumulated transform
///    (a mesh used by two nodes appears twice); meshes no node references are kept
///    with the identity transform. Polygons are triangulated; points and lines are
///    dropped;
/// 2. merges vertices whose transformed coordinates are bit-identical in double
///    precision (-0.0 and +0.0 count as equal). No tolerance is applied: nearly
///    coincident vertices stay apart, so a seam that is open in the file stays open;
/// 3. checks that the mesh is usable (check_mesh_usable);
/// 4. unless told not to, repairs orientation (orient_mesh), with a warning per kind
///    of repair.
/// Coordinates are in the file's units and the scene root's frame. COLLADA's
/// <up_axis> is ignored (no rotation is added) and its <unit> scale is applied, which is
/// how robot description tools read DAE meshes.
///
/// Precision: Debian's assimp stores coordinates in single precision, so every
/// coordinate is a float widened to double. Transforms are composed in double.

#include <string>
#include <vector>

#include "medspheres/mesh_report.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

struct MeshLoadOptions {
  bool fix_orientation = true;  ///< run orient_mesh after loading
};

struct LoadedMesh {
  TriangleMesh mesh;
  MeshReport report;                  ///< of the mesh as returned (after repairs)
  OrientationFix orientation_fix;     ///< what step 4 changed
  std::vector<std::string> warnings;  ///< one sentence each, for the user
};

/// Loads, welds, validates and (by default) orients the mesh in \p path.
/// \throws InputError naming \p path: missing or unreadable file, a format assimp does
///   not read, a file assimp cannot parse, no triangles, non-finite coordinates, or
///   only degenerate triangles.
LoadedMesh load_mesh(const std::string& path, const MeshLoadOptions& options = {});

/// The SHA-256 of the bytes of \p path, as 64 lowercase hex digits.
/// \throws InputError when the file cannot be read.
std::string file_sha256(const std::string& path);

/// The SHA-256 of \p bytes, as 64 lowercase hex digits.
std::string sha256_hex(const std::string& bytes);

}  // namespace medspheres
