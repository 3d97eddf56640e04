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
///
/// Isolation. assimp (5.2.5, Debian 12's) can crash, loop forever or allocate without
/// bound on malformed files: a binary PLY with a misspelled end_header segfaults, the same
/// in ASCII loops, a stray letter inside a COLLADA <p> list loops while allocating. Bad
/// input must end in an error naming the file, so by default step 1 runs in a child
/// process (fork; Linux): the child reads the file with assimp under an address-space
/// limit (RLIMIT_AS) and sends back the transformed coordinates and triangles of each
/// placed mesh through a pipe; the caller waits with a wall-clock timeout, kills the
/// child at the deadline and does steps 2 to 4 itself. A child that crashes, times out
/// or runs out of memory becomes an InputError saying so. The child leaves with _exit
/// (no atexit handlers, no stdio flush) and is always reaped. The cost is a fork and a
/// copy of the mesh through the pipe: a few milliseconds for a small file, and up to
/// about twice the in-process load time for a large mesh on a virtual machine, where
/// copy-on-write page faults are slow. The child of a multi-threaded caller holds only
/// the calling thread and runs only assimp and the C++ runtime (glibc's malloc is safe
/// after fork), so load_mesh may be called from any thread.
///
/// OFF files are pre-scanned before assimp reads them: assimp clamps an out-of-range
/// face index to the last vertex and reads a negative one as 0, silently, and drops faces
/// of more than 9 vertices; the pre-scan rejects such files instead, naming the face.

#include <cstdint>
#include <string>
#include <vector>

#include "medspheres/mesh_report.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

struct MeshLoadOptions {
  bool fix_orientation = true;  ///< run orient_mesh after loading

  /// Run assimp in a child process (see "Isolation" above). false runs it in this
  /// process, where a malformed file can crash or hang the caller; the limits below
  /// then do not apply.
  bool isolate_import = true;

  /// Wall-clock limit on the import, in seconds. Negative (the default): 30 s plus 5 s
  /// per MiB of file, generous for any well-formed file; 0: no limit.
  double import_timeout_seconds = -1.0;

  /// Address space the import may add to what the process has mapped, in bytes.
  /// Negative (the default): max(4 GiB, 64 x the file size); 0: no limit. Not applied in
  /// builds with AddressSanitizer, ThreadSanitizer or MemorySanitizer, which reserve
  /// terabytes of address space: there only the timeout guards the import.
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
/// \throws Error when the import process cannot be started.
LoadedMesh load_mesh(const std::string& path, const MeshLoadOptions& options = {});

/// The SHA-256 of the bytes of \p path, as 64 lowercase hex digits.
/// \throws InputError when the file cannot be read.
std::string file_sha256(const std::string& path);

/// The SHA-256 of \p bytes, as 64 lowercase hex digits.
std::string sha256_hex(const std::string& bytes);

}  // namespace medspheres
