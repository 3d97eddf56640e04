#pragma once
/// \file
/// Reading and writing sphere-set files.
///
/// The file is JSON:
/// \code{.json}
/// {
///   "format": "medspheres.sphere_set",
///   "version": 1,
///   "spheres": [[x, y, z, r], ...],
///   "source": {"mesh": "link1.stl", "sha256": "...", "triangles": 3000,
///              "bbox_min": [0, 0, 0], "bbox_max": [1, 1, 1]},
///   "generator": {"method": "medial", "version": "0.1.0", "params": {}},
///   "stats": {"nerr": 0.034, "nerr_kind": "exact", "bake_seconds": 0.41}
/// }
/// \endcode
/// A reader needs only "spheres"; "format" and "version", when present, must be the
/// values above. Every other key is provenance: it is kept in
/// SphereSet::metadata_json and written back unchanged. Unknown keys are not errors.

#include <string>

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
/// \throws InputError naming \p path when it does not exist, is a directory, or cannot be
///   opened or read.
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
/// - \p path is first followed through symbolic links; the link stays, and its final
///   target (which need not exist yet) is what gets written;
/// - a regular file, or a new one, is written to a temporary file in the target's
///   directory, flushed to disk and renamed over the target: readers see the old file
///   or the whole new one, and on failure the temporary file is removed and the target
///   is untouched. The temporary file is created by this call (O_EXCL: an existing file
///   or symbolic link at its name is never written through), with mode 0600, and given
///   its final permission bits before any contents are written: those of the file it
///   replaces, or 0666 less the umask for a new file. Only the permission bits are
///   kept: the new file belongs to this process's user and group, whoever owned the
///   file it replaces, and extended attributes and ACLs are not copied;
/// - an existing file that is not a regular file (a character device such as
///   /dev/null, a FIFO) is written in place, as a shell redirection would: renaming
///   over it would replace the device by a regular file.
/// \throws InputError naming \p path when it is a directory, when its directory does
///   not exist or is not a directory, or for a symbolic-link loop or a name too long
///   (bad usage); Error naming \p path when the path cannot be looked up for another
///   reason (no search permission on a directory on the way, ...) or a step of writing
///   fails (permissions, a read-only file system, a full disk, ...).
void write_file_atomically(const std::string& path, const std::string& contents);

/// The checks write_file_atomically makes before writing, without writing: run before a
/// long computation whose result goes to \p path, so that a bad path fails at once.
/// Same errors (InputError for a directory or a missing directory; Error when the path
/// cannot be looked up, or the directory, or the existing non-regular file, is not
/// writable for this process).
void check_output_path(const std::string& path);

}  // namespace medspheres
