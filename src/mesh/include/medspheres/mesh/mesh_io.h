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
/// (no atexit handlers, no stdio flush) and is always reaped; it is signalled through a
/// pidfd where the kernel has them (Linux 5.3), so that a caller that ignores SIGCHLD
/// cannot have the signal reach another process that reuses the child's pid. The cost is
/// a fork and a copy of the mesh through the pipe: a few milliseconds for a small file,
/// and up to about twice the in-process load time for a large mesh on a virtual machine,
/// where copy-on-write page faults are slow.
///
/// Threads. load_mesh may be called from any thread, and from several at once, but the
/// isolated import has one risk in a multi-threaded process. The child of a fork holds
/// only the calling thread, and a lock that another thread held at the moment of the
/// fork stays locked in the child for ever. So the child does as little as it can: the
/// checks of the file and options, the OFF pre-scan and the limits are done in the
/// caller before the fork, and the child itself uses no C++ streams; glibc makes its
/// malloc and stdio safe after fork. What remains is assimp and the parts of the C++
/// runtime that assimp uses (its logger, locale-dependent parsing in some importers,
/// function-local statics). If another thread holds one of their locks when the child
/// is forked, for example because it is itself inside assimp, the child waits for ever
/// and the import ends at the timeout, with the timeout's error, although the file may
/// be fine. A caller that runs assimp or changes the global locale on other threads while
/// it loads meshes can set isolate_import = false: no fork, hence no such risk, but no
/// protection from malformed files either.
///
/// OFF files are pre-scanned before assimp reads them: assimp clamps an out-of-range
/// face index to the last vertex and reads a negative one as 0, silently, and drops faces
/// of more than 9 vertices; the pre-scan rejects such files instead, naming the face.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/mesh/mesh_report.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

struct MeshLoadOptions {
  bool fix_orientation = true;  ///< run orient_mesh after loading

  /// Run assimp in a child process (see "Isolation" above). false runs it in this
  /// process, where a malformed file can crash or hang the caller; the limits below
  /// then do not apply.
  bool isolate_import = true;

  /// Wall-clock limit on the import, in seconds. Unset (the default): 30 s plus 5 s per
  /// MiB of file, generous for any well-formed file; 0 or +infinity: no limit. NaN and
  /// negative values are rejected (std::invalid_argument), also when isolate_import is
  /// false.
  std::optional<double> import_timeout_seconds;

  /// Address space the import may add to what the process has mapped, in bytes.
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

/// Whether this build of the library applies MeshLoadOptions::import_memory_limit_bytes:
/// false in builds with AddressSanitizer, ThreadSanitizer or MemorySanitizer, which
/// reserve terabytes of address space up front, so that any address-space limit would
/// fail every allocation.
bool import_memory_limit_enforced() noexcept;

/// The SHA-256 of the bytes of \p path, as 64 lowercase hex digits.
/// \throws InputError when the file cannot be read.
std::string file_sha256(const std::string& path);

/// The SHA-256 of \p bytes, as 64 lowercase hex digits.
std::string sha256_hex(const std::string& bytes);

}  // namespace medspheres
