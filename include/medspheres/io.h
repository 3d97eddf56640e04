#pragma once
/// \file
/// Reading and writing sphere-set files: JSON with "format": "medspheres.sphere_set",
/// "version": 1, "spheres": [[x, y, z, r], ...] and provenance keys ("source",
/// "generator", "stats"; docs/baking.md, "The sphere-set file"). A reader needs only "spheres";
/// "format" and "version", when present, must be the values below. Every other key is
/// kept in SphereSet::metadata_json and written back unchanged; unknown keys are not
/// errors.

#include <string>
#include <vector>

#include "medspheres/sphere_set.h"

namespace medspheres {

/// The value of the "format" key.
inline constexpr const char* kSphereSetFormat = "medspheres.sphere_set";
/// The highest "version" this library reads, and the one it writes.
inline constexpr int kSphereSetVersion = 1;

/// Reads and validates a sphere-set file.
/// \throws InputError naming \p path when the file is missing or unreadable, is not
///   JSON, lacks "spheres", has a wrong "format" or a newer "version", or holds a
///   sphere that is not four finite numbers with radius > 0 and a finite bounding box
///   (validate_sphere_set; subnormal radii are valid).
SphereSet load_sphere_set(const std::string& path);

/// The whole content of the file \p path, byte for byte.
/// \throws InputError naming \p path when it does not exist, is a directory or a device
///   (/dev/zero would never end), or cannot be opened or read.
std::string read_text_file(const std::string& path);

/// Parses sphere-set JSON text; \p source names it in error messages.
SphereSet parse_sphere_set(const std::string& json_text, const std::string& source);

/// The JSON text of \p set (format, version, spheres, then the metadata keys),
/// with numbers written so that they read back bit-identical.
std::string sphere_set_to_json(const SphereSet& set);

/// Writes \p set to \p path atomically (see write_file_atomically).
/// \throws InputError if the set is invalid, and as write_file_atomically.
void save_sphere_set(const SphereSet& set, const std::string& path);

/// Writes \p contents to \p path, atomically wherever a file is replaced:
/// - symbolic links are followed: the link stays, its final target (which need not exist)
///   is written;
/// - a regular or new file is written to a temporary file beside it (created O_EXCL, mode
///   0600), flushed and renamed over it: readers see the old file or the whole new one,
///   and on failure the target is untouched and the temporary removed. The new file gets
///   the permission bits of the one it replaces (0666 less the umask if new) before any
///   contents, and belongs to this process's user and group; owner, extended attributes
///   and ACLs of the old file are not kept;
/// - an existing file that is not regular (/dev/null, a FIFO) is written in place.
/// \throws InputError naming \p path when it is a directory, its directory is missing or
///   not a directory, or for a symbolic-link loop or a name too long (bad usage); Error
///   naming \p path when it cannot be looked up otherwise (no search permission, ...) or
///   a step of writing fails (permissions, read-only file system, full disk, ...).
void write_file_atomically(const std::string& path, const std::string& contents);

/// The checks write_file_atomically makes before writing, without writing: run before a
/// long computation whose result goes to \p path, so that a bad path fails at once.
/// Same errors (InputError for a directory or a missing directory; Error when the path
/// cannot be looked up, or the directory, or the existing non-regular file, is not
/// writable for this process).
void check_output_path(const std::string& path);

/// Writing \p output (a file, or a folder replaced as a whole) must not overwrite or remove
/// any of \p inputs (files read before it is written): none may be \p output itself or lie
/// under it, symbolic links resolved as far as the paths exist; empty names are skipped.
/// \throws InputError (field "output", value \p output) naming the first such input.
void check_output_spares_inputs(const std::string& output, const std::vector<std::string>& inputs);

}  // namespace medspheres
