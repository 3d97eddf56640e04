#pragma once
/// \file
/// Loading triangle meshes through assimp: STL (binary and ASCII), OBJ, PLY, OFF,
/// COLLADA (.dae), glTF 2 (.gltf, .glb), and the other formats assimp reads.
///
/// load_mesh, in order:
/// 1. reads every mesh of the scene with its node's accumulated transform applied (a mesh
///    used by two nodes appears twice; a mesh no node references gets the identity);
///    polygons are triangulated, points and lines dropped;
/// 2. merges vertices whose transformed coordinates are bit-identical in double
///    (-0.0 == +0.0). No tolerance: a seam that is open in the file stays open;
/// 3. check_mesh_usable, then canonicalize_order (canonical_order.h), so that a file that
///    lists the same vertices and triangles in another order loads identically;
/// 4. unless told not to, orient_mesh, with a warning per kind of repair.
/// A scene that assimp's validation rejects for its non-mesh parts (two cameras of one
/// name) gives its triangles with a warning (scene_import.h).
/// Frame and units: the scene root's frame, the file's units; COLLADA's <unit> scale is
/// applied and its <up_axis> ignored, as robot description tools do. Coordinates are
/// assimp's floats widened to double; transforms are composed in double.
///
/// Isolation (MeshLoadOptions::isolate_import): step 1 runs in a child process, the
/// program medspheres-import installed beside the medspheres CLI (Linux), under an
/// address-space limit and a wall-clock timeout, so that a malformed file that crashes,
/// hangs or exhausts assimp ends in an InputError naming the file. The program is looked
/// for beside the binary holding the library (the program, shared library or Python
/// module), in the install's bin folder, beside the running program, then in the bin
/// folder of the install prefix; the environment variable MEDSPHERES_IMPORT_HELPER names it
/// instead. None found: medspheres::Error naming the places looked in. OFF files are
/// pre-scanned: a face index out of range or a face of more than 9 vertices is an
/// InputError naming the face (assimp would alter the face silently).
///
/// Threads: load_mesh may run on several threads at once, isolated or not (the child is
/// started with posix_spawn, not a fork of the caller). Reasons and costs: mesh_io.cpp,
/// docs/baking.md (Meshes).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/mesh/mesh_report.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

struct MeshLoadOptions {
  bool fix_orientation = true;  ///< run orient_mesh after loading

  /// Run assimp in a child process (see "Isolation" above). false: in this process,
  /// where a malformed file can crash or hang the caller; the limits below do not apply.
  bool isolate_import = true;

  /// Wall-clock limit on the import, in seconds. Unset (the default): 30 s plus 5 s per
  /// MiB of file, generous for any well-formed file; 0 or +infinity: no limit. NaN and
  /// negative values are rejected (std::invalid_argument), also when isolate_import is
  /// false.
  std::optional<double> import_timeout_seconds;

  /// Address space the import process may map beyond what it maps when it starts, in bytes.
  /// Negative (the default): max(4 GiB, 64 x the file size); 0: no limit. Not applied
  /// where import_memory_limit_enforced() is false: there only the timeout guards the
  /// import.
  std::int64_t import_memory_limit_bytes = -1;
};

struct LoadedMesh {
  TriangleMesh mesh;
  MeshReport report;                  ///< of the mesh as returned (after repairs)
  OrientationFix orientation_fix;     ///< what step 4 changed
  std::vector<std::string> warnings;  ///< one sentence each, for the user
};

/// Loads, welds, validates and (by default) orients the mesh in \p path.
/// \throws InputError naming \p path: missing or unreadable file, not a regular file
///   (a FIFO, a device), a format assimp does not read, a file assimp cannot parse
///   ("cannot parse the file (assimp: ...)"), an OFF face with an index out of range, an
///   importer that crashed, timed out or ran out of memory on the file, no triangles,
///   non-finite coordinates (named by assimp's mesh and vertex index), or only degenerate
///   triangles.
/// \throws Error naming \p path when the import process cannot be started.
/// \throws std::invalid_argument for an import_timeout_seconds that is NaN or negative.
LoadedMesh load_mesh(const std::string& path, const MeshLoadOptions& options = {});

/// Steps 3 and 4 of load_mesh on a mesh given in memory (an indexed mesh needs no
/// welding): check_mesh_usable, the canonical order, orient_mesh when \p fix_orientation,
/// analyze_mesh, and the same warnings. \p source names the mesh in errors.
/// \throws InputError naming \p source as check_mesh_usable.
LoadedMesh prepare_mesh(TriangleMesh mesh, const std::string& source, bool fix_orientation = true);

/// Whether this build of the library applies MeshLoadOptions::import_memory_limit_bytes:
/// false in builds with AddressSanitizer, ThreadSanitizer or MemorySanitizer, which
/// reserve terabytes of address space up front, so that any address-space limit would
/// fail every allocation.
bool import_memory_limit_enforced() noexcept;

}  // namespace medspheres
