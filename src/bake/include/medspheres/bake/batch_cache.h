#pragma once
/// \file
/// A folder of baked sphere-set files keyed by what determines them (--cache DIR).
///
/// Key: the SHA-256 of the mesh file's SHA-256, its lower-case extension (it picks the
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

  /// DIR/<first two hex digits>/<key>.spheres.json
  std::string path_of(const std::string& key) const;

 private:
  std::string dir_;
};

}  // namespace medspheres
