#pragma once
/// \file
/// A folder of baked results keyed by what determines them (--cache DIR): sphere-set
/// files of meshes, and the output files of robots (batch_robot.h, its own key).
///
/// A mesh's key: the SHA-256 of the mesh file's SHA-256, its lower-case extension (it picks the
/// importer), every field of the BakeRequest that changes the spheres or the file (not
/// threads or progress, which do not) and the tool's version. Entries are written with
/// write_file_atomically (a temporary file renamed into place), so a reader sees a whole
/// entry or none, and several processes may share one folder: a race to store one key
/// stores the same bytes twice. An entry that does not parse as a sphere-set file (the
/// folder was tampered with) is a miss and is overwritten by the next store.

#include <optional>
#include <string>

#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/sphere_set.h"

namespace medspheres {

/// 64 hex digits naming the result of baking the mesh with SHA-256 \p mesh_sha256 and
/// file extension \p extension (with or without the dot, any case) with \p request.
std::string bake_cache_key(const std::string& mesh_sha256, const std::string& extension,
                           const BakeRequest& request);

/// Every field of \p request that changes the written file, one "name=value" line each
/// (not threads or progress): the part of a key that the request gives.
std::string bake_request_text(const BakeRequest& request);

/// Spheres as exact text ("x y z r;" each), for cache keys.
std::string spheres_text(const std::vector<Sphere>& spheres);

class BakeCache {
 public:
  /// Creates \p dir (and its parents) when missing.
  /// \throws InputError naming \p dir when it exists and is not a folder, or cannot be made.
  explicit BakeCache(std::string dir);

  /// The entry of \p key, parsed; none when missing or unreadable as a sphere set.
  std::optional<SphereSet> find(const std::string& key) const;

  /// Stores \p json_text (a sphere-set file) as the entry of \p key, atomically.
  /// \throws as write_file_atomically.
  void store(const std::string& key, const std::string& json_text) const;

  /// The bytes of the entry of \p key with file suffix \p suffix; none when missing.
  std::optional<std::string> find_bytes(const std::string& key, const std::string& suffix) const;

  /// Stores \p bytes as the entry of \p key with suffix \p suffix, atomically.
  /// \throws as write_file_atomically.
  void store_bytes(const std::string& key, const std::string& suffix,
                   const std::string& bytes) const;

  /// DIR/<first two hex digits>/<key><suffix>
  std::string path_of(const std::string& key, const std::string& suffix = ".spheres.json") const;

 private:
  std::string dir_;
};

}  // namespace medspheres
