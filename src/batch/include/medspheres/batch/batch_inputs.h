#pragma once
/// \file
/// The inputs of a batch bake: paths given by the caller (files, folders scanned
/// recursively by extension, the lines of a list file) and the relative path each output
/// mirrors under the output folder.

#include <istream>
#include <string>
#include <vector>

namespace medspheres {

/// One mesh of a batch: the file, and its relative path (POSIX separators, never
/// absolute, never through ".."), which names its output and picks its shard.
struct BatchInput {
  std::string path;
  std::string relative;
};

/// How collect_inputs turns paths into inputs.
struct InputScan {
  /// File extensions a folder scan keeps, lower case without the dot (a file's extension
  /// is compared in lower case); empty: default_mesh_extensions().
  std::vector<std::string> extensions;
  /// The folder a file given by path is made relative to; empty: the working directory.
  std::string relative_to;
};

/// stl, obj, ply, off, dae, gltf, glb, fbx, 3ds.
const std::vector<std::string>& default_mesh_extensions();

/// The inputs of \p paths, sorted by relative path:
/// - a folder: every regular file below it (symbolic links to files followed, to folders
///   not) with a kept extension, relative to that folder;
/// - anything else is a file, whether or not it exists (a missing file fails its own row
///   of the batch): relative to InputScan::relative_to, or its file name alone when it
///   lies outside.
/// The same file reached twice is kept once.
/// \throws InputError naming both paths when two inputs would write the same output
///   (output_relative), e.g. a.stl and a.obj in one folder; and naming an extension
///   that is empty or has a dot or a separator.
std::vector<BatchInput> collect_inputs(const std::vector<std::string>& paths,
                                       const InputScan& scan = {});

/// One path per line of \p in (for --from-list); blank lines and lines starting with #
/// are skipped, a trailing carriage return and surrounding blanks are removed.
/// \throws InputError naming \p source when it cannot be read.
std::vector<std::string> read_path_list(std::istream& in, const std::string& source);

/// The output of an input, relative to the output folder: its relative path with the
/// extension replaced by ".spheres.json" (a/b/arm.stl -> a/b/arm.spheres.json), as a
/// single `bake` names it.
std::string output_relative(const std::string& relative);

}  // namespace medspheres
