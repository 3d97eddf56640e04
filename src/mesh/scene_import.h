#pragma once
// Private: the assimp import of a mesh file, flattened to plain arrays so that it can
// run in a child process and be sent back to load_mesh through a pipe (see mesh_io.h).

#include <cstdint>
#include <string>
#include <vector>

#include "medspheres/mesh/mesh_io.h"

namespace medspheres::detail {

/// One placement of one assimp mesh: its vertices under the node's accumulated
/// transform, and its triangles as indices into those vertices.
struct FlatMesh {
  std::vector<double> xyz;           ///< 3 per vertex
  std::vector<std::uint32_t> index;  ///< 3 per triangle, each < xyz.size() / 3
};

struct FlatScene {
  std::vector<FlatMesh> meshes;  ///< placed meshes in node order, then the orphans
  std::uint64_t orphans = 0;     ///< meshes no node places, kept with the identity
  /// Empty, or assimp's validation message when the scene failed validation and was read
  /// again without it (its meshes checked here instead).
  std::string validation_failure;
};

/// Reads \p path with assimp, checks that every coordinate is finite, and flattens the
/// scene. A scene that assimp's validation rejects (for instance two cameras that share a
/// name) is read again without it, as viewers do: the meshes are checked here (every
/// array present, every index in range) and the message is kept in validation_failure. This is what
/// the import program runs (import_helper_main.cpp). OFF files must have passed check_off_faces
/// first. \throws InputError naming \p path for a file that cannot be
/// read as a mesh;
///   std::bad_alloc when the import runs out of memory.
FlatScene import_flat(const std::string& path);

/// Checks the face list of the OFF file \p path against its header: every face line
/// present, 1 to 9 vertices per face, every index an integer in [0, vertices). assimp
/// itself clamps an out-of-range index silently. Files whose header it does not
/// recognise are left to assimp. Runs in the caller's process, before the import starts.
/// \throws InputError naming \p path, the face (counted from 0) and the bad index.
void check_off_faces(const std::string& path);

/// Checks the element counts of the PLY header of \p path (of \p file_size bytes)
/// against the bytes after the header, at the fewest bytes an element can take (2 per
/// ASCII value, the type's size in binary), so that a header announcing 10^12 vertices is
/// an error before anything is allocated. Other files are left to assimp.
/// \throws InputError naming \p path and the element.
void check_ply_counts(const std::string& path, std::uintmax_t file_size);

/// A file of \p file_size bytes that does not start with "solid" is binary STL, whose
/// size follows from the triangle count in its header; a size that does not is an error
/// before anything is allocated (assimp's own message does not say why).
/// \throws InputError naming \p path, the count and both sizes.
void check_stl_counts(const std::string& path, std::uintmax_t file_size);

// The byte format of the child's answer: one tag byte, then the payload.
//   'R' FlatScene; 'E' problem text of an InputError; 'M' out of memory; 'X' other
//   exception text.
std::string encode_scene(const FlatScene& scene);
std::string encode_message(char tag, const std::string& text);

/// A decoded answer. ok is false when \p bytes is truncated or malformed.
struct ImportAnswer {
  bool ok = false;
  char tag = 0;
  FlatScene scene;   ///< for 'R'
  std::string text;  ///< for the other tags
};
ImportAnswer decode_answer(const std::string& bytes);

/// Steps 2 to 4 of load_mesh (mesh_io.h) on an imported scene: welds bit-identical
/// points, checks the mesh (check_mesh_usable, naming \p path), orients it when
/// \p fix_orientation, and reports it with the user's warnings.
/// Precondition: every index of a FlatMesh is below its vertex count.
LoadedMesh mesh_from_scene(FlatScene scene, const std::string& path, bool fix_orientation);

}  // namespace medspheres::detail
