#include "medspheres/mesh/mesh_io.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unordered_map>

#include <sys/stat.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <assimp/Importer.hpp>

#include "import_helper_path.h"
#include "isolated_call.h"
#include "medspheres/error.h"
#include "medspheres/mesh/canonical_order.h"
#include "medspheres/number_text.h"
#include "scene_import.h"

namespace medspheres {

namespace {

// Bit-exact welding key; -0.0 is folded onto +0.0.
struct PointKey {
  std::uint64_t bits[3];
  bool operator==(const PointKey& o) const {
    return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2];
  }
};
struct PointKeyHash {
  std::size_t operator()(const PointKey& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (std::uint64_t b : k.bits) h = (h ^ b) * 1099511628211ull ^ (b >> 29);
    return static_cast<std::size_t>(h);
  }
};
PointKey key_of(const Eigen::Vector3d& p) {
  PointKey k;
  for (int i = 0; i < 3; ++i) {
    const double v = p[i] == 0.0 ? 0.0 : p[i];
    std::memcpy(&k.bits[i], &v, sizeof v);
  }
  return k;
}

class Welder {
 public:
  explicit Welder(TriangleMesh& mesh) : mesh_(mesh) {}
  int add(const Eigen::Vector3d& p) {
    // NaN compares unequal to itself, so never weld non-finite points; the usability
    // check reports them.
    if (!p.allFinite()) return push(p);
    auto [it, inserted] = index_.try_emplace(key_of(p), 0);
    if (inserted) it->second = push(p);
    return it->second;
  }

 private:
  int push(const Eigen::Vector3d& p) {
    mesh_.vertices.push_back(p);
    return static_cast<int>(mesh_.vertices.size() - 1);
  }
  TriangleMesh& mesh_;
  std::unordered_map<PointKey, int, PointKeyHash> index_;
};

// Gives the heap's free pages back to the system (glibc): the import frees many small
// blocks (assimp's faces, the welding map) that would otherwise stay resident while the
// later, larger arrays are mapped anew.
void release_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

constexpr double kMiB = 1024.0 * 1024.0;

// "30", "2.5": whole seconds from 10 s up (rounded as "%.0f" rounds), three digits below.
std::string seconds_text(double s) {
  return s >= 10.0 ? number_text(std::nearbyint(s), 17) : number_text(s, 3);
}

// The import in a child process, its outcome turned into a FlatScene or an error.
detail::FlatScene import_isolated(const std::string& path, std::uintmax_t file_bytes,
                                  const MeshLoadOptions& options) {
  detail::IsolationLimits limits;
  if (!options.import_timeout_seconds)
    limits.timeout_seconds = 30.0 + 5.0 * static_cast<double>(file_bytes) / kMiB;
  else if (std::isfinite(*options.import_timeout_seconds))
    limits.timeout_seconds = *options.import_timeout_seconds;  // else 0: no limit
  if (!import_memory_limit_enforced())
    limits.address_space_bytes = 0;
  else if (options.import_memory_limit_bytes < 0)
    limits.address_space_bytes =
        std::max<std::uint64_t>(std::uint64_t{4} << 30, std::uint64_t{64} * file_bytes);
  else
    limits.address_space_bytes = static_cast<std::uint64_t>(options.import_memory_limit_bytes);

  // The child runs assimp and nothing else (import_helper_main.cpp).
  const detail::IsolatedOutcome outcome =
      detail::run_isolated(detail::import_helper_path(path), {path}, limits, path);

  using End = detail::IsolatedOutcome::End;
  if (outcome.end == End::kTimedOut)
    throw InputError(path, "the importer did not finish within " +
                               seconds_text(limits.timeout_seconds) +
                               " s: the file may be malformed, or too large for the limit "
                               "(MeshLoadOptions::import_timeout_seconds)");
  if (outcome.end == End::kSignaled) {
    const std::string sig =
        "signal " + std::to_string(outcome.code) + ": " + detail::signal_name(outcome.code);
    if (outcome.code == SIGKILL)
      throw InputError(path, "the importer was killed (" + sig +
                                 "), probably for using too much memory: the file is malformed "
                                 "or too large");
    throw InputError(path, "the importer crashed on the file (" + sig + "): it is malformed");
  }
  detail::ImportAnswer answer = detail::decode_answer(outcome.output);
  if (!answer.ok) {
    if (outcome.code == 0) throw Error(path + ": the import process sent an incomplete result");
    // A crash that a sanitizer turned into an exit status, or a failure to answer.
    throw InputError(path, "the importer failed on the file (exit status " +
                               std::to_string(outcome.code) + ", no result): it is malformed");
  }
  switch (answer.tag) {
    case 'R':
      return std::move(answer.scene);
    case 'E':
      throw InputError(path, answer.text);
    case 'M':
      throw InputError(
          path, "the importer ran out of memory" +
                    (limits.address_space_bytes > 0
                         ? " (" + std::to_string(limits.address_space_bytes >> 20) + " MiB allowed)"
                         : std::string()) +
                    ": the file is malformed or too large for the memory limit");
    default:
      throw InputError(path, "cannot parse the file (" + answer.text + ")");
  }
}

}  // namespace

bool import_memory_limit_enforced() noexcept {
  // Sanitizers that reserve terabytes of address space up front: an RLIMIT_AS on the
  // import child would fail every allocation there, so only the timeout applies.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  return false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
  return false;
#else
  return true;
#endif
#else
  return true;
#endif
}

// Why the import is isolated. assimp (5.2.5, Debian 12's) can crash, loop forever or
// allocate without bound on malformed files: a binary PLY with a misspelled end_header
// segfaults, the same in ASCII loops, a stray letter inside a COLLADA <p> list loops while
// allocating. So by default step 1 runs in a child process (isolated_call.h): the program
// medspheres-import (import_helper_main.cpp, found by import_helper_path.h) reads the file
// with assimp under RLIMIT_AS and sends back the transformed coordinates and triangles of
// each placed mesh through a pipe; the caller waits with a wall-clock timeout, kills the
// child at the deadline and welds, checks and orients itself. A child that crashes, times
// out or runs out of memory becomes an InputError saying so. The child is always reaped,
// through a pidfd where the kernel has one (see isolated_call.cpp). The cost is a process
// start and a copy of the mesh through the pipe (figures in docs/baking.md, Meshes).
//
// Threads. The child is started with posix_spawn, which runs nothing of the caller's in
// the new process before it executes the helper: no lock another thread of the caller
// holds (its allocator's, assimp's, the C++ runtime's) is inherited, so imports may run on
// any number of threads, beside anything else. The checks of the file and options, the
// OFF, PLY and STL pre-scans and the limits are done here, before the start, so that
// their errors do not depend on the helper.
//
// The OFF pre-scan (check_off_faces): assimp clamps an out-of-range face index to the
// last vertex and reads a negative one as 0, silently, and drops faces of more than 9
// vertices; the pre-scan rejects such files instead, naming the face.
LoadedMesh load_mesh(const std::string& path, const MeshLoadOptions& options) {
  if (options.import_timeout_seconds && !(*options.import_timeout_seconds >= 0.0)) {
    throw std::invalid_argument(
        "MeshLoadOptions::import_timeout_seconds must be unset, >= 0 or +infinity, not " +
        number_text(*options.import_timeout_seconds));
  }

  // stat, not open: opening a FIFO blocks until a writer comes, and opening a device
  // can have side effects.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT || errno == ENOTDIR)
      throw InputError(ErrorKind::kFileMissing, path, "no such file");
    throw InputError(ErrorKind::kFileUnreadable, path,
                     std::string("cannot open for reading: ") + std::strerror(errno));
  }
  if (S_ISDIR(st.st_mode))
    throw InputError(ErrorKind::kFileUnreadable, path, "is a directory, not a mesh file");
  if (!S_ISREG(st.st_mode))
    throw InputError(ErrorKind::kFileUnreadable, path,
                     "is not a regular file (a FIFO, device or socket cannot be read as "
                     "a mesh)");
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe)
      throw InputError(ErrorKind::kFileUnreadable, path,
                       std::string("cannot open for reading: ") + std::strerror(errno));
  }
  if (st.st_size == 0) throw InputError(path, "the file is empty");

  const std::string ext = lower_extension(path);
  if (ext.empty() || !Assimp::Importer().IsExtensionSupported(ext)) {
    throw InputError(ErrorKind::kUnsupported, path,
                     "unsupported mesh format '" + ext +
                         "' (use STL, OBJ, PLY, OFF, DAE, glTF/GLB or another format "
                         "assimp reads)");
  }

  // In this process, also for the isolated import: the child does no more than assimp's
  // part.
  if (ext == ".off") detail::check_off_faces(path);
  if (ext == ".ply") detail::check_ply_counts(path, static_cast<std::uintmax_t>(st.st_size));
  if (ext == ".stl") detail::check_stl_counts(path, static_cast<std::uintmax_t>(st.st_size));

  detail::FlatScene scene =
      options.isolate_import
          ? import_isolated(path, static_cast<std::uintmax_t>(st.st_size), options)
          : detail::import_flat(path);

  return detail::mesh_from_scene(std::move(scene), path, options.fix_orientation);
}

// Steps 2 to 4 of load_mesh on the imported scene (scene_import.h). Each placed mesh is
// freed once welded, and the welding map before the checks, so that the flat scene (36
// bytes per triangle corner) and the welded mesh are not all held at once.
LoadedMesh detail::mesh_from_scene(detail::FlatScene scene, const std::string& path,
                                   bool fix_orientation) {
  LoadedMesh out;
  TriangleMesh& mesh = out.mesh;
  {
    std::size_t triangles = 0;
    for (const detail::FlatMesh& m : scene.meshes) triangles += m.index.size() / 3;
    mesh.triangles.reserve(triangles);
    Welder welder(mesh);
    std::vector<int> ids;
    for (detail::FlatMesh& m : scene.meshes) {
      const std::size_t nv = m.xyz.size() / 3;
      ids.resize(nv);
      for (std::size_t v = 0; v < nv; ++v)
        ids[v] = welder.add(Eigen::Vector3d(m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2]));
      for (std::size_t t = 0; t + 2 < m.index.size(); t += 3)
        mesh.triangles.push_back({ids[m.index[t]], ids[m.index[t + 1]], ids[m.index[t + 2]]});
      m = detail::FlatMesh{};
    }
  }
  mesh.vertices.shrink_to_fit();
  release_free_memory();
  if (!scene.validation_failure.empty())
    out.warnings.push_back("assimp's validation rejected the scene (" + scene.validation_failure +
                           "); its meshes were read without it and checked, the rest ignored");
  if (scene.orphans > 0)
    out.warnings.push_back(std::to_string(scene.orphans) +
                           " mesh(es) not placed by any scene node were kept untransformed");

  LoadedMesh prepared = prepare_mesh(std::move(mesh), path, fix_orientation);
  out.warnings.insert(out.warnings.end(), prepared.warnings.begin(), prepared.warnings.end());
  prepared.warnings = std::move(out.warnings);
  return prepared;
}

LoadedMesh prepare_mesh(TriangleMesh mesh, const std::string& source, bool fix_orientation) {
  LoadedMesh out;
  out.mesh = std::move(mesh);
  check_mesh_usable(out.mesh, source);
  canonicalize_order(out.mesh);

  if (fix_orientation) {
    out.orientation_fix = orient_mesh(out.mesh);
    if (out.orientation_fix.triangles_flipped_for_consistency > 0)
      out.warnings.push_back(
          "flipped " +
          count_text(out.orientation_fix.triangles_flipped_for_consistency, "triangle") +
          " to make the winding of their component consistent");
    if (out.orientation_fix.components_flipped_outward > 0)
      out.warnings.push_back("flipped " +
                             count_text(out.orientation_fix.components_flipped_outward,
                                        "inward-wound closed component") +
                             " to face outward");
  }
  out.report = analyze_mesh(out.mesh);
  if (!out.report.closed)
    out.warnings.push_back("the mesh is not closed (" +
                           count_text(out.report.boundary_edges, "boundary edge") + ", " +
                           count_text(out.report.nonmanifold_edges, "non-manifold edge") +
                           "); its inside is defined by the generalized "
                           "winding number");
  if (out.report.degenerate_triangles > 0)
    out.warnings.push_back(
        count_text(out.report.degenerate_triangles, "degenerate (zero-area) triangle"));
  return out;
}

}  // namespace medspheres
